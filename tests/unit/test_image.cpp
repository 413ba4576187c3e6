#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <random>

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

// Issue 54: parts with different data windows are read in their union (before: refused), each
// part's channels 0 outside its own window.
TEST(Image, PartsWithDifferentDataWindowsAreReadInTheirUnion) {
  auto dir = isg::test::temp_dir("mpwin");
  auto path = (dir / "bad.exr").string();
  OIIO::ImageSpec a(4, 3, 1, OIIO::TypeDesc::FLOAT), b(5, 3, 1, OIIO::TypeDesc::FLOAT);
  b.full_width = 4;  // parts share the display window; only the data windows differ
  a.channelnames = {"R"};
  b.channelnames = {"Z"};
  a.attribute("name", "a");
  b.attribute("name", "b");
  std::vector<float> pa(12, 1.f), pb(15, 2.f);
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec specs[2] = {a, b};
  ASSERT_TRUE(out->open(path, 2, specs)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pa.data()));
  ASSERT_TRUE(out->open(path, b, OIIO::ImageOutput::AppendSubimage));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pb.data()));
  out->close();
  auto img = isg::io::read_exr(path);
  ASSERT_EQ(img.width, 5);
  ASSERT_EQ(img.height, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      EXPECT_EQ(img.find("R")->data[size_t(y * 5 + x)], x < 4 ? 1.0f : 0.0f) << x << "," << y;
      EXPECT_EQ(img.find("Z")->data[size_t(y * 5 + x)], 2.0f);
    }
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

namespace {

// Random bit patterns of T: every value a type can hold, NaNs, infinities and denormals included.
template <class T>
std::vector<T> random_bits(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<T> v(n);
  for (auto& x : v) {
    uint32_t b = rng();
    std::memcpy(&x, &b, sizeof x);
  }
  return v;
}

// One part of `nchannels` channels of type `t`, from a buffer of that type.
struct PartOf {
  OIIO::ImageSpec spec;
  std::vector<char> pixels;
};

}  // namespace

// Three parts (half, float, uint channels) with an offset data window, read through OpenEXR in
// the child and in-process: every value must equal OIIO's own read, bit for bit, in OIIO's
// channel order (R, G, B, A first, which is not the file's order).
TEST(Image, MultiPartHalfFloatUintReadBitExactAsOIIOReadsIt) {
  auto dir = isg::test::temp_dir("bitexact");
  const std::string path = (dir / "mp.exr").string();
  const int w = 37, h = 21;
  const size_t n = size_t(w) * h;
  std::vector<PartOf> parts;
  auto add = [&](OIIO::TypeDesc t, std::vector<std::string> names, const char* part_name,
                 std::vector<char> px) {
    OIIO::ImageSpec s(w, h, int(names.size()), t);
    s.x = 3;
    s.y = -2;
    s.full_x = 0;
    s.full_y = 0;
    s.full_width = 48;
    s.full_height = 24;
    s.channelnames = names;
    s.attribute("name", part_name);
    s.attribute("compression", "zip");
    parts.push_back({s, std::move(px)});
  };
  auto bytes = [](const auto& v) {
    return std::vector<char>(reinterpret_cast<const char*>(v.data()),
                             reinterpret_cast<const char*>(v.data() + v.size()));
  };
  add(OIIO::TypeDesc::HALF, {"R", "G", "B", "A", "Y"}, "beauty", bytes(random_bits<uint16_t>(n * 5, 1)));
  add(OIIO::TypeDesc::FLOAT, {"P.X", "P.Y", "P.Z"}, "position", bytes(random_bits<float>(n * 3, 2)));
  add(OIIO::TypeDesc::UINT, {"id"}, "ids", bytes(random_bits<uint32_t>(n, 3)));
  {
    auto out = OIIO::ImageOutput::create(path);
    std::vector<OIIO::ImageSpec> specs;
    for (const auto& p : parts) specs.push_back(p.spec);
    ASSERT_TRUE(out->open(path, int(specs.size()), specs.data())) << out->geterror();
    for (size_t i = 0; i < parts.size(); ++i) {
      if (i) {
        ASSERT_TRUE(out->open(path, parts[i].spec, OIIO::ImageOutput::AppendSubimage));
      }
      ASSERT_TRUE(out->write_image(parts[i].spec.format, parts[i].pixels.data())) << out->geterror();
    }
    ASSERT_TRUE(out->close());
  }
  // OIIO's read: each part as interleaved floats, channels in its order.
  std::vector<std::string> names;
  std::vector<std::vector<float>> expected;
  {
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    for (int s = 0; in->seek_subimage(s, 0); ++s) {
      const auto spec = in->spec();
      std::vector<float> buf(n * size_t(spec.nchannels));
      ASSERT_TRUE(in->read_image(s, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, buf.data()));
      for (int c = 0; c < spec.nchannels; ++c) {
        names.push_back(spec.channel_name(c));
        auto& e = expected.emplace_back(n);
        for (size_t i = 0; i < n; ++i) e[i] = buf[i * size_t(spec.nchannels) + size_t(c)];
      }
    }
  }
  ASSERT_EQ(names.size(), 9u);
  EXPECT_EQ(names[0], "R");  // the file's own order starts with A
  isg::io::ReadLimits child;
  child.check_seconds = 10;
  child.checker = ISG_EXRCHECK;
  for (const auto& limits : {child, isg::io::ReadLimits{}}) {
    auto img = isg::io::read_exr(path, limits);
    EXPECT_EQ(img.parts, 3);
    EXPECT_EQ(img.x0, 3);
    EXPECT_EQ(img.y0, -2);
    ASSERT_EQ(img.channel_names(), names);
    for (size_t c = 0; c < names.size(); ++c) {
      ASSERT_EQ(img.channels[c].data.size(), n);
      EXPECT_EQ(std::memcmp(img.channels[c].data.data(), expected[c].data(), n * 4), 0)
          << names[c] << (limits.check_seconds > 0 ? " (child)" : " (in-process)");
    }
    EXPECT_EQ(img.find("G")->storage, isg::io::Storage::half);
    EXPECT_EQ(img.find("P.Y")->storage, isg::io::Storage::f32);
    EXPECT_EQ(img.find("id")->storage, isg::io::Storage::other);
  }
}

