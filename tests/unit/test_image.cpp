#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <fstream>

#include "io/image.h"
#include "support/images.h"

namespace fs = std::filesystem;
using isg::io::IoError;

namespace {
void expect_io_error(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
    FAIL() << "no error; expected one mentioning " << needle;
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(Image, RoundTripKeepsChannelsStorageAndAttributes) {
  auto dir = isg::test::temp_dir("img");
  auto img = isg::test::contract_aovs(17, 9);
  img.find("R")->storage = isg::io::Storage::half;
  img.attributes.attribute("studio:shot", "sq010_sh020");
  isg::io::write_exr(dir / "a.exr", img, {"piz", false});
  auto back = isg::io::read_exr(dir / "a.exr");
  EXPECT_EQ(back.width, 17);
  EXPECT_EQ(back.height, 9);
  ASSERT_EQ(back.channels.size(), img.channels.size());
  for (const auto& c : img.channels) {
    const auto* b = back.find(c.name);
    ASSERT_TRUE(b) << c.name;
    EXPECT_EQ(b->storage, c.storage) << c.name;
    for (size_t i = 0; i < c.data.size(); ++i) {
      float tol = c.storage == isg::io::Storage::half ? 1e-3f * std::max(1.0f, std::abs(c.data[i])) : 0.0f;
      ASSERT_NEAR(b->data[i], c.data[i], tol) << c.name << " " << i;
    }
  }
  EXPECT_EQ(back.attributes.get_string("studio:shot"), "sq010_sh020");
  EXPECT_EQ(back.attributes.get_string("compression"), "piz");
  // Nothing but the output in the folder: the temporary file was renamed.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(Image, MultiPartReadsEveryPart) {
  auto dir = isg::test::temp_dir("multipart");
  auto path = (dir / "mp.exr").string();
  OIIO::ImageSpec a(4, 3, 2, OIIO::TypeDesc::HALF), b(4, 3, 1, OIIO::TypeDesc::FLOAT);
  a.channelnames = {"R", "G"};
  b.channelnames = {"Z"};
  a.attribute("name", "rgb");
  b.attribute("name", "depth");
  std::vector<float> pa(24, 0.5f), pb(12, 7.0f);
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec specs[2] = {a, b};
  ASSERT_TRUE(out->open(path, 2, specs));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pa.data()));
  ASSERT_TRUE(out->open(path, b, OIIO::ImageOutput::AppendSubimage));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pb.data()));
  out->close();
  auto img = isg::io::read_exr(path);
  EXPECT_EQ(img.parts, 2);
  ASSERT_TRUE(img.find("Z"));
  EXPECT_EQ(img.find("Z")->data[5], 7.0f);
  EXPECT_EQ(img.find("G")->storage, isg::io::Storage::half);
}

TEST(Image, PartsWithDifferentDataWindowsAreRejected) {
  auto dir = isg::test::temp_dir("mpwin");
  auto path = (dir / "bad.exr").string();
  OIIO::ImageSpec a(4, 3, 1, OIIO::TypeDesc::FLOAT), b(5, 3, 1, OIIO::TypeDesc::FLOAT);
  b.full_width = 4;  // parts share the display window; only the data windows differ
  a.channelnames = {"R"};
  b.channelnames = {"Z"};
  a.attribute("name", "a");
  b.attribute("name", "b");
  std::vector<float> pa(12, 0.f), pb(15, 0.f);
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec specs[2] = {a, b};
  ASSERT_TRUE(out->open(path, 2, specs)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pa.data()));
  ASSERT_TRUE(out->open(path, b, OIIO::ImageOutput::AppendSubimage));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pb.data()));
  out->close();
  expect_io_error([&] { isg::io::read_exr(path); }, "different data window");
}

TEST(Image, BadFilesGiveOneLineErrorsNamingTheFile) {
  auto dir = isg::test::temp_dir("badfiles");
  expect_io_error([&] { isg::io::read_exr(dir / "missing.exr"); }, "missing.exr: no such file");
  std::ofstream(dir / "text.exr") << "hello, not an image";
  expect_io_error([&] { isg::io::read_exr(dir / "text.exr"); }, "not an OpenEXR file");
  // Truncations of a real file: in the header and in the pixel data.
  auto img = isg::test::contract_aovs(64, 64);
  isg::io::write_exr(dir / "good.exr", img, {"none", false});
  auto size = fs::file_size(dir / "good.exr");
  for (double frac : {0.01, 0.1, 0.5, 0.95}) {
    auto cut = dir / ("cut" + std::to_string(int(frac * 100)) + ".exr");
    fs::copy_file(dir / "good.exr", cut);
    fs::resize_file(cut, uintmax_t(double(size) * frac));
    try {
      isg::io::read_exr(cut);
      ADD_FAILURE() << "truncated file read without error at " << frac;
    } catch (const IoError& e) {
      std::string m = e.what();
      EXPECT_NE(m.find(cut.filename().string()), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
}

TEST(Image, LimitsAreCheckedBeforeDecoding) {
  auto dir = isg::test::temp_dir("limits");
  isg::io::write_exr(dir / "a.exr", isg::test::contract_aovs(32, 32), {});
  isg::io::ReadLimits l;
  l.max_pixels = 100;
  expect_io_error([&] { isg::io::read_exr(dir / "a.exr", l); }, "exceeds the limit");
  l = {};
  l.max_channels = 3;
  expect_io_error([&] { isg::io::read_exr(dir / "a.exr", l); }, "more than 3 channels");
}

TEST(Image, SanitizeCountsAndZeroesNonFinite) {
  auto img = isg::test::make_image(4, 1, {"R", "G"}, [](const std::string& n, int x, int) {
    if (n == "R" && x == 1) return NAN;
    if (n == "R" && x == 2) return INFINITY;
    return 0.5f;
  });
  auto r = isg::io::sanitize(img);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].channel, "R");
  EXPECT_EQ(r[0].count, 2u);
  EXPECT_EQ(img.find("R")->data[1], 0.0f);
  EXPECT_EQ(img.find("R")->data[3], 0.5f);
}

TEST(Image, WritesAreAtomicAndRespectNoClobber) {
  auto dir = isg::test::temp_dir("atomic");
  auto img = isg::test::contract_aovs(8, 8);
  isg::io::write_exr(dir / "o.exr", img, {});
  auto before = fs::last_write_time(dir / "o.exr");
  expect_io_error([&] { isg::io::write_exr(dir / "o.exr", img, {"zip", true}); }, "--no-clobber");
  EXPECT_EQ(fs::last_write_time(dir / "o.exr"), before);
  expect_io_error([&] { isg::io::write_exr(dir / "nodir" / "o.exr", img, {}); }, "does not exist");
  expect_io_error([&] { isg::io::write_exr(dir / "x.exr", img, {"lzma", false}); }, "--compression");
  EXPECT_FALSE(fs::exists(dir / "x.exr"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}
