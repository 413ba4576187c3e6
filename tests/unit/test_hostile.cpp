// Damaged EXRs the tests write themselves: each must give a one-line IoError naming the file,
// never a crash, a hang or an allocation past the limits.
#include <gtest/gtest.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfTiledOutputFile.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
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
}

// A header whose chunks cannot hold the pixels it declares (issue 54: a 355-byte file claiming
// 100663297x1 pixels decoded for 45 s into 4.9 GB): with every other limit lifted, the data
// window widened past what each compression's largest ratio allows is refused by the structure
// walk, naming both figures; the same file at its own width reads.
TEST(Hostile, HeaderClaimingMorePixelsThanItsBytesHoldIsRefused) {
  isg::io::ReadLimits open;
  open.max_pixels = int64_t(1) << 50;
  open.max_bytes = int64_t(1) << 60;
  const int64_t ratios[] = {1, 128, 1032, 1032, 1024, 1400, 11, 11, 1032 * 128, 1032 * 128};
  const char* names[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};
  for (int c = 0; c < 10; ++c) {
    Fixture f(std::string("ratio-") + names[c], names[c]);
    ASSERT_EQ(f.layout.parts[0].compression, c) << names[c];
    EXPECT_NO_THROW(isg::io::check_exr_structure(f.good, open)) << names[c];
    // The most compressible file there is (every value 0, half and float planes, wide lines)
    // stays within the bounds: they refuse no file an encoder writes.
    isg::io::Image flat;
    flat.width = flat.full_w = 4096;
    flat.height = flat.full_h = 300;
    flat.set("R", std::vector<float>(flat.pixels(), 0.0f), isg::io::Storage::half);
    flat.set("Z", std::vector<float>(flat.pixels(), 0.0f), isg::io::Storage::f32);
    isg::io::write_exr(f.dir / "flat.exr", flat, {names[c], false});
    EXPECT_NO_THROW(isg::io::read_exr(f.dir / "flat.exr", checked())) << names[c];
    // The widest chunk's data, times the ratio, over its lines and channels: a width past it.
    int64_t largest = 0;
    for (uint64_t o : f.layout.chunk_offsets[0]) {
      int32_t size;
      std::memcpy(&size, f.bytes.data() + o + 4, 4);
      largest = std::max<int64_t>(largest, size);
    }
    const int64_t width = largest * ratios[c] / 2 + 64;  // > the bound with one line, 2-byte pixels
    auto b = f.bytes;
    poke<int32_t>(b, f.attr("dataWindow") + 8, int32_t(width - 1));  // xmax; the lines stay
    auto p = f.dir / "claims.exr";
    spit(p, b);
    try {
      isg::io::check_exr_structure(p, open);
      ADD_FAILURE() << names[c] << ": a " << width << "-wide claim passed";
    } catch (const IoError& e) {
      std::string m = e.what();
      EXPECT_NE(m.find(c == 0 ? "uncompressed pixels take" : "can hold (at most"), std::string::npos) << m;
      EXPECT_NE(m.find("claims.exr"), std::string::npos) << m;
    }
  }
}

// A chunk table with an entry listed twice (so a chunk is missing): the lines it leaves would
// decode as nothing; refused, naming the chunk.
TEST(Hostile, ChunkListedTwiceIsRefused) {
  Fixture f("twice");
  auto b = f.bytes;
  poke<uint64_t>(b, f.layout.offsets_begin + 8, f.layout.chunk_offsets[0][0]);
  spit(f.dir / "twice.exr", b);
  expect_rejected(f.dir / "twice.exr", "a chunk is missing or listed twice");
}