// Every attribute type an input can bring comes out as OIIO's EXR writer would write it: the
// same file written through OIIO reads back with the same attributes.
TEST(Image, WriteKeepsAttributesAsOIIOWritesThem) {
  auto dir = isg::test::temp_dir("attrs");
  auto img = isg::test::contract_aovs(6, 5);
  auto& a = img.attributes;
  a.attribute("isg:note", "a string");
  a.attribute("isg:count", 7);
  a.attribute("isg:ratio", 0.25f);
  a.attribute("isg:precise", OIIO::TypeDesc::DOUBLE, std::vector<double>{1.0 / 3}.data());
  const float m44[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  a.attribute("worldtocamera", OIIO::TypeMatrix, m44);
  a.attribute("isg:m33", OIIO::TypeMatrix33, m44);
  const double d44[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0.25, 0.125, 1};
  a.attribute("isg:m44d", OIIO::TypeDesc(OIIO::TypeDesc::DOUBLE, OIIO::TypeDesc::MATRIX44), d44);
  a.attribute("isg:v2f", OIIO::TypeVector2, m44);
  a.attribute("isg:v3f", OIIO::TypeVector, m44);
  const int ints[4] = {-1, 2, 30, 40};
  a.attribute("isg:v2i", OIIO::TypeDesc(OIIO::TypeDesc::INT, OIIO::TypeDesc::VEC2), ints);
  a.attribute("isg:v3i", OIIO::TypeDesc(OIIO::TypeDesc::INT, OIIO::TypeDesc::VEC3), ints);
  a.attribute("isg:box", OIIO::TypeDesc(OIIO::TypeDesc::INT, OIIO::TypeDesc::VEC2, 2), ints);
  a.attribute("isg:v3d", OIIO::TypeDesc(OIIO::TypeDesc::DOUBLE, OIIO::TypeDesc::VEC3), d44);
  a.attribute("isg:floats", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 5), m44);
  const char* strs[3] = {"x", "y", "z"};
  a.attribute("isg:strings", OIIO::TypeDesc(OIIO::TypeDesc::STRING, 3), strs);
  const int fps[2] = {24000, 1001};
  a.attribute("FramesPerSecond", OIIO::TypeRational, fps);
  const unsigned tc[2] = {0x01020304, 0};
  a.attribute("smpte:TimeCode", OIIO::TypeTimeCode, tc);
  a.attribute("DateTime", "2024:01:02 03:04:05");
  a.attribute("ImageDescription", "described");
  a.attribute("Copyright", "us");
  a.attribute("oiio:ConstantColor", "0.5");
  a.attribute("oiio:internal", "dropped");
  a.attribute("tiff:Compression", 5);
  a.attribute("Exif:ExposureTime", 0.01f);
  a.attribute("XResolution", 300.0f);
  a.attribute("YResolution", 150.0f);
  a.attribute("ResolutionUnit", "cm");

  isg::io::write_exr(dir / "ours.exr", img, {"zip", false});
  // The same image through OIIO's writer, as write_exr did before it wrote with OpenEXR.
  {
    OIIO::ImageSpec spec(img.width, img.height, int(img.channels.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = img.channel_names();
    spec.channelformats.clear();
    spec.alpha_channel = spec.z_channel = -1;
    spec.extra_attribs = a;
    spec.attribute("compression", "zip");
    std::vector<float> px(img.pixels() * img.channels.size());
    for (size_t c = 0; c < img.channels.size(); ++c)
      for (size_t i = 0; i < img.pixels(); ++i) px[i * img.channels.size() + c] = img.channels[c].data[i];
    auto out = OIIO::ImageOutput::create("openexr");
    ASSERT_TRUE(out->open((dir / "oiio.exr").string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    ASSERT_TRUE(out->close());
  }
  auto ours = isg::io::read_exr_header(dir / "ours.exr").attributes;
  auto theirs = isg::io::read_exr_header(dir / "oiio.exr").attributes;
  auto describe = [](const OIIO::ParamValueList& l) {
    std::map<std::string, std::string> m;
    for (const auto& p : l) m[p.name().string()] = p.type().c_str() + std::string(" ") + p.get_string(0);
    return m;
  };
  EXPECT_EQ(describe(ours), describe(theirs));
  // And the attributes are there at all (not both dropped).
  auto m = describe(ours);
  for (const char* k : {"isg:note", "isg:count", "isg:precise", "worldToCamera", "isg:m33", "isg:m44d",
                        "isg:v3i", "isg:box", "isg:v3d", "isg:floats", "isg:strings", "FramesPerSecond",
                        "smpte:TimeCode", "DateTime", "ImageDescription", "Copyright", "oiio:ConstantColor",
                        "Exif:ExposureTime", "XResolution"}) {
    EXPECT_TRUE(m.count(k)) << k;
  }
  EXPECT_FALSE(m.count("oiio:internal"));
  EXPECT_FALSE(m.count("tiff:Compression"));
}
