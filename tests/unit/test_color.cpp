#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "io/color.h"
#include "support/images.h"

namespace {
// IEC 61966-2-1, the closed form the built-in config's display must reproduce.
double srgb_encode(double l) { return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055; }
}  // namespace

TEST(Color, BuiltinDisplayIsTheSrgbCurve) {
  ::unsetenv("OCIO");
  const std::vector<float> values = {0.0f, 0.001f, 0.0031308f, 0.05f, 0.18f, 0.5f, 1.0f, 4.0f};
  auto img = isg::test::make_image(int(values.size()), 1, {"R", "G", "B"},
                                   [&](auto&, int x, int) { return values[x]; });
  auto pic = isg::io::display_picture(img, {"R", "G", "B"}, {});
  ASSERT_EQ(pic.size(), 3 * values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    double want = std::round(255.0 * std::min(1.0, srgb_encode(values[i])));
    EXPECT_NEAR(pic[3 * i], want, 1.0) << values[i];
  }
}

TEST(Color, InputColorspaceBringsTheBeautyToSceneLinear) {
  ::unsetenv("OCIO");
  auto img = isg::test::make_image(3, 1, {"R", "G", "B"}, [](auto&, int x, int) {
    return float(srgb_encode(0.1 * (x + 1)));
  });
  isg::io::to_scene_linear(img, {"R", "G", "B"}, "sRGB - Display");
  for (int x = 0; x < 3; ++x) EXPECT_NEAR(img.find("G")->data[x], 0.1 * (x + 1), 1e-4);
  EXPECT_THROW(isg::io::to_scene_linear(img, {"R", "G", "B"}, "no such space"), isg::io::IoError);
}
