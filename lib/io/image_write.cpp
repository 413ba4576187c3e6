#include "io/image.h"

#include "io/exr_decode.h"
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
#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <random>

// Writing: EXR through OpenEXR directly (atomic: a temporary file renamed when complete) and
// display pictures through OIIO.
namespace isg::io {

namespace fs = std::filesystem;
using detail::first_line;
using detail::reserve_fresh;

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

namespace {

// An output is written to a temporary file beside it and renamed over it only once complete
// (issue 54): a full disk, a kill at any point or a second writer leaves the target either as
// it was or whole. The temporary's name carries the writer's pid and host, so that a later write
// of the same target on the same host removes what a killed writer left (its pid gone) and
// never a live writer's, nor one on another host sharing the folder (a farm's file server).
const std::string kTmpTag = ".tmp";

std::string host_name() {
  char h[256] = {};
  if (::gethostname(h, sizeof h - 1) != 0) return "host";
  std::string s(h);
  for (char& c : s)
    if (c == '/' || c == '@') c = '_';
  return s;
}

fs::path temp_beside(const fs::path& path, const std::string& ext) {
  std::mt19937_64 rng(std::random_device{}());
  fs::path tmp = path;
  tmp.replace_filename("." + path.filename().string() + kTmpTag + std::to_string(::getpid()) + "-" +
                       std::to_string(rng() % 1000000) + "@" + host_name() + ext);
  return tmp;
}

// Removes the temporaries of `path` left by writers of this host that are no longer running.
void remove_stale_temps(const fs::path& path) {
  const std::string prefix = "." + path.filename().string() + kTmpTag, host = "@" + host_name() + ".";
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(prefix, 0) != 0 || name.find(host, prefix.size()) == std::string::npos) continue;
    const std::string rest = name.substr(prefix.size());
    const size_t dash = rest.find('-');
    if (dash == std::string::npos || dash == 0 || rest.find_first_not_of("0123456789") != dash) continue;
    const long pid = std::strtol(rest.substr(0, dash).c_str(), nullptr, 10);
    if (pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH) {
      std::error_code rm;
      fs::remove(it->path(), rm);
    }
  }
}

// Renames the finished temporary over the target; with no_clobber, only if the target still
// does not exist, in one step (renameat2's RENAME_NOREPLACE), so a writer that appeared
// meanwhile is never replaced. Returns the error text, empty on success.
std::string commit_temp(const fs::path& tmp, const fs::path& path, bool no_clobber) {
  if (no_clobber) {
    const char* appeared = "appeared while writing, and --no-clobber was given";
    if (::renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, path.c_str(), RENAME_NOREPLACE) == 0) return "";
    if (errno == EEXIST) return appeared;
    if (errno != EINVAL && errno != ENOSYS) return std::strerror(errno);
    // A filesystem without RENAME_NOREPLACE (NFS, some FUSE): link() refuses an existing name
    // as atomically.
    if (::link(tmp.c_str(), path.c_str()) != 0) return errno == EEXIST ? appeared : std::strerror(errno);
    std::error_code ec;
    fs::remove(tmp, ec);
    return "";
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  return ec ? ec.message() : "";
}

// OIIO's names for the EXR standard attributes its reader renames, and the type the EXR
// attribute has; an empty EXR name is one OpenEXR owns (dropped, as OIIO's writer drops it).
struct ExrName {
  const char *oiio, *exr;
  OIIO::TypeDesc type;
};
const ExrName kExrNames[] = {
    {"worldtocamera", "worldToCamera", OIIO::TypeMatrix},
    {"worldtoNDC", "worldToNDC", OIIO::TypeMatrix},
    {"worldtoscreen", "worldToScreen", OIIO::TypeMatrix},
    {"DateTime", "capDate", OIIO::TypeString},
    {"ImageDescription", "comments", OIIO::TypeString},
    {"description", "comments", OIIO::TypeString},
    {"Copyright", "owner", OIIO::TypeString},
    {"XResolution", "xDensity", OIIO::TypeFloat},
    {"ExposureTime", "expTime", OIIO::TypeFloat},
    {"FNumber", "aperture", OIIO::TypeFloat},
    {"smpte:TimeCode", "timeCode", OIIO::TypeTimeCode},
    {"smpte:KeyCode", "keyCode", OIIO::TypeKeyCode},
    {"YResolution", "", {}}, {"planarconfig", "", {}}, {"type", "", {}}, {"tiles", "", {}},
    {"maxSamplesPerPixel", "", {}},
};

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(),
                    [](char x, char y) { return std::tolower(x) == std::tolower(y); });
}

