#include "io/image.h"

#include "io/exr_check.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <random>

namespace isg::io {

namespace fs = std::filesystem;

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

std::string first_line(std::string s) {
  auto nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  return s;
}

Storage storage_of(OIIO::TypeDesc t) {
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
    } else if (s.width != img.width || s.height != img.height || s.x != img.x0 || s.y != img.y0) {
      throw IoError(f + ": part " + std::to_string(part) +
                    " has a different data window from part 0 (all parts must share one)");
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
    auto in = open_checked(path, limits, img, specs);
    if (limits.check_seconds > 0 && !limits.checker.empty()) {
      check_exr_with_library(path, limits.checker, limits.check_seconds,
                             uint64_t(limits.max_bytes) + (uint64_t(1) << 30));
    }
    for (int part = 0; part < img.parts; ++part) {
      const OIIO::ImageSpec& s = specs[part];
      std::vector<float> buf(img.pixels() * size_t(s.nchannels));
      if (!in->read_image(part, 0, 0, s.nchannels, OIIO::TypeDesc::FLOAT, buf.data())) {
        throw IoError(f + ": pixel data unreadable (truncated or corrupt): " +
                      first_line(in->geterror()));
      }
      for (int c = 0; c < s.nchannels; ++c) {
        Channel ch;
        ch.name = s.channel_name(c);
        if (img.find(ch.name)) {
          throw IoError(f + ": channel " + ch.name + " appears in more than one part");
        }
        ch.storage = storage_of(s.channelformat(c));
        ch.data.resize(img.pixels());
        for (size_t i = 0; i < img.pixels(); ++i) ch.data[i] = buf[i * s.nchannels + c];
        img.channels.push_back(std::move(ch));
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

void check_writable(const fs::path& path, const WriteOptions& opt) {
  const std::string f = path.string();
  std::error_code ec;
  if (opt.no_clobber && fs::exists(path, ec)) {
    throw IoError(f + ": exists, and --no-clobber was given");
  }
  if (fs::is_directory(path, ec)) throw IoError(f + ": is a folder");
  fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  if (!fs::is_directory(dir, ec)) throw IoError(f + ": folder " + dir.string() + " does not exist");
  if (::access(dir.c_str(), W_OK) != 0) throw IoError(f + ": folder " + dir.string() + " is not writable");
  if (fs::exists(path, ec) && ::access(path.c_str(), W_OK) != 0) {
    throw IoError(f + ": exists and is not writable");
  }
}

void write_exr(const fs::path& path, const Image& img, const WriteOptions& opt) {
  const std::string f = path.string();
  check_writable(path, opt);
  static const char* kCompressions[] = {"none", "rle", "zip", "zips", "piz", "pxr24",
                                        "b44", "b44a", "dwaa", "dwab"};
  bool known = false;
  for (const char* c : kCompressions) known |= opt.compression.rfind(c, 0) == 0;
  if (!known) throw IoError("--compression " + opt.compression + ": unknown EXR compression");

  OIIO::ImageSpec spec(img.width, img.height, int(img.channels.size()), OIIO::TypeDesc::FLOAT);
  spec.x = img.x0;
  spec.y = img.y0;
  spec.full_x = img.full_x0;
  spec.full_y = img.full_y0;
  spec.full_width = img.full_w ? img.full_w : img.width;
  spec.full_height = img.full_h ? img.full_h : img.height;
  spec.channelnames.clear();
  spec.channelformats.clear();
  for (const auto& c : img.channels) {
    spec.channelnames.push_back(c.name);
    spec.channelformats.push_back(c.storage == Storage::half ? OIIO::TypeDesc::HALF
                                                             : OIIO::TypeDesc::FLOAT);
  }
  spec.alpha_channel = -1;
  spec.z_channel = -1;
  for (const auto& p : img.attributes) {
    // Structural attributes are the writer's to set.
    std::string n = p.name().string();
    if (n == "compression" || n == "oiio:ColorSpace" || n.rfind("openexr:", 0) == 0 ||
        n == "PixelAspectRatio" || n == "screenWindowCenter" || n == "screenWindowWidth" ||
        n == "oiio:subimages" || n == "oiio:subimagename" || n == "name" || n == "chunkCount" ||
        n == "view") {
      continue;
    }
    spec.extra_attribs.push_back(p);
  }
  spec.attribute("compression", opt.compression);

  // Temporary file in the target's folder so the final rename is atomic.
  std::mt19937_64 rng(std::random_device{}());
  fs::path tmp = path;
  std::string tmp_name(1, '.');
  tmp_name.append(path.filename().string()).append(".tmp").append(std::to_string(rng() % 1000000));
  tmp_name.append(".exr");
  tmp.replace_filename(tmp_name);
  auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(f + ": cannot write: " + first_line(why));
  };
  try {
    auto out = OIIO::ImageOutput::create("openexr");
    if (!out) fail(OIIO::geterror());
    if (!out->open(tmp.string(), spec)) fail(out->geterror());
    const size_t nc = img.channels.size();
    std::vector<float> buf(img.pixels() * nc);
    for (size_t c = 0; c < nc; ++c) {
      const auto& d = img.channels[c].data;
      for (size_t i = 0; i < img.pixels(); ++i) buf[i * nc + c] = d[i];
    }
    if (!out->write_image(OIIO::TypeDesc::FLOAT, buf.data())) fail(out->geterror());
    if (!out->close()) fail(out->geterror());
  } catch (const IoError&) {
    throw;
  } catch (const std::exception& e) {
    fail(e.what());
  }
  std::error_code ec;
  if (opt.no_clobber && fs::exists(path, ec)) fail("appeared while writing, and --no-clobber was given");
  fs::rename(tmp, path, ec);
  if (ec) fail(ec.message());
}

void write_picture(const fs::path& path, int width, int height,
                   const std::vector<unsigned char>& rgb, bool no_clobber) {
  const std::string f = path.string();
  check_writable(path, {"zip", no_clobber});
  std::string ext = path.extension().string();
  for (auto& c : ext) c = char(std::tolower(c));
  if (ext != ".png" && ext != ".jpg" && ext != ".jpeg") throw IoError(f + ": pictures are .png or .jpg");
  std::string tmp_name(1, '.');
  tmp_name.append(path.filename().string()).append(".tmp").append(ext);
  fs::path tmp = path;
  tmp.replace_filename(tmp_name);
  auto out = OIIO::ImageOutput::create(tmp.string());
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  bool ok = out && out->open(tmp.string(), spec) &&
            out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) && out->close();
  std::error_code ec;
  if (ok) fs::rename(tmp, path, ec);
  if (!ok || ec) {
    fs::remove(tmp, ec);
    throw IoError(f + ": cannot write the picture" + (out ? ": " + first_line(out->geterror()) : std::string()));
  }
}

}  // namespace isg::io
