// EXR AOV images as values: named float planes plus the header attributes to carry through.
// Knows nothing of Vulkan.
#pragma once

#include <OpenImageIO/paramlist.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace isg::io {

// Every I/O failure: a one-line message that names the file (and channel/key) it is about.
struct IoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class Storage { half, f32, other };

struct Channel {
  std::string name;
  Storage storage = Storage::f32;  // as stored in the file; kept on output
  std::vector<float> data;         // width * height, row-major, top row first
};

struct Image {
  std::filesystem::path path;
  int width = 0, height = 0;
  int x0 = 0, y0 = 0;                          // data window origin
  int full_x0 = 0, full_y0 = 0, full_w = 0, full_h = 0;  // display window
  int parts = 1;
  std::vector<Channel> channels;
  OIIO::ParamValueList attributes;  // header attributes of every part (first part wins)

  size_t pixels() const { return size_t(width) * size_t(height); }
  const Channel* find(const std::string& name) const;
  Channel* find(const std::string& name);
  std::vector<std::string> channel_names() const;
  // Adds or replaces a channel.
  Channel& set(const std::string& name, std::vector<float> data, Storage s = Storage::f32);
};

// Limits checked before any pixel is decoded.
struct ReadLimits {
  int64_t max_pixels = int64_t(1) << 28;  // 268M pixels (16K x 16K)
  int max_channels = 1024;
  int64_t max_bytes = int64_t(16) << 30;  // decoded float bytes
  // Pixels are decoded by OpenEXR in a child process (the isg-exrcheck executable at
  // `checker`) given this long, so a file that crashes or hangs the library is a one-line error;
  // 0 seconds or an empty path decodes in this process instead, for files that are trusted.
  double check_seconds = 0.0;
  std::string checker;
};

// Reads all parts into float planes of the union of their data windows (a part's channels are 0
// outside its own).
Image read_exr(const std::filesystem::path& path, const ReadLimits& limits = {});

// Header only: channel names of all parts, size, attributes. Pixels are not decoded.
Image read_exr_header(const std::filesystem::path& path, const ReadLimits& limits = {});

struct NonFinite {
  std::string channel;
  size_t count = 0;
};
// Replaces NaN/Inf with 0 and reports how many each channel had.
std::vector<NonFinite> sanitize(Image& img);

struct WriteOptions {
  std::string compression = "zip";
  bool no_clobber = false;
};

// Checks that `path` can be written (folder exists and is writable, and --no-clobber holds)
// before any work is done.
void check_writable(const std::filesystem::path& path, const WriteOptions& opt);

// Writes one EXR part with all channels, atomically: a temporary file in the same folder,
// renamed over the target only once it is complete.
void write_exr(const std::filesystem::path& path, const Image& img, const WriteOptions& opt);

// Writes an 8-bit RGB picture (PNG or JPEG by extension), atomically like write_exr.
void write_picture(const std::filesystem::path& path, int width, int height,
                   const std::vector<unsigned char>& rgb, bool no_clobber = false);

}  // namespace isg::io