// Parts with different data windows (a beauty whole, AOVs cropped to their bounding box): read
// in the union of the windows, each part's channels 0 outside its own, equal to the same
// channels written in one part.
TEST(Hostile, PartsWithDifferentDataWindowsAreReadInTheirUnion) {
  auto dir = isg::test::temp_dir("union");
  const int W = 12, H = 20, cx = 3, cy = 5, cw = 6, ch = 9;  // part 1's crop
  std::vector<float> r(W * H), z(size_t(cw) * ch), z_full(W * H, 0.0f);
  for (int i = 0; i < W * H; ++i) r[size_t(i)] = 0.25f + 0.001f * float(i);
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x) {
      z[size_t(y * cw + x)] = 3.0f + 0.5f * float(x) + float(y);
      z_full[size_t((y + cy) * W + x + cx)] = z[size_t(y * cw + x)];
    }
  OIIO::ImageSpec a(W, H, 1, OIIO::TypeDesc::FLOAT), b(cw, ch, 1, OIIO::TypeDesc::FLOAT);
  a.channelnames = {"R"};
  b.channelnames = {"Z"};
  b.x = cx;
  b.y = cy;
  b.full_width = W;
  b.full_height = H;
  a.attribute("name", "beauty");
  b.attribute("name", "aovs");
  const auto path = (dir / "cropped.exr").string();
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec specs[2] = {a, b};
  ASSERT_TRUE(out->open(path, 2, specs));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, r.data()));
  ASSERT_TRUE(out->open(path, b, OIIO::ImageOutput::AppendSubimage));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, z.data()));
  out->close();
  isg::io::Image one;
  one.width = one.full_w = W;
  one.height = one.full_h = H;
  one.set("R", r);
  one.set("Z", z_full);
  isg::io::write_exr(dir / "one.exr", one, {"zip", false});
  for (const auto& limits : {isg::io::ReadLimits{}, checked()}) {
    auto img = isg::io::read_exr(path, limits);
    auto ref = isg::io::read_exr(dir / "one.exr", limits);
    ASSERT_EQ(img.width, W);
    ASSERT_EQ(img.height, H);
    EXPECT_EQ(img.x0, 0);
    EXPECT_EQ(img.y0, 0);
    ASSERT_TRUE(img.find("R") && img.find("Z"));
    EXPECT_EQ(img.find("R")->data, ref.find("R")->data);
    EXPECT_EQ(img.find("Z")->data, ref.find("Z")->data);
    EXPECT_EQ(img.find("Z")->data[size_t((cy + 1) * W + cx + 2)], 3.0f + 1.0f + 1.0f);
    EXPECT_EQ(img.find("Z")->data[0], 0.0f);  // outside the crop
  }
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

// The table-entry checks accept tiled files OpenEXR wrote: one level, mipmapped and ripmapped
// (levels in order, each level's tiles row by row, edge tiles clipped), rounding down and up.
TEST(Hostile, TiledFilesOpenExrWroteAreAccepted) {
  auto dir = isg::test::temp_dir("tiled");
  const int W = 45, H = 29;
  int n = 0;
  for (auto mode : {Imf::ONE_LEVEL, Imf::MIPMAP_LEVELS, Imf::RIPMAP_LEVELS})
    for (auto rounding : {Imf::ROUND_DOWN, Imf::ROUND_UP}) {
      const auto path = (dir / ("t" + std::to_string(n++) + ".exr")).string();
      Imf::Header header(W, H);
      header.channels().insert("R", Imf::Channel(Imf::HALF));
      header.compression() = Imf::ZIP_COMPRESSION;
      header.setTileDescription(Imf::TileDescription(16, 8, mode, rounding));
      {
        Imf::TiledOutputFile out(path.c_str(), header);
        for (int ly = 0; ly < out.numYLevels(); ++ly)
          for (int lx = 0; lx < out.numXLevels(); ++lx) {
            if (mode == Imf::MIPMAP_LEVELS && lx != ly) continue;
            if (mode == Imf::ONE_LEVEL && (lx || ly)) continue;
            const int w = out.levelWidth(lx), h = out.levelHeight(ly);
            std::vector<half> px(size_t(w) * h);
            for (size_t i = 0; i < px.size(); ++i) px[i] = half(0.01f * float(i % 97));
            Imf::FrameBuffer fb;
            fb.insert("R", Imf::Slice(Imf::HALF, reinterpret_cast<char*>(px.data()), sizeof(half), sizeof(half) * size_t(w)));
            out.setFrameBuffer(fb);
            out.writeTiles(0, out.numXTiles(lx) - 1, 0, out.numYTiles(ly) - 1, lx, ly);
          }
      }
      auto layout = isg::io::check_exr_structure(path, {});
      ASSERT_EQ(layout.parts.size(), 1u);
      EXPECT_TRUE(layout.parts[0].tiled);
      EXPECT_EQ(layout.parts[0].level_mode, int(mode)) << path;
      auto img = isg::io::read_exr(path, checked());
      ASSERT_EQ(img.width, W);
      EXPECT_NEAR(img.find("R")->data[100], 0.01f * 3.0f, 1e-3) << path;  // 100 % 97
    }
}
