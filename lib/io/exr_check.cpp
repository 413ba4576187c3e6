#include "io/exr_check.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fstream>
#include <thread>

#include "io/image.h"

namespace isg::io {

namespace fs = std::filesystem;

namespace {

constexpr uint32_t kMagic = 20000630;  // 0x762f3101
constexpr uint32_t kTiledFlag = 0x200, kLongNamesFlag = 0x400, kNonImageFlag = 0x800,
                   kMultipartFlag = 0x1000;
constexpr int kMaxCompression = 9;  // NONE .. DWAB

// Bounds-checked reads from the file; every failure names the file and the offset.
class Reader {
 public:
  Reader(const fs::path& p, uint64_t size) : path_(p), size_(size), in_(p, std::ios::binary) {
    if (!in_) fail("cannot be opened");
  }
  [[noreturn]] void fail(const std::string& why) const { throw IoError(path_.string() + ": " + why); }
  uint64_t pos() const { return pos_; }
  uint64_t size() const { return size_; }
  void seek(uint64_t p) {
    if (p > size_) fail("truncated (offset " + std::to_string(p) + " is past the end, " + std::to_string(size_) + " bytes)");
    pos_ = p;
    in_.clear();
    in_.seekg(std::streamoff(p));
  }
  void bytes(void* dst, uint64_t n, const char* what) {
    if (n > size_ || pos_ > size_ - n) fail(std::string("truncated while reading ") + what);
    in_.read(static_cast<char*>(dst), std::streamsize(n));
    if (uint64_t(in_.gcount()) != n) fail(std::string("truncated while reading ") + what);
    pos_ += n;
  }
  template <class T>
  T value(const char* what) {
    T v{};
    bytes(&v, sizeof(T), what);  // EXR is little-endian, as is every platform we build for
    return v;
  }
  std::string name(size_t max_len, const char* what) {
    std::string s;
    for (;;) {
      char c = value<char>(what);
      if (c == 0) return s;
      s.push_back(c);
      if (s.size() > max_len) fail(std::string(what) + " longer than " + std::to_string(max_len) + " characters");
    }
  }

