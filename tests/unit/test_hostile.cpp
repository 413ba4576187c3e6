// Damaged EXRs the tests write themselves: each must give a one-line IoError naming the file,
// never a crash, a hang or an allocation past the limits.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cstring>
#include <fstream>
#include <set>

#include "io/exr_check.h"
#include "io/image.h"
#include "support/images.h"

namespace fs = std::filesystem;
using isg::io::IoError;

namespace {

isg::io::ReadLimits checked() {
  isg::io::ReadLimits l;
  l.check_seconds = 10;
  l.checker = ISG_EXRCHECK;
  return l;
}

std::vector<char> slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

void spit(const fs::path& p, const std::vector<char>& b) {
  std::ofstream(p, std::ios::binary).write(b.data(), std::streamsize(b.size()));
}

template <class T>
void poke(std::vector<char>& b, uint64_t at, T v) {
  std::memcpy(b.data() + at, &v, sizeof v);
}

// Reading `p` must fail with one line that names it, and the message must contain `needle`.
void expect_rejected(const fs::path& p, const std::string& needle = "") {
  try {
    isg::io::read_exr(p, checked());
    ADD_FAILURE() << p << " was read without error";
  } catch (const IoError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find(p.filename().string()), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    if (!needle.empty()) {
      EXPECT_NE(m.find(needle), std::string::npos) << m;
    }
  }
}

struct Fixture {
  fs::path dir, good;
  std::vector<char> bytes;
  isg::io::ExrLayout layout;
  explicit Fixture(const std::string& name, const std::string& compression = "zip") {
    dir = isg::test::temp_dir(name);
    good = dir / "good.exr";
    isg::io::write_exr(good, isg::test::contract_aovs(40, 37), {compression, false});
    bytes = slurp(good);
    layout = isg::io::check_exr_structure(good, {});
  }
  uint64_t attr(const std::string& name) const { return layout.parts[0].attributes.at(name).offset; }
};

}  // namespace

TEST(Hostile, GoodFilePassesEveryCheck) {
  Fixture f("good");
  EXPECT_NO_THROW(isg::io::read_exr(f.good, checked()));
  EXPECT_EQ(f.layout.parts.size(), 1u);
  EXPECT_EQ(f.layout.parts[0].chunks, 3u);  // 37 lines, 16 per zip chunk
}

TEST(Hostile, TruncationAtEveryHeaderBoundaryAndInsideThePixels) {
  Fixture f("truncate");
  std::set<uint64_t> cuts = {0, 1, 3, 4, 7, 8};
  for (const auto& [name, a] : f.layout.parts[0].attributes) {
    uint64_t name_start = a.offset - 4 - a.type.size() - 1 - name.size() - 1;
    for (uint64_t c : {name_start, name_start + 1, a.offset - 4, a.offset, a.offset + a.size / 2,
                       a.offset + a.size}) cuts.insert(c);
  }
  cuts.insert(f.layout.offsets_begin);
  cuts.insert(f.layout.offsets_begin + 5);
  cuts.insert(f.layout.offsets_end);
  for (uint64_t o : f.layout.chunk_offsets[0]) {
    for (uint64_t c : {o, o + 2, o + 6, o + 8, o + 40}) cuts.insert(c);
  }
  cuts.insert(f.bytes.size() - 1);
  int n = 0;
  for (uint64_t c : cuts) {
    if (c >= f.bytes.size()) continue;
    auto p = f.dir / ("cut" + std::to_string(c) + ".exr");
    spit(p, std::vector<char>(f.bytes.begin(), f.bytes.begin() + long(c)));
    expect_rejected(p);
    ++n;
  }
  EXPECT_GT(n, 60);
}

TEST(Hostile, HugeNegativeOrInvertedDataWindow) {
  Fixture f("window");
  auto b = f.bytes;
  poke<int32_t>(b, f.attr("dataWindow") + 8, 1 << 29);  // xmax
  poke<int32_t>(b, f.attr("dataWindow") + 12, 1 << 29);  // ymax
  spit(f.dir / "huge.exr", b);
  expect_rejected(f.dir / "huge.exr", "exceeds the limit");
  b = f.bytes;
  poke<int32_t>(b, f.attr("dataWindow") + 8, -5);  // xmax < xmin
  spit(f.dir / "inverted.exr", b);
  expect_rejected(f.dir / "inverted.exr", "empty or inverted");
  b = f.bytes;
  poke<int32_t>(b, f.attr("dataWindow"), INT32_MIN);
  spit(f.dir / "negative.exr", b);
  expect_rejected(f.dir / "negative.exr", "out of range");
}

TEST(Hostile, BogusChannelsAndAttributeSizes) {
  Fixture f("channels");
  auto b = f.bytes;
  // The first channel's pixel type: after its name and the terminating 0.
  uint64_t first = f.attr("channels");
  uint64_t type_at = first + std::strlen(b.data() + first) + 1;
  poke<int32_t>(b, type_at, 7);
  spit(f.dir / "pixeltype.exr", b);
  expect_rejected(f.dir / "pixeltype.exr", "unknown pixel type");
  b = f.bytes;
  poke<int32_t>(b, type_at + 8, 2);  // x sampling
  spit(f.dir / "sampling.exr", b);
  expect_rejected(f.dir / "sampling.exr", "subsampled");
  b = f.bytes;
  poke<int32_t>(b, f.attr("channels") - 4, 1 << 30);  // the chlist's size
  spit(f.dir / "size.exr", b);
  expect_rejected(f.dir / "size.exr", "bad size");
  b = f.bytes;
  poke<int32_t>(b, f.attr("channels") - 4, 9);  // a list cut short inside its attribute
  spit(f.dir / "short.exr", b);
  expect_rejected(f.dir / "short.exr");
}