// Adds one of Image::attributes to an OpenEXR header under the name and type OIIO's EXR writer
// would give it, so writing with OpenEXR directly keeps every attribute a write through OIIO
// kept. `formats` is OIIO's list of format names: "tiff:..." and the like are other formats'.
void put_attribute(Imf::Header& h, const OIIO::ParamValue& p, const std::vector<std::string>& formats) {
  std::string name = p.name().string();
  OIIO::TypeDesc t = p.type(), want;
  for (const auto& e : kExrNames) {
    if (iequals(name, e.oiio) || (*e.exr && iequals(name, e.exr))) {
      name = e.exr;
      want = e.type;
      break;
    }
  }
  if (name.empty()) return;
  if (name.rfind("oiio:", 0) == 0 && name != "oiio:ConstantColor" && name != "oiio:AverageColor" &&
      name != "oiio:SHA-1") {
    return;
  }
  if (auto colon = name.find(':'); colon != std::string::npos) {
    std::string prefix = name.substr(0, colon);
    for (auto& c : prefix) c = char(std::tolower(c));
    if (prefix != "openexr" && std::find(formats.begin(), formats.end(), prefix) != formats.end()) return;
  }
  if (name.rfind("ICCProfile:", 0) == 0) return;
  const void* d = p.data();
  float as_float = 0;
  if (want == OIIO::TypeFloat && t == OIIO::TypeInt) {
    as_float = float(*static_cast<const int*>(d));
    d = &as_float;
    t = OIIO::TypeFloat;
  } else if (want == OIIO::TypeMatrix && t == OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 16)) {
    t = OIIO::TypeMatrix;
  }
  if (want != OIIO::TypeDesc() && !want.equivalent(t)) return;
  const char* n = name.c_str();
  const auto* f = static_cast<const float*>(d);
  const auto* i = static_cast<const int*>(d);
  const auto* db = static_cast<const double*>(d);
  const auto base = OIIO::TypeDesc::BASETYPE(t.basetype);
  const bool is_int = base == OIIO::TypeDesc::INT || base == OIIO::TypeDesc::UINT;
  const bool is_float = base == OIIO::TypeDesc::FLOAT, is_double = base == OIIO::TypeDesc::DOUBLE;
  // Vectors and matrices come as aggregates or as plain arrays of 2, 3, 9 or 16 values.
  const int values = int(t.basevalues());
  const bool plain = t.aggregate == OIIO::TypeDesc::SCALAR;
  auto shape = [&](OIIO::TypeDesc::AGGREGATE agg, int len) {
    return (t.arraylen == 0 && t.aggregate == agg) || (plain && t.arraylen == len);
  };
  if (t == OIIO::TypeString) {
    if (const char* v = *static_cast<const char* const*>(d)) h.insert(n, Imf::StringAttribute(v));
  } else if (t == OIIO::TypeTimeCode) {
    const auto* u = static_cast<const unsigned*>(d);
    h.insert(n, Imf::TimeCodeAttribute(Imf::TimeCode(u[0], u[1])));
  } else if (t == OIIO::TypeKeyCode) {
    h.insert(n, Imf::KeyCodeAttribute(Imf::KeyCode(i[0], i[1], i[2], i[3], i[4], i[5], i[6])));
  } else if (t.arraylen == 0 && t.aggregate == OIIO::TypeDesc::SCALAR) {
    switch (base) {
      case OIIO::TypeDesc::INT: case OIIO::TypeDesc::UINT: h.insert(n, Imf::IntAttribute(*i)); break;
      case OIIO::TypeDesc::INT16: h.insert(n, Imf::IntAttribute(*static_cast<const int16_t*>(d))); break;
      case OIIO::TypeDesc::UINT16: h.insert(n, Imf::IntAttribute(*static_cast<const uint16_t*>(d))); break;
      case OIIO::TypeDesc::FLOAT: h.insert(n, Imf::FloatAttribute(*f)); break;
      case OIIO::TypeDesc::HALF: h.insert(n, Imf::FloatAttribute(float(*static_cast<const half*>(d)))); break;
      case OIIO::TypeDesc::DOUBLE: h.insert(n, Imf::DoubleAttribute(*db)); break;
      default: break;
    }
  } else if (is_int && t.arraylen == 0 && t.aggregate == OIIO::TypeDesc::VEC2 &&
             t.vecsemantics == OIIO::TypeDesc::RATIONAL) {
    h.insert(n, Imf::RationalAttribute(Imf::Rational(i[0], static_cast<const unsigned*>(d)[1])));
  } else if (t.arraylen == 2 && t.aggregate == OIIO::TypeDesc::VEC2 && (is_int || is_float)) {
    // Two 2-vectors: a box.
    if (is_int) h.insert(n, Imf::Box2iAttribute(Imath::Box2i({i[0], i[1]}, {i[2], i[3]})));
    else h.insert(n, Imf::Box2fAttribute(Imath::Box2f({f[0], f[1]}, {f[2], f[3]})));
  } else if (shape(OIIO::TypeDesc::VEC2, 2) && (is_int || is_float || is_double)) {
    if (is_int) h.insert(n, Imf::V2iAttribute(Imath::V2i(i[0], i[1])));
    else if (is_float) h.insert(n, Imf::V2fAttribute(Imath::V2f(f[0], f[1])));
    else h.insert(n, Imf::V2dAttribute(Imath::V2d(db[0], db[1])));
  } else if (shape(OIIO::TypeDesc::VEC3, 3) && (is_int || is_float || is_double)) {
    if (is_int) h.insert(n, Imf::V3iAttribute(Imath::V3i(i[0], i[1], i[2])));
    else if (is_float) h.insert(n, Imf::V3fAttribute(Imath::V3f(f[0], f[1], f[2])));
    else h.insert(n, Imf::V3dAttribute(Imath::V3d(db[0], db[1], db[2])));
  } else if (shape(OIIO::TypeDesc::MATRIX33, 9) && (is_float || is_double)) {
    if (is_float) h.insert(n, Imf::M33fAttribute(Imath::M33f(reinterpret_cast<const float(*)[3]>(f))));
    else h.insert(n, Imf::M33dAttribute(Imath::M33d(reinterpret_cast<const double(*)[3]>(db))));
  } else if (shape(OIIO::TypeDesc::MATRIX44, 16) && (is_float || is_double)) {
    if (is_float) h.insert(n, Imf::M44fAttribute(Imath::M44f(reinterpret_cast<const float(*)[4]>(f))));
    else h.insert(n, Imf::M44dAttribute(Imath::M44d(reinterpret_cast<const double(*)[4]>(db))));
  } else if (t.arraylen > 0 && is_float && values == 8 && name == "chromaticities") {
    h.insert(n, Imf::ChromaticitiesAttribute(Imf::Chromaticities(
                    {f[0], f[1]}, {f[2], f[3]}, {f[4], f[5]}, {f[6], f[7]})));
  } else if (t.arraylen > 0 && base == OIIO::TypeDesc::STRING) {
    const auto* v = static_cast<const char* const*>(d);
    h.insert(n, Imf::StringVectorAttribute(Imf::StringVector(v, v + values)));
  } else if (t.arraylen > 0 && is_float) {
    h.insert(n, Imf::FloatVectorAttribute(Imf::FloatVector(f, f + values)));
  }
  // Anything else (arrays of unknown length, other shapes) OIIO's writer drops too.
}