 private:
  fs::path path_;
  uint64_t size_;
  std::ifstream in_;
  uint64_t pos_ = 0;
};

int lines_per_chunk(int compression) {
  switch (compression) {
    case 0: case 1: case 2: return 1;     // none, rle, zips
    case 3: case 5: return 16;            // zip, pxr24
    case 4: case 6: case 7: case 8: return 32;  // piz, b44, b44a, dwaa
    case 9: return 256;                   // dwab
  }
  return 1;
}

int64_t ceil_div(int64_t a, int64_t b) { return (a + b - 1) / b; }

// The most pixel bytes one byte of a chunk's data can decode to, for each compression (issue 54):
// a header whose chunks claim more than their bytes can hold was not written by an encoder, and
// is refused before anything is allocated for it. Deflate tops out at 1032:1 (258 bytes from 2
// bits); rle at 64:1 (a 2-byte run of 128); piz's Huffman at about 410:1 (a run of 256 shorts in
// 10 bits); pxr24 stores 24 of a float's 32 bits before deflate; b44a packs a flat 4x4 block of
// halves (32 bytes) in 3; dwa's constant 8x8 blocks leave one code per block before deflate.
// Each bound is rounded up: none of them refuses a file an encoder wrote.
const char* const kCompressionNames[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};
int64_t max_ratio(int compression) {
  switch (compression) {
    case 0: return 1;                    // none: the chunk holds exactly its pixels
    case 1: return 128;                  // rle
    case 2: case 3: return 1032;         // zips, zip
    case 4: return 1024;                 // piz
    case 5: return 1400;                 // pxr24
    case 6: case 7: return 11;           // b44, b44a
    default: return int64_t(1032) * 128; // dwaa, dwab
  }
}

int64_t level_count(int64_t size, int rounding) {
  int64_t n = 1;
  while (size > 1) {
    size = rounding ? (size + 1) / 2 : size / 2;
    ++n;
  }
  return n;
}

int64_t level_size(int64_t size, int64_t level, int rounding) {
  for (int64_t i = 0; i < level; ++i) size = rounding ? (size + 1) / 2 : size / 2;
  return std::max<int64_t>(size, 1);
}

// Chunks a part's offset table must hold, from its header.
uint64_t expected_chunks(const ExrPartInfo& p, int rounding) {
  const int64_t w = p.width(), h = p.height();
  if (!p.tiled) return uint64_t(ceil_div(h, lines_per_chunk(p.compression)));
  const int64_t tx = p.tile_x, ty = p.tile_y;
  int64_t total = 0;
  if (p.level_mode == 0) return uint64_t(ceil_div(w, tx) * ceil_div(h, ty));
  const int64_t lx = level_count(w, rounding), ly = level_count(h, rounding);
  if (p.level_mode == 1) {  // mipmap: levels of both axes together
    for (int64_t l = 0; l < std::max(lx, ly); ++l)
      total += ceil_div(level_size(w, l, rounding), tx) * ceil_div(level_size(h, l, rounding), ty);
  } else {  // ripmap
    for (int64_t j = 0; j < ly; ++j)
      for (int64_t i = 0; i < lx; ++i)
        total += ceil_div(level_size(w, i, rounding), tx) * ceil_div(level_size(h, j, rounding), ty);
  }
  return uint64_t(total);
}

}  // namespace

ExrLayout check_exr_structure(const fs::path& path, const ReadLimits& limits) {
  std::error_code ec;
  ExrLayout L;
  L.file_size = fs::file_size(path, ec);
  if (ec) throw IoError(path.string() + ": cannot be read (" + ec.message() + ")");
  Reader r(path, L.file_size);
  if (r.value<uint32_t>("the magic number") != kMagic) r.fail("not an OpenEXR file (bad magic number)");
  const uint32_t version = r.value<uint32_t>("the version field");
  if ((version & 0xff) != 2) r.fail("unsupported OpenEXR version " + std::to_string(version & 0xff));
  if (version & ~uint32_t(0xff | kTiledFlag | kLongNamesFlag | kNonImageFlag | kMultipartFlag)) {
    r.fail("unknown flags in the version field");
  }
  L.multipart = version & kMultipartFlag;
  L.long_names = version & kLongNamesFlag;
  const size_t max_name = L.long_names ? 255 : 31;

  int64_t total_channels = 0;
  std::vector<int> roundings;
  for (;;) {
    if (L.multipart) {
      // An empty header (a single 0 byte) ends the list of parts.
      char c = r.value<char>("the header list");
      if (c == 0) break;
      r.seek(r.pos() - 1);
    }
    const std::string part = "part " + std::to_string(L.parts.size());
    if (L.parts.size() >= 1024) r.fail("more than 1024 parts");
    ExrPartInfo P;
    int rounding = 0;
    for (;;) {
      std::string name = r.name(max_name, "an attribute name");
      if (name.empty()) break;
      ExrAttribute a;
      a.type = r.name(max_name, "an attribute type");
      int32_t size = r.value<int32_t>("an attribute size");
      if (size < 0 || uint64_t(size) > r.size() - r.pos()) {
        r.fail(part + ": attribute " + name + " has a bad size (" + std::to_string(size) + ")");
      }
      a.offset = r.pos();
      a.size = uint32_t(size);
      if (P.attributes.count(name)) r.fail(part + ": attribute " + name + " appears twice");
      const uint64_t end = a.offset + a.size;
      auto need = [&](const char* type, uint32_t min_size) {
        if (a.type != type) r.fail(part + ": attribute " + name + " has type " + a.type + ", expected " + type);
        if (a.size < min_size) r.fail(part + ": attribute " + name + " is too short");
      };
      if (name == "channels") {
        need("chlist", 1);
        for (;;) {
          std::string ch = r.name(max_name, "a channel name");
          if (ch.empty()) break;
          ExrChannelInfo ci;
          ci.name = ch;
          ci.pixel_type = r.value<int32_t>("a channel's pixel type");
          r.value<uint32_t>("a channel's linear flag");
          ci.x_sampling = r.value<int32_t>("a channel's x sampling");
          ci.y_sampling = r.value<int32_t>("a channel's y sampling");
          if (ci.pixel_type < 0 || ci.pixel_type > 2) {
            r.fail(part + ": channel " + ch + " has an unknown pixel type " + std::to_string(ci.pixel_type));
          }
          if (ci.x_sampling != 1 || ci.y_sampling != 1) {
            r.fail(part + ": channel " + ch + " is subsampled (" + std::to_string(ci.x_sampling) + "x" +
                   std::to_string(ci.y_sampling) + "); only full-resolution channels are supported");
          }
          P.channels.push_back(ci);
          if (++total_channels > limits.max_channels) {
            r.fail("more than " + std::to_string(limits.max_channels) + " channels (limits.max_channels)");
          }
          if (r.pos() > end) r.fail(part + ": the channel list overruns its attribute");
        }
        if (r.pos() != end) r.fail(part + ": the channel list does not fill its attribute");
      } else if (name == "compression") {
        need("compression", 1);
        P.compression = r.value<uint8_t>("the compression");
        if (P.compression > kMaxCompression) {
          r.fail(part + ": unknown compression " + std::to_string(P.compression));
        }
      } else if (name == "dataWindow" || name == "displayWindow") {
        need("box2i", 16);
        int32_t b[4];
        for (int& v : b) v = r.value<int32_t>("a window");
        for (int v : b) {
          if (v < -(1 << 30) || v > (1 << 30)) r.fail(part + ": " + name + " coordinate " + std::to_string(v) + " is out of range");
        }
        if (b[2] < b[0] || b[3] < b[1]) r.fail(part + ": " + name + " is empty or inverted");
        if (name == "dataWindow") std::memcpy(P.data_window, b, sizeof b);
      } else if (name == "tiles") {
        need("tiledesc", 9);
        P.tile_x = r.value<uint32_t>("the tile width");
        P.tile_y = r.value<uint32_t>("the tile height");
        uint8_t mode = r.value<uint8_t>("the tile mode");
        P.level_mode = mode & 0xf;
        rounding = mode >> 4;
        if (P.tile_x == 0 || P.tile_y == 0 || P.tile_x > (1u << 16) || P.tile_y > (1u << 16)) {
          r.fail(part + ": bad tile size " + std::to_string(P.tile_x) + "x" + std::to_string(P.tile_y));
        }
        if (P.level_mode > 2 || rounding > 1) r.fail(part + ": bad tile level mode");
      } else if (name == "type") {
        need("string", 1);
        std::string t(a.size, '\0');
        r.bytes(t.data(), a.size, "the part type");
        if (t == "tiledimage") P.tiled = true;
        else if (t == "deepscanline" || t == "deeptile") P.deep = true;
        else if (t != "scanlineimage") r.fail(part + ": unknown part type " + t);
      } else if (name == "chunkCount") {
        need("int", 4);
        int32_t n = r.value<int32_t>("the chunk count");
        if (n <= 0) r.fail(part + ": bad chunkCount " + std::to_string(n));
        P.chunks = uint64_t(n);
      }
      r.seek(end);
      P.attributes[name] = a;
    }
    for (const char* req : {"channels", "compression", "dataWindow", "displayWindow", "lineOrder"}) {
      if (!P.attributes.count(req)) r.fail(part + ": required attribute " + req + " is missing");
    }
    if (!L.multipart && (version & kTiledFlag)) P.tiled = true;
    if (L.multipart && !P.attributes.count("type")) r.fail(part + ": multi-part file without a part type");
    if (version & kNonImageFlag) P.deep = true;
    if (P.deep) r.fail(part + ": deep data is not supported");
    if (P.tiled && !P.attributes.count("tiles")) r.fail(part + ": tiled part without a tile description");
    if (P.channels.empty()) r.fail(part + ": has no channels");
    if (P.width() * P.height() > limits.max_pixels) {
      r.fail(part + ": data window " + std::to_string(P.width()) + "x" + std::to_string(P.height()) +
             " exceeds the limit of " + std::to_string(limits.max_pixels) + " pixels (limits.max_megapixels)");
    }
    // Parts may cover different data windows (a beauty whole, AOVs cropped to their bounding
    // box): the image is their union, each part placed in it (read_exr).
    if (L.parts.empty()) {
      std::memcpy(L.window, P.data_window, sizeof L.window);
    } else {
      L.window[0] = std::min(L.window[0], P.data_window[0]);
      L.window[1] = std::min(L.window[1], P.data_window[1]);
      L.window[2] = std::max(L.window[2], P.data_window[2]);
      L.window[3] = std::max(L.window[3], P.data_window[3]);
    }
    const int64_t union_pixels = (int64_t(L.window[2]) - L.window[0] + 1) * (int64_t(L.window[3]) - L.window[1] + 1);
    if (union_pixels > limits.max_pixels) {
      r.fail("the parts' data windows span " + std::to_string(union_pixels) + " pixels, over the limit of " +
             std::to_string(limits.max_pixels) + " (limits.max_megapixels)");
    }
    const uint64_t expected = expected_chunks(P, rounding);
    if (L.multipart && P.chunks != expected) {
      r.fail(part + ": chunkCount " + std::to_string(P.chunks) + " disagrees with its header (" +
             std::to_string(expected) + ")");
    }
    P.chunks = expected;
    roundings.push_back(rounding);
    L.parts.push_back(P);
    L.header_ends.push_back(r.pos());
    if (!L.multipart) break;
  }
  if (L.parts.empty()) r.fail("has no parts");
  // Every channel is decoded into a float plane of the union window.
  const int64_t bytes = (int64_t(L.window[2]) - L.window[0] + 1) * (int64_t(L.window[3]) - L.window[1] + 1) *
                        total_channels * 4;
  if (bytes > limits.max_bytes) {
    r.fail("decoding would need " + std::to_string(bytes >> 20) + " MiB, more than limits.max_memory_mb");
  }

  // Offset tables: every chunk must start inside the file, after the tables.
  L.offsets_begin = r.pos();
  uint64_t table_entries = 0;
  for (const auto& p : L.parts) table_entries += p.chunks;
  if (table_entries > (r.size() - r.pos()) / 8) {
    r.fail("truncated: the offset tables need " + std::to_string(table_entries * 8) + " bytes");
  }
  L.offsets_end = r.pos() + table_entries * 8;
  for (size_t pi = 0; pi < L.parts.size(); ++pi) {
    std::vector<uint64_t> offs(L.parts[pi].chunks);
    for (auto& o : offs) {
      o = r.value<uint64_t>("the offset table");
      if (o < L.offsets_end || o >= r.size()) {
        r.fail("part " + std::to_string(pi) + ": chunk offset " + std::to_string(o) +
               (o >= r.size() ? " is past the end of the file (truncated?)" : " points into the header"));
      }
    }
    L.chunk_offsets.push_back(std::move(offs));
  }
  // Chunk headers: part number, the chunk the table's entry stands for (a chunk missing or listed
  // twice leaves lines that nothing decodes), and a data size that fits in the file and can hold
  // the pixels the header gives the chunk (max_ratio).
  for (size_t pi = 0; pi < L.parts.size(); ++pi) {
    const auto& P = L.parts[pi];
    const std::string part = "part " + std::to_string(pi);
    int64_t pixel_bytes = 0;  // decoded bytes of one pixel of every channel
    for (const auto& c : P.channels) pixel_bytes += c.pixel_type == 1 ? 2 : 4;
    const int lpc = lines_per_chunk(P.compression);
    const int rounding = roundings[pi];
    for (size_t k = 0; k < L.chunk_offsets[pi].size(); ++k) {
      const uint64_t o = L.chunk_offsets[pi][k];
      const std::string chunk = part + ": chunk " + std::to_string(k) + " (at byte " + std::to_string(o) + ")";
      r.seek(o);
      if (L.multipart && r.value<int32_t>("a chunk's part number") != int32_t(pi)) {
        r.fail(chunk + " belongs to another part");
      }
      int64_t cols = 0, lines = 0;
      if (P.tiled) {
        int32_t t[4];
        for (int& v : t) v = r.value<int32_t>("a tile's coordinates");
        if (t[0] < 0 || t[1] < 0 || t[2] < 0 || t[3] < 0) r.fail(chunk + ": negative tile coordinates");
        // The table lists levels in order (mipmap: level l of both axes; ripmap: x levels within
        // y levels), each level's tiles row by row.
        const int64_t lx_n = P.level_mode == 0 ? 1 : level_count(P.width(), rounding);
        const int64_t ly_n = P.level_mode == 0 ? 1 : level_count(P.height(), rounding);
        if ((P.level_mode == 1 && (t[2] != t[3] || t[2] >= std::max(lx_n, ly_n))) ||
            (P.level_mode != 1 && (t[2] >= lx_n || t[3] >= ly_n))) {
          r.fail(chunk + ": tile level " + std::to_string(t[2]) + "," + std::to_string(t[3]) + " does not exist");
        }
        const int64_t lw = level_size(P.width(), t[2], rounding), lh = level_size(P.height(), t[3], rounding);
        const int64_t nx = ceil_div(lw, P.tile_x), ny = ceil_div(lh, P.tile_y);
        if (t[0] >= nx || t[1] >= ny) r.fail(chunk + ": tile " + std::to_string(t[0]) + "," + std::to_string(t[1]) + " lies outside its level");
        uint64_t index = 0;  // of the level's first tile
        if (P.level_mode == 1) {
          for (int64_t l = 0; l < t[2]; ++l)
            index += uint64_t(ceil_div(level_size(P.width(), l, rounding), P.tile_x) *
                              ceil_div(level_size(P.height(), l, rounding), P.tile_y));
        } else if (P.level_mode == 2) {
          for (int64_t j = 0; j <= t[3]; ++j)
            for (int64_t i = 0; i < (j < t[3] ? lx_n : t[2]); ++i)
              index += uint64_t(ceil_div(level_size(P.width(), i, rounding), P.tile_x) *
                                ceil_div(level_size(P.height(), j, rounding), P.tile_y));
        }
        index += uint64_t(t[1] * nx + t[0]);
        if (index != k) r.fail(chunk + " holds tile " + std::to_string(index) + ": a tile is missing or listed twice");
        cols = std::min<int64_t>(P.tile_x, lw - int64_t(t[0]) * P.tile_x);
        lines = std::min<int64_t>(P.tile_y, lh - int64_t(t[1]) * P.tile_y);
      } else {
        const int32_t y = r.value<int32_t>("a chunk's first line");
        const int64_t want = int64_t(P.data_window[1]) + int64_t(k) * lpc;
        if (y != want) {
          r.fail(chunk + " starts on line " + std::to_string(y) + ", where line " + std::to_string(want) +
                 " belongs: a chunk is missing or listed twice");
        }
        cols = P.width();
        lines = std::min<int64_t>(lpc, int64_t(P.data_window[3]) - y + 1);
      }
      const int32_t size = r.value<int32_t>("a chunk's data size");
      if (size < 0 || uint64_t(size) > r.size() - r.pos()) {
        r.fail(chunk + " runs past the end of the file (truncated pixel data)");
      }
      const int64_t decoded = cols * lines * pixel_bytes;
      if (P.compression == 0 && int64_t(size) != decoded) {
        r.fail(chunk + " holds " + std::to_string(size) + " bytes where its " + std::to_string(cols) + "x" +
               std::to_string(lines) + " uncompressed pixels take " + std::to_string(decoded));
      }
      if (decoded > int64_t(size) * max_ratio(P.compression)) {
        r.fail(chunk + ": the header gives it " + std::to_string(cols) + "x" + std::to_string(lines) + " pixels, " +
               std::to_string(decoded) + " bytes, more than its " + std::to_string(size) + " bytes of " +
               kCompressionNames[P.compression] + " data can hold (at most " +
               std::to_string(max_ratio(P.compression)) + ":1): the file claims pixels it does not have");
      }
    }
  }
  return L;
}

namespace {

// An open file descriptor, closed on scope exit.
struct Fd {
  int fd = -1;
  explicit Fd(int f) : fd(f) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

// The child's last words (stderr went to `fd`), first line only, for the error message.
std::string child_message(int fd) {
  char buf[256];
  ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  std::string s(buf, size_t(std::max<ssize_t>(n, 0)));
  if (auto nl = s.find('\n'); nl != std::string::npos) s.resize(nl);
  return s;
}

}  // namespace

void decode_exr_in_child(const fs::path& path, const std::string& helper, const ExrDecodeRequest& req,
                         double seconds, uint64_t memory_bytes,
                         const std::function<void(size_t, const void*)>& take) {
  const std::string f = path.string();
  if (::access(helper.c_str(), X_OK) != 0) {
    throw IoError(f + ": cannot decode the file: " + helper +
                  " is missing (set limits.check_seconds = 0 to decode in-process)");
  }
  const uint64_t plane_bytes = uint64_t(req.pixels()) * 4;
  const uint64_t bytes = plane_bytes * req.planes.size();
  // The planes travel back through anonymous shared memory the child maps as fd 3; its stderr
  // goes to a second one so a damaged file's reason can be told.
  Fd shm(::memfd_create("isg-planes", MFD_CLOEXEC));
  Fd msg(::memfd_create("isg-exrcheck-stderr", MFD_CLOEXEC));
  if (shm.fd < 0 || msg.fd < 0 || ::ftruncate(shm.fd, off_t(bytes)) != 0) {
    throw IoError(f + ": cannot create " + std::to_string(bytes >> 20) + " MiB of shared memory for decoding");
  }
  // Everything the child needs is built before fork: after it, only async-signal-safe calls.
  std::vector<std::string> args = {"isg-exrcheck", f, std::to_string(req.x0), std::to_string(req.y0),
                                   std::to_string(req.width), std::to_string(req.height)};
  for (const auto& p : req.planes) {
    args.push_back(std::to_string(p.part));
    args.push_back(p.name);
  }
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = ::fork();
  if (pid < 0) throw IoError(f + ": cannot start the decoder (fork failed)");
  if (pid == 0) {
    struct rlimit rl {};
    rl.rlim_cur = rl.rlim_max = memory_bytes;
    ::setrlimit(RLIMIT_AS, &rl);
    // Copies above the standard descriptors first, so the dup2s below cannot clobber each other.
    int s = ::fcntl(shm.fd, F_DUPFD_CLOEXEC, 10), m = ::fcntl(msg.fd, F_DUPFD_CLOEXEC, 10);
    int devnull = ::open("/dev/null", O_WRONLY);
    if (s < 0 || m < 0 || devnull < 0 || ::dup2(devnull, 1) < 0 || ::dup2(m, 2) < 0 ||
        ::dup2(s, 3) < 0) {
      ::_exit(4);
    }
    ::execv(helper.c_str(), argv.data());
    ::_exit(4);
  }
  auto start = std::chrono::steady_clock::now();
  int status = 0;
  for (;;) {
    pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (w < 0) throw IoError(f + ": the decoder vanished");
    double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (el > seconds) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      throw IoError(f + ": damaged EXR: OpenEXR's decoder did not finish in " +
                    std::to_string(int(seconds)) + " s (limits.check_seconds)");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(el < 0.05 ? 1 : 10));
  }
  if (WIFSIGNALED(status)) {
    throw IoError(f + ": damaged EXR: OpenEXR's decoder crashed (signal " +
                  std::to_string(WTERMSIG(status)) + ")");
  }
  int code = WIFEXITED(status) ? WEXITSTATUS(status) : 5;
  if (code == 1) {
    std::string why = child_message(msg.fd);
    throw IoError(f + ": damaged EXR: OpenEXR: " + (why.empty() ? "corrupt data" : why));
  }
  if (code == 3) throw IoError(f + ": OpenEXR's decoder ran out of memory (limits.max_memory_mb)");
  if (code == 4) throw IoError(f + ": cannot decode the file: " + helper + " did not start");
  if (code != 0) {
    std::string why = child_message(msg.fd);
    throw IoError(f + ": damaged EXR: OpenEXR's decoder failed (exit " + std::to_string(code) +
                  (why.empty() ? "" : ": " + why) + ")");
  }
  // Mapped, not read: each plane is copied once, straight into the memory that keeps it.
  void* mem = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED | MAP_POPULATE, shm.fd, 0);
  if (mem == MAP_FAILED) throw IoError(f + ": the decoded planes could not be mapped");
  struct Unmap {
    void* p;
    uint64_t n;
    ~Unmap() { ::munmap(p, n); }
  } unmap{mem, bytes};
  for (size_t i = 0; i < req.planes.size(); ++i) {
    const uint64_t at = i * plane_bytes;
    take(i, static_cast<const char*>(mem) + at);
    // Each plane's pages are freed once taken, so reading peaks at one plane over the image.
    ::fallocate(shm.fd, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, off_t(at), off_t(plane_bytes));
  }
}

}  // namespace isg::io
