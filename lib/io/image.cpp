#include "io/image.h"

#include "io/exr_check.h"
#include "io/image_detail.h"

#include <OpenEXR/ImfBoxAttribute.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFloatVectorAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfKeyCodeAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfRationalAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfStringVectorAttribute.h>
#include <OpenEXR/ImfTimeCodeAttribute.h>
#include <OpenEXR/ImfVecAttribute.h>
#include <OpenImageIO/imageio.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fstream>
#include <random>

namespace isg::io {

namespace fs = std::filesystem;
using detail::first_line;
using detail::reserve_fresh;

const Channel* Image::find(const std::string& name) const {
  for (const auto& c : channels) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

Channel* Image::find(const std::string& name) {
  for (auto& c : channels) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::vector<std::string> Image::channel_names() const {
  std::vector<std::string> n;
  for (const auto& c : channels) n.push_back(c.name);
  return n;
}

Channel& Image::set(const std::string& name, std::vector<float> data, Storage s) {
  if (data.size() != pixels()) throw IoError("channel " + name + ": wrong pixel count");
  if (Channel* c = find(name)) {
    c->data = std::move(data);
    c->storage = s;
    return *c;
  }
  channels.push_back(Channel{name, s, std::move(data)});
  return channels.back();
}

namespace {

Storage storage_of(const OIIO::TypeDesc& t) {
  if (t == OIIO::TypeDesc::HALF) return Storage::half;
  if (t == OIIO::TypeDesc::FLOAT) return Storage::f32;
  return Storage::other;
}

// Opens the file and walks its parts' headers, checking them against `limits`.
std::unique_ptr<OIIO::ImageInput> open_checked(const fs::path& path, const ReadLimits& limits,
                                               Image& img, std::vector<OIIO::ImageSpec>& specs) {
  const std::string f = path.string();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IoError(f + ": no such file");
  if (!fs::is_regular_file(path, ec)) throw IoError(f + ": not a regular file");
  // Our own bounds-checked walk of the structure first: no library code sees a file that fails it.
  check_exr_structure(path, limits);
  auto in = OIIO::ImageInput::open(f);
  if (!in) throw IoError(f + ": cannot be read: " + first_line(OIIO::geterror()));
  if (std::string(in->format_name()) != "openexr") throw IoError(f + ": not an OpenEXR file");
  img.path = path;
  int part = 0;
  int64_t total_channels = 0;
  do {
    const OIIO::ImageSpec& s = in->spec();
    if (s.depth != 1 || s.deep) throw IoError(f + ": deep or volumetric EXR is not supported");
    if (s.width <= 0 || s.height <= 0) throw IoError(f + ": empty data window");
    if (int64_t(s.width) * s.height > limits.max_pixels) {
      throw IoError(f + ": data window " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                    " exceeds the limit of " + std::to_string(limits.max_pixels) + " pixels");
    }
    if (part == 0) {
      img.width = s.width;
      img.height = s.height;
      img.x0 = s.x;
      img.y0 = s.y;
      img.full_x0 = s.full_x;
      img.full_y0 = s.full_y;
      img.full_w = s.full_width;
      img.full_h = s.full_height;
    } else {
      // Parts with other data windows (AOVs cropped to their bounding box): the image is the
      // union, and each part's channels are 0 outside its own window (read_exr).
      const int x1 = std::max(img.x0 + img.width, s.x + s.width), y1 = std::max(img.y0 + img.height, s.y + s.height);
      img.x0 = std::min(img.x0, s.x);
      img.y0 = std::min(img.y0, s.y);
      img.width = x1 - img.x0;
      img.height = y1 - img.y0;
    }
    total_channels += s.nchannels;
    if (total_channels > limits.max_channels) {
      throw IoError(f + ": more than " + std::to_string(limits.max_channels) + " channels");
    }
    specs.push_back(s);
    ++part;
  } while (in->seek_subimage(part, 0));
  img.parts = part;
  if (int64_t(img.width) * img.height * total_channels * 4 > limits.max_bytes) {
    throw IoError(f + ": decoding would need more than " +
                  std::to_string(limits.max_bytes >> 20) + " MiB");
  }
  for (const auto& s : specs) {
    for (const auto& p : s.extra_attribs) {
      if (!img.attributes.contains(p.name())) img.attributes.push_back(p);
    }
  }
  return in;
}

}  // namespace

Image read_exr_header(const fs::path& path, const ReadLimits& limits) {
  Image img;
  std::vector<OIIO::ImageSpec> specs;
  auto in = open_checked(path, limits, img, specs);
  for (const auto& s : specs) {
    for (int c = 0; c < s.nchannels; ++c) {
      Channel ch;
      ch.name = s.channel_name(c);
      ch.storage = storage_of(s.channelformat(c));
      img.channels.push_back(std::move(ch));
    }
  }
  return img;
}

Image read_exr(const fs::path& path, const ReadLimits& limits) {
  const std::string f = path.string();
  try {
    Image img;
    std::vector<OIIO::ImageSpec> specs;
    open_checked(path, limits, img, specs);
    // Channels in OIIO's order (which is not the file's: OIIO puts R, G, B, A first), decoded in
    // that order by OpenEXR; the header walk above is all OIIO does.
    ExrDecodeRequest req{img.x0, img.y0, img.width, img.height, {}};
    for (int part = 0; part < img.parts; ++part) {
      const OIIO::ImageSpec& s = specs[size_t(part)];
      for (int c = 0; c < s.nchannels; ++c) {
        Channel ch;
        ch.name = s.channel_name(c);
        if (img.find(ch.name)) {
          throw IoError(f + ": channel " + ch.name + " appears in more than one part");
        }
        ch.storage = storage_of(s.channelformat(c));
        img.channels.push_back(std::move(ch));
        req.planes.push_back({part, s.channel_name(c)});
      }
    }
    if (limits.check_seconds > 0 && !limits.checker.empty()) {
      // Planes are allocated as they arrive, one at a time, and copied without a zero fill
      // first: on this path, the cost of reading is mostly that of touching memory.
      decode_exr_in_child(path, limits.checker, req, limits.check_seconds,
                          uint64_t(limits.max_bytes) + (uint64_t(1) << 30),
                          [&](size_t i, const void* values) {
                            const auto* v = static_cast<const float*>(values);
                            reserve_fresh(img.channels[i].data, img.pixels());
                            img.channels[i].data.assign(v, v + img.pixels());
                          });
    } else {
      try {
        decode_exr_planes(f, req, [&](size_t i) -> void* {
          reserve_fresh(img.channels[i].data, img.pixels());
          img.channels[i].data.resize(img.pixels());
          return img.channels[i].data.data();
        });
      } catch (const std::bad_alloc&) {
        throw;
      } catch (const std::exception& e) {
        throw IoError(f + ": pixel data unreadable (truncated or corrupt): " + first_line(e.what()));
      }
    }
    // UINT channels came as raw values: converted as OIIO converts them, in slices so that the
    // conversion never reads what it has written.
    for (auto& ch : img.channels) {
      if (ch.storage != Storage::other) continue;
      std::vector<uint32_t> raw(std::min<size_t>(ch.data.size(), 1 << 16));
      for (size_t at = 0; at < ch.data.size(); at += raw.size()) {
        const size_t n = std::min(raw.size(), ch.data.size() - at);
        std::memcpy(raw.data(), ch.data.data() + at, n * 4);
        OIIO::convert_pixel_values(OIIO::TypeDesc::UINT, raw.data(), OIIO::TypeDesc::FLOAT,
                                   ch.data.data() + at, int(n));
      }
    }
    return img;
  } catch (const IoError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw IoError(f + ": out of memory while reading");
  } catch (const std::exception& e) {
    throw IoError(f + ": " + first_line(e.what()));
  }
}

std::vector<NonFinite> sanitize(Image& img) {
  std::vector<NonFinite> out;
  for (auto& c : img.channels) {
    size_t n = 0;
    for (float& v : c.data) {
      if (!std::isfinite(v)) {
        v = 0.0f;
        ++n;
      }
    }
    if (n) out.push_back({c.name, n});
  }
  return out;
}

}  // namespace isg::io
