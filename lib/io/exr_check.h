// Validation of an EXR before any library decodes it: our own bounds-checked walk of the header,
// the offset tables and every chunk's header; then the pixels are decoded by OpenEXR in a child
// process with a time and memory limit, so a file that crashes or hangs the library becomes a
// one-line error instead.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "io/exr_decode.h"

namespace isg::io {

struct ReadLimits;

struct ExrAttribute {
  std::string type;
  uint64_t offset = 0;  // of the value, in the file
  uint32_t size = 0;
};

struct ExrChannelInfo {
  std::string name;
  int pixel_type = 0;  // 0 uint, 1 half, 2 float
  int x_sampling = 1, y_sampling = 1;
};

struct ExrPartInfo {
  std::map<std::string, ExrAttribute> attributes;
  std::vector<ExrChannelInfo> channels;
  int data_window[4] = {0, 0, 0, 0};  // xmin, ymin, xmax, ymax
  int compression = 0;
  bool tiled = false, deep = false;
  uint32_t tile_x = 0, tile_y = 0;
  int level_mode = 0;
  uint64_t chunks = 0;  // entries in the offset table
  int64_t width() const { return int64_t(data_window[2]) - data_window[0] + 1; }
  int64_t height() const { return int64_t(data_window[3]) - data_window[1] + 1; }
};

struct ExrLayout {
  uint64_t file_size = 0;
  bool multipart = false, long_names = false;
  std::vector<ExrPartInfo> parts;
  int window[4] = {0, 0, 0, 0};  // the union of the parts' data windows (xmin, ymin, xmax, ymax)
  std::vector<uint64_t> header_ends;  // file offset just past each part's header
  uint64_t offsets_begin = 0, offsets_end = 0;
  std::vector<std::vector<uint64_t>> chunk_offsets;  // per part
};

// Walks the file's structure (header attributes, offset tables, chunk headers) with every read
// bounds-checked against the file size and the limits. Throws IoError naming the file and the
// first thing wrong. Reads only headers: cost is independent of the pixel data size.
ExrLayout check_exr_structure(const std::filesystem::path& path, const ReadLimits& limits);

// Decodes the planes `req` names with OpenEXR in a child process (the `helper` executable,
// isg-exrcheck) limited to `seconds` and `memory_bytes`, through shared memory; once the child
// has succeeded, calls `take(i, values)` for each plane in order, with its width * height
// 4-byte values (see decode_exr_planes), valid during the call. Throws IoError naming the file
// if the child reports damage, crashes, hangs or runs out of memory; nothing is taken then. A
// separate executable rather than a bare fork: the library's thread pools do not survive fork.
void decode_exr_in_child(const std::filesystem::path& path, const std::string& helper,
                         const ExrDecodeRequest& req, double seconds, uint64_t memory_bytes,
                         const std::function<void(size_t, const void*)>& take);

}  // namespace isg::io