TEST(Hostile, WrongCompressionByte) {
  Fixture f("compression");
  auto b = f.bytes;
  poke<uint8_t>(b, f.attr("compression"), 42);
  spit(f.dir / "unknown.exr", b);
  expect_rejected(f.dir / "unknown.exr", "unknown compression");
  // ZIP -> PXR24: the same 16 lines per chunk, so the structure holds and only decoding can
  // tell; OpenEXR's checker in its child process does.
  b = f.bytes;
  poke<uint8_t>(b, f.attr("compression"), 5);
  spit(f.dir / "pxr24.exr", b);
  expect_rejected(f.dir / "pxr24.exr", "damaged EXR");
}

TEST(Hostile, CorruptPixelDataAndOffsets) {
  Fixture f("pixels");
  auto b = f.bytes;
  uint64_t o = f.layout.chunk_offsets[0][1];
  for (uint64_t i = o + 8; i < o + 200 && i < b.size(); ++i) b[i] = char(i * 131);
  spit(f.dir / "garbage.exr", b);
  expect_rejected(f.dir / "garbage.exr");
  b = f.bytes;
  poke<uint64_t>(b, f.layout.offsets_begin + 8, uint64_t(1) << 40);
  spit(f.dir / "offset.exr", b);
  expect_rejected(f.dir / "offset.exr", "past the end");
  b = f.bytes;
  poke<int32_t>(b, o + 4, 1 << 30);  // a chunk's data size
  spit(f.dir / "chunksize.exr", b);
  expect_rejected(f.dir / "chunksize.exr", "truncated pixel data");
}

TEST(Hostile, PartsThatDisagree) {
  auto dir = isg::test::temp_dir("parts");
  auto path = (dir / "mp.exr").string();
  OIIO::ImageSpec a(8, 20, 1, OIIO::TypeDesc::HALF), b(8, 20, 1, OIIO::TypeDesc::FLOAT);
  a.channelnames = {"R"};
  b.channelnames = {"Z"};
  a.attribute("name", "a");
  b.attribute("name", "b");
  a.attribute("compression", "zip");
  b.attribute("compression", "zip");
  std::vector<float> px(160, 0.5f);
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec specs[2] = {a, b};
  ASSERT_TRUE(out->open(path, 2, specs));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  ASSERT_TRUE(out->open(path, b, OIIO::ImageOutput::AppendSubimage));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  out->close();
  auto layout = isg::io::check_exr_structure(path, {});
  ASSERT_EQ(layout.parts.size(), 2u);
  auto bytes = slurp(path);
  auto cc = layout.parts[1].attributes.at("chunkCount").offset;
  poke<int32_t>(bytes, cc, 7);
  spit(dir / "count.exr", bytes);
  expect_rejected(dir / "count.exr", "chunkCount");
  bytes = slurp(path);
  poke<int32_t>(bytes, layout.parts[1].attributes.at("dataWindow").offset + 12, 18);
  spit(dir / "window.exr", bytes);
  expect_rejected(dir / "window.exr", "different data window");
}

// The decoding child's ways of failing: each is one line naming the file, and nothing is copied.
TEST(Hostile, DecoderCrashHangOrExhaustionBecomesAnError) {
  auto dir = isg::test::temp_dir("hang");
  auto img = isg::test::contract_aovs(8, 8);
  isg::io::write_exr(dir / "a.exr", img, {});
  isg::io::ExrDecodeRequest req{0, 0, 8, 8, {}};
  for (const auto& c : img.channels) req.planes.push_back({0, c.name});
  std::vector<float> sink(req.pixels());
  int copied = 0;
  auto plane = [&](size_t, const void* values) {
    ++copied;
    std::memcpy(sink.data(), values, sink.size() * 4);
  };
  auto expect_error = [&](const std::string& helper, double seconds, uint64_t memory,
                          const std::string& needle) {
    try {
      isg::io::decode_exr_in_child(dir / "a.exr", helper, req, seconds, memory, plane);
      ADD_FAILURE() << helper << ": no error";
    } catch (const IoError& e) {
      std::string m = e.what();
      EXPECT_NE(m.find("a.exr"), std::string::npos) << m;
      EXPECT_NE(m.find(needle), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    EXPECT_EQ(copied, 0) << helper;
  };
  // A stand-in decoder that hangs: the parent kills it after the time limit.
  auto hang = dir / "hang.sh";
  std::ofstream(hang) << "#!/bin/sh\nsleep 30\n";
  fs::permissions(hang, fs::perms::owner_all);
  expect_error(hang.string(), 0.3, 1 << 30, "did not finish");
  // One killed by a signal.
  auto crash = dir / "crash.sh";
  std::ofstream(crash) << "#!/bin/sh\nkill -SEGV $$\n";
  fs::permissions(crash, fs::perms::owner_all);
  expect_error(crash.string(), 5, 1 << 30, "crashed (signal 11)");
  // The real decoder under a memory limit smaller than what the planes need.
  req.width = req.height = 4096;
  expect_error(ISG_EXRCHECK, 10, 256 << 20, "out of memory");
  // And the real decoder asked for a channel the file does not have.
  req.width = req.height = 8;
  req.planes.push_back({0, "nonesuch"});
  expect_error(ISG_EXRCHECK, 10, 1 << 30, "no channel nonesuch");
  // A good request through the real decoder gets every plane.
  req.planes.pop_back();
  isg::io::decode_exr_in_child(dir / "a.exr", ISG_EXRCHECK, req, 10, 1 << 30, plane);
  EXPECT_EQ(copied, int(req.planes.size()));
}