// The capDate OIIO's writer gives a file whose attributes have no DateTime: now, local time.
std::string now_as_exif_date() {
  std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::localtime_r(&now, &tm);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d:%02d:%02d %02d:%02d:%02d", tm.tm_year + 1900, tm.tm_mon + 1,
                tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec);
  return buf;
}

}  // namespace

void write_exr(const fs::path& path, const Image& img, const WriteOptions& opt) {
  const std::string f = path.string();
  check_writable(path, opt);
  // "name" or "name:level", as OIIO takes it.
  static const std::pair<const char*, Imf::Compression> kCompressions[] = {
      {"none", Imf::NO_COMPRESSION}, {"rle", Imf::RLE_COMPRESSION},     {"zip", Imf::ZIP_COMPRESSION},
      {"zips", Imf::ZIPS_COMPRESSION}, {"piz", Imf::PIZ_COMPRESSION},   {"pxr24", Imf::PXR24_COMPRESSION},
      {"b44", Imf::B44_COMPRESSION},   {"b44a", Imf::B44A_COMPRESSION}, {"dwaa", Imf::DWAA_COMPRESSION},
      {"dwab", Imf::DWAB_COMPRESSION}};
  const std::string comp_name = opt.compression.substr(0, opt.compression.find(':'));
  int level = 0;
  if (auto colon = opt.compression.find(':'); colon != std::string::npos) {
    level = std::atoi(opt.compression.c_str() + colon + 1);
  }
  const auto* comp = std::find_if(std::begin(kCompressions), std::end(kCompressions),
                                  [&](const auto& c) { return comp_name == c.first; });
  if (comp == std::end(kCompressions)) {
    throw IoError("--compression " + opt.compression + ": unknown EXR compression");
  }
  for (const auto& c : img.channels) {
    if (c.data.size() != img.pixels()) throw IoError(f + ": channel " + c.name + ": wrong pixel count");
  }

  const Imath::Box2i data(Imath::V2i(img.x0, img.y0),
                          Imath::V2i(img.x0 + img.width - 1, img.y0 + img.height - 1));
  const int full_w = img.full_w ? img.full_w : img.width, full_h = img.full_h ? img.full_h : img.height;
  const Imath::Box2i display(Imath::V2i(img.full_x0, img.full_y0),
                             Imath::V2i(img.full_x0 + full_w - 1, img.full_y0 + full_h - 1));
  Imf::Header header(display, data);
  // OIIO's choices, kept: DWA on a single channel falls back to zip; zip's level defaults to 4.
  Imf::Compression compression = comp->second;
  if (img.channels.size() == 1 && comp_name.rfind("dwa", 0) == 0) compression = Imf::ZIP_COMPRESSION;
  header.compression() = compression;
  if (compression == Imf::ZIP_COMPRESSION || compression == Imf::ZIPS_COMPRESSION) {
    header.zipCompressionLevel() = level >= 1 && level <= 9 ? level : 4;
  }
  if (compression == Imf::DWAA_COMPRESSION || compression == Imf::DWAB_COMPRESSION) {
    header.dwaCompressionLevel() = level > 0 ? float(level) : 45.0f;
    header.insert("dwaCompressionLevel", Imf::FloatAttribute(header.dwaCompressionLevel()));
  }
  // Float channels are written from their planes where they are. OpenEXR's writer does not
  // convert, so half channels get a half copy, rounded by OIIO's converter as a write through
  // OIIO rounded them.
  Imf::FrameBuffer fb;
  std::vector<std::vector<half>> halves;
  for (const auto& c : img.channels) {
    const bool is_half = c.storage == Storage::half;
    header.channels().insert(c.name, Imf::Channel(is_half ? Imf::HALF : Imf::FLOAT));
    if (!is_half) {
      fb.insert(c.name, Imf::Slice::Make(Imf::FLOAT, c.data.data(), data, 4, 4 * size_t(img.width)));
      continue;
    }
    auto& h = halves.emplace_back();
    reserve_fresh(h, img.pixels());
    h.resize(img.pixels());
    OIIO::parallel_convert_image(1, img.width, img.height, 1, c.data.data(), OIIO::TypeDesc::FLOAT,
                                 OIIO::AutoStride, OIIO::AutoStride, OIIO::AutoStride, h.data(),
                                 OIIO::TypeDesc::HALF, OIIO::AutoStride, OIIO::AutoStride,
                                 OIIO::AutoStride);
    fb.insert(c.name, Imf::Slice::Make(Imf::HALF, h.data(), data, 2, 2 * size_t(img.width)));
  }
  std::string format_list;
  OIIO::getattribute("format_list", format_list);
  std::vector<std::string> formats;
  for (size_t a = 0; a <= format_list.size();) {
    size_t b = std::min(format_list.find(',', a), format_list.size());
    formats.push_back(format_list.substr(a, b - a));
    a = b + 1;
  }
  for (const auto& p : img.attributes) {
    // Structural attributes are the writer's to set.
    std::string n = p.name().string();
    if (n == "compression" || n == "oiio:ColorSpace" || n.rfind("openexr:", 0) == 0 ||
        n == "PixelAspectRatio" || n == "screenWindowCenter" || n == "screenWindowWidth" ||
        n == "oiio:subimages" || n == "oiio:subimagename" || n == "name" || n == "chunkCount" ||
        n == "view") {
      continue;
    }
    put_attribute(header, p, formats);
  }
  if (!img.attributes.contains("DateTime")) header.insert("capDate", Imf::StringAttribute(now_as_exif_date()));
  // As OIIO's writer: the pixel aspect follows the densities when both are given (in inches).
  const float xd = img.attributes.get_float("XResolution"), yd = img.attributes.get_float("YResolution");
  if (xd > 0 && yd > 0) {
    header.pixelAspectRatio() = xd / yd;
    if (img.attributes.get_string("ResolutionUnit") == "cm") header.insert("xDensity", Imf::FloatAttribute(xd / 2.54f));
  }

  remove_stale_temps(path);
  const fs::path tmp = temp_beside(path, ".exr");
  auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(f + ": cannot write: " + first_line(why));
  };
  try {
    // OpenEXR converts and compresses the line blocks on its thread pool, reading the planes
    // where they are: no interleaved copy of the image.
    Imf::OutputFile out(tmp.c_str(), header, exr_thread_count());
    out.setFrameBuffer(fb);
    out.writePixels(img.height);
  } catch (const std::bad_alloc&) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(f + ": out of memory while encoding the output");  // not the file's fault
  } catch (const std::exception& e) {
    fail(e.what());
  }
  if (std::string why = commit_temp(tmp, path, opt.no_clobber); !why.empty()) fail(why);
}

void write_picture(const fs::path& path, int width, int height,
                   const std::vector<unsigned char>& rgb, bool no_clobber) {
  const std::string f = path.string();
  check_writable(path, {"zip", no_clobber});
  std::string ext = path.extension().string();
  for (auto& c : ext) c = char(std::tolower(c));
  if (ext != ".png" && ext != ".jpg" && ext != ".jpeg") throw IoError(f + ": pictures are .png or .jpg");
  remove_stale_temps(path);
  const fs::path tmp = temp_beside(path, ext);
  auto out = OIIO::ImageOutput::create(tmp.string());
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  bool ok = out && out->open(tmp.string(), spec) &&
            out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) && out->close();
  std::string why = ok ? commit_temp(tmp, path, no_clobber) : (out ? out->geterror() : std::string("no writer"));
  if (!why.empty()) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(f + ": cannot write the picture: " + first_line(why));
  }
}

}  // namespace isg::io
