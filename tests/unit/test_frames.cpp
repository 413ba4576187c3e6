#include <gtest/gtest.h>

#include "frames/frames.h"

using isg::frames::expand_pattern;
using isg::frames::parse_frames;

TEST(Frames, Patterns) {
  EXPECT_EQ(expand_pattern("shot.####.exr", 7), "shot.0007.exr");
  EXPECT_EQ(expand_pattern("/a/b/s_##.exr", 1001), "/a/b/s_1001.exr");
  EXPECT_EQ(expand_pattern("out.%04d.exr", 12), "out.0012.exr");
  EXPECT_EQ(expand_pattern("out.%d.exr", 12), "out.12.exr");
  EXPECT_TRUE(isg::frames::is_sequence_pattern("x.####.exr"));
  EXPECT_TRUE(isg::frames::is_sequence_pattern("x.%05d.exr"));
  EXPECT_FALSE(isg::frames::is_sequence_pattern("x.0001.exr"));
}

TEST(Frames, Ranges) {
  EXPECT_EQ(parse_frames("1001-1004"), (std::vector<int>{1001, 1002, 1003, 1004}));
  EXPECT_EQ(parse_frames("1-9x4"), (std::vector<int>{1, 5, 9}));
  EXPECT_EQ(parse_frames("3,7-8, 10"), (std::vector<int>{3, 7, 8, 10}));
  EXPECT_EQ(parse_frames("5"), (std::vector<int>{5}));
  EXPECT_THROW(parse_frames("9-3"), std::invalid_argument);
  EXPECT_THROW(parse_frames("1-5x0"), std::invalid_argument);
  EXPECT_THROW(parse_frames("a-b"), std::invalid_argument);
  EXPECT_THROW(parse_frames(""), std::invalid_argument);
}
