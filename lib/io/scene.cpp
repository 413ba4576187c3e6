#include "io/scene.h"

#include <OpenImageIO/typedesc.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace isg::io {

using json = nlohmann::json;
namespace fs = std::filesystem;

Mat4 identity4() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Mat4 mul(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[i * 4 + k] * b[k * 4 + j];
      r[i * 4 + j] = s;
    }
  return r;
}

Mat4 inverse(const Mat4& m) {
  // Gauss-Jordan with partial pivoting, in double.
  double a[4][8];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 8; ++j) a[i][j] = j < 4 ? m[i * 4 + j] : (j - 4 == i ? 1.0 : 0.0);
  for (int c = 0; c < 4; ++c) {
    int p = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(a[r][c]) > std::abs(a[p][c])) p = r;
    if (std::abs(a[p][c]) < 1e-300) throw IoError("matrix is singular");
    if (p != c)
      for (int j = 0; j < 8; ++j) std::swap(a[p][j], a[c][j]);
    double d = a[c][c];
    for (int j = 0; j < 8; ++j) a[c][j] /= d;
    for (int r = 0; r < 4; ++r) {
      if (r == c) continue;
      double f = a[r][c];
      for (int j = 0; j < 8; ++j) a[r][j] -= f * a[c][j];
    }
  }
  Mat4 r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r[i * 4 + j] = a[i][j + 4];
  return r;
}

Vec3 transform_point(const Mat4& m, const Vec3& p) {
  Vec3 r{};
  for (int i = 0; i < 3; ++i) r[i] = m[i * 4] * p[0] + m[i * 4 + 1] * p[1] + m[i * 4 + 2] * p[2] + m[i * 4 + 3];
  return r;
}

std::array<double, 3> Camera::project(const Vec3& world) const {
  Vec3 c = transform_point(world_to_camera, world);
  double z = -c[2];
  double t = std::tan(yfov_deg * M_PI / 360.0);
  double aspect = double(width) / double(height);
  double ndc_x = c[0] / (z * t * aspect);
  double ndc_y = c[1] / (z * t);
  return {(ndc_x * 0.5 + 0.5) * width, (0.5 - ndc_y * 0.5) * height, z};
}

double Camera::pixel_size_at(double z) const {
  return 2.0 * z * std::tan(yfov_deg * M_PI / 360.0) / double(height);
}

const char* to_string(LightType t) {
  switch (t) {
    case LightType::sphere: return "sphere";
    case LightType::disk: return "disk";
    case LightType::rect: return "rect";
    case LightType::point: return "point";
    case LightType::spot: return "spot";
    case LightType::sun: return "sun";
  }
  return "?";
}

std::string describe(const Light& l) {
  std::ostringstream o;
  o.precision(4);
  auto vec = [&](const Vec3& v) { o << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")"; };
  o << to_string(l.type) << ": ";
  switch (l.type) {
    case LightType::sun:
      o << l.angle_deg << " deg disk toward ";
      vec(l.direction);
      break;
    case LightType::spot:
      o << "disk of radius " << l.radius << " at ";
      vec(l.position);
      o << " shining along ";
      vec(l.normal);
      o << ", cone " << l.spot_angle_deg << " deg, blend " << l.spot_blend;
      break;
    case LightType::rect:
      o << l.size[0] << " x " << l.size[1] << " at ";
      vec(l.position);
      break;
    case LightType::point:
      o << "at ";
      vec(l.position);
      break;
    default:
      o << "radius " << l.radius << " at ";
      vec(l.position);
  }
  if (l.shadowmap) {
    const ShadowMap& m = *l.shadowmap;
    o << "; " << m.projection << " map ";
    if (m.orthographic()) o << m.width_m << " x " << m.height_m << " m, ";
    else o << m.yfov_deg << " deg, ";
    o << m.width << "x" << m.height;
  } else {
    o << "; no shadow map";
  }
  return o.str();
}

const Light* Scene::light(const std::string& name) const {
  for (const auto& l : lights)
    if (l.name == name) return &l;
  return nullptr;
}

namespace {

// Strict reading of one JSON object: every key must be consumed.
class Reader {
 public:
  Reader(const json& j, std::string where, std::string file)
      : j_(j), where_(std::move(where)), file_(std::move(file)) {
    if (!j_.is_object()) fail("", "must be an object");
  }
  [[noreturn]] void fail(const std::string& key, const std::string& why) const {
    std::string k = where_.empty() ? key : (key.empty() ? where_ : where_ + "." + key);
    throw IoError(file_ + ": " + k + ": " + why);
  }
  bool has(const std::string& k) const { return j_.contains(k); }
  const json& raw(const std::string& k) {
    used_.insert(k);
    return j_.at(k);
  }
  double number(const std::string& k, double lo, double hi, bool lo_open = false) {
    if (!has(k)) fail(k, "missing");
    const json& v = raw(k);
    if (!v.is_number()) fail(k, "must be a number");
    double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi || (lo_open && d == lo)) {
      std::ostringstream s;
      s << "value " << d << " is out of range " << (lo_open ? "(" : "[") << lo << ", " << hi << "]";
      fail(k, s.str());
    }
    return d;
  }
  double number_or(const std::string& k, double def, double lo, double hi, bool lo_open = false) {
    return has(k) ? number(k, lo, hi, lo_open) : def;
  }
  int integer(const std::string& k, int lo, int hi) {
    if (!has(k)) fail(k, "missing");
    const json& v = raw(k);
    if (!v.is_number_integer()) fail(k, "must be an integer");
    int64_t d = v.get<int64_t>();
    if (d < lo || d > hi) fail(k, "value " + std::to_string(d) + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(d);
  }
  std::string string(const std::string& k, const std::set<std::string>& allowed = {}) {
    if (!has(k)) fail(k, "missing");
    const json& v = raw(k);
    if (!v.is_string()) fail(k, "must be a string");
    std::string s = v.get<std::string>();
    if (!allowed.empty() && !allowed.count(s)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(k, "'" + s + "' is not one of " + list);
    }
    return s;
  }
  std::vector<double> numbers(const std::string& k, size_t n) {
    if (!has(k)) fail(k, "missing");
    const json& v = raw(k);
    if (!v.is_array() || v.size() != n) fail(k, "must be an array of " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (const auto& e : v) {
      if (!e.is_number() || !std::isfinite(e.get<double>())) fail(k, "must hold finite numbers");
      out.push_back(e.get<double>());
    }
    return out;
  }
  Vec3 vec3(const std::string& k) {
    auto v = numbers(k, 3);
    return {v[0], v[1], v[2]};
  }
  Vec3 unit3(const std::string& k) {
    Vec3 v = vec3(k);
    double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l < 1e-12) fail(k, "must be a non-zero vector");
    return {v[0] / l, v[1] / l, v[2] / l};
  }
  Mat4 matrix(const std::string& k) {
    auto v = numbers(k, 16);
    Mat4 m{};
    std::copy(v.begin(), v.end(), m.begin());
    try {
      inverse(m);
    } catch (const IoError&) {
      fail(k, "matrix is singular");
    }
    return m;
  }
  Reader child(const std::string& k) {
    if (!has(k)) fail(k, "missing");
    return Reader(raw(k), where_.empty() ? k : where_ + "." + k, file_);
  }
  void finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      if (!used_.count(it.key())) fail(it.key(), "unknown key");
    }
  }
  const std::string& where() const { return where_; }

 private:
  const json& j_;
  std::string where_, file_;
  std::set<std::string> used_;
};

Camera read_camera(Reader r) {
  Camera c;
  c.source = "scene file";
  c.world_to_camera = r.matrix("world_to_camera");
  c.projection = r.string("projection", {"perspective"});
  c.yfov_deg = r.number("yfov_deg", 0.0, 179.0, true);
  c.width = r.integer("width", 1, 1 << 16);
  c.height = r.integer("height", 1, 1 << 16);
  c.near_clip = r.number_or("near", 0.1, 0.0, 1e30, true);
  c.far_clip = r.number_or("far", 1e4, 0.0, 1e30, true);
  if (c.far_clip <= c.near_clip) r.fail("far", "must be greater than near");
  c.focus_distance = r.number_or("focus_distance", 5.0, 0.0, 1e30, true);
  c.fstop = r.number_or("fstop", 2.8, 0.0, 1e6, true);
  c.focal_length_mm = r.number_or("focal_length_mm", 50.0, 0.0, 1e6, true);
  c.sensor_width_mm = r.number_or("sensor_width_mm", 36.0, 0.0, 1e6, true);
  r.finish();
  return c;
}

ShadowMap read_shadowmap(Reader s, const fs::path& scene_dir, bool distant) {
  ShadowMap m;
  m.file = s.string("file");
  if (m.file.is_relative()) m.file = scene_dir / m.file;
  m.world_to_light = s.matrix("world_to_light");
  m.projection = s.string("projection", {"perspective", "orthographic"});
  // A sun's map is orthographic (its rays are parallel); a light with a position is seen from it.
  if (distant && !m.orthographic()) s.fail("projection", "a sun's shadow map must be orthographic");
  if (!distant && m.orthographic())
    s.fail("projection", "'orthographic' is for a sun's map; a light with a position has a perspective one");
  if (m.orthographic()) {
    m.width_m = s.number("width_m", 0.0, 1e30, true);
    m.height_m = s.number("height_m", 0.0, 1e30, true);
    // Depths are measured from the map's camera plane, which stands before the scene.
    m.near_clip = s.number_or("near", 0.0, 0.0, 1e30);
    m.far_clip = s.number("far", 0.0, 1e30, true);
  } else {
    m.yfov_deg = s.number("yfov_deg", 0.0, 179.0, true);
    m.near_clip = s.number("near", 0.0, 1e30, true);
    m.far_clip = s.number("far", 0.0, 1e30, true);
  }
  if (m.far_clip <= m.near_clip) s.fail("far", "must be greater than near");
  m.width = s.integer("width", 1, 1 << 16);
  m.height = s.integer("height", 1, 1 << 16);
  // Every method's kernels are round in texels: an orthographic map's texels must be square.
  if (m.orthographic() && std::abs(m.width_m / m.width - m.height_m / m.height) > 1e-3 * (m.height_m / m.height))
    s.fail("height_m", "gives texels of another height than width (width_m / width must equal height_m / height)");
  s.finish();
  return m;
}

Light read_light(Reader r, const fs::path& scene_dir) {
  Light l;
  l.name = r.string("name");
  if (l.name.empty() || l.name.find_first_of(". \t") != std::string::npos) {
    r.fail("name", "'" + l.name + "' must be non-empty with no dots or spaces (it prefixes channel names)");
  }
  std::string t = r.string("type", {"sphere", "disk", "rect", "point", "spot", "sun"});
  for (LightType k : {LightType::sphere, LightType::disk, LightType::rect, LightType::point,
                      LightType::spot, LightType::sun})
    if (t == to_string(k)) l.type = k;
  if (l.distant()) {
    // A sun is distant: a direction and the angle of its disk, and nothing placed in the scene.
    if (r.has("position")) r.fail("position", "a sun has no position (it is distant): give its direction");
    for (const char* k : {"radius", "normal", "size", "u_axis", "spot_angle_deg", "spot_blend"})
      if (r.has(k)) r.fail(k, std::string("is not a sun's key (a sun has direction and angle_deg)"));
    l.direction = r.unit3("direction");
    l.angle_deg = r.number("angle_deg", 0.0, 90.0, true);
    if (l.angle_deg >= 90.0) r.fail("angle_deg", "must be below 90 degrees (the full angle of the sun's disk)");
  } else {
    l.position = r.vec3("position");
    const bool round = l.type == LightType::sphere || l.type == LightType::disk || l.type == LightType::spot;
    if (round) {
      l.radius = r.number("radius", 0.0, 1e30, true);
    } else if (r.has("radius")) {
      l.radius = r.number("radius", 0.0, 1e30);
    }
    if (l.type == LightType::disk || l.type == LightType::rect || l.type == LightType::spot ||
        r.has("normal")) {  // required for those, read where given for the rest
      l.normal = r.unit3("normal");
    }
    if (l.type == LightType::rect) {
      auto s = r.numbers("size", 2);
      if (!(s[0] > 0 && s[1] > 0)) r.fail("size", "both extents must be > 0");
      l.size = {s[0], s[1]};
      l.u_axis = r.unit3("u_axis");
    } else {
      if (r.has("size")) r.numbers("size", 2);
      if (r.has("u_axis")) r.unit3("u_axis");
    }
    if (l.type == LightType::spot) {
      // Blender's spot size and blend (its defaults where absent).
      l.spot_angle_deg = r.number_or("spot_angle_deg", 45.0, 0.0, 180.0, true);
      l.spot_blend = r.number_or("spot_blend", 0.15, 0.0, 1.0);
    } else {
      for (const char* k : {"spot_angle_deg", "spot_blend"})
        if (r.has(k)) r.fail(k, std::string("is only a spot light's key"));
    }
    for (const char* k : {"direction", "angle_deg"})
      if (r.has(k)) r.fail(k, std::string("is only a sun's key"));
  }
  if (r.has("shadowmap")) {
    l.shadowmap = read_shadowmap(r.child("shadowmap"), scene_dir, l.distant());
    // A sun's map looks down −Z along −direction (contract input 3): within 1°.
    const Mat4& m = l.shadowmap->world_to_light;
    const double n = std::sqrt(m[8] * m[8] + m[9] * m[9] + m[10] * m[10]);
    if (l.distant() && (m[8] * l.direction[0] + m[9] * l.direction[1] + m[10] * l.direction[2]) < std::cos(M_PI / 180.0) * n)
      r.fail("shadowmap.world_to_light", "must look down -Z along -direction (its +Z axis within 1 degree of the sun's direction)");
  }
  r.finish();
  return l;
}

}  // namespace

Scene parse_scene(const std::string& text, const fs::path& path) {
  const std::string f = path.string();
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    // parse_error, and out_of_range for numbers beyond double (found by fuzz_scene).
    std::string what = e.what();
    auto b = what.find("] ");
    throw IoError(f + ": not valid JSON (" + (b == std::string::npos ? what : what.substr(b + 2)) + ")");
  }
  Scene s;
  s.path = path;
  Reader r(j, "", f);
  if (r.has("units")) s.units = r.string("units");
  s.scene_radius = r.number("scene_radius", 0.0, 1e30, true);
  if (r.has("camera")) s.camera = read_camera(r.child("camera"));
  if (r.has("lights")) {
    const json& ls = r.raw("lights");
    if (!ls.is_array()) r.fail("lights", "must be an array");
    std::set<std::string> names;
    for (size_t i = 0; i < ls.size(); ++i) {
      Light l = read_light(Reader(ls[i], "lights[" + std::to_string(i) + "]", f), path.parent_path());
      if (!names.insert(l.name).second) r.fail("lights[" + std::to_string(i) + "].name", "duplicate light name " + l.name);
      s.lights.push_back(l);
    }
  }
  r.finish();
  return s;
}

Scene read_scene(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path.string() + ": cannot open scene file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), path);
}

std::optional<Camera> camera_from_header(const Image& img) {
  const OIIO::ParamValue* w2c = img.attributes.find_pv("worldToCamera", OIIO::TypeMatrix44);
  if (!w2c) return std::nullopt;
  const float* m = static_cast<const float*>(w2c->data());
  Camera c;
  c.source = "EXR header";
  // Imath matrices act on row vectors (p * M): ours is the transpose.
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) c.world_to_camera[i * 4 + j] = m[j * 4 + i];
  c.width = img.full_w ? img.full_w : img.width;
  c.height = img.full_h ? img.full_h : img.height;
  const OIIO::ParamValue* w2n = img.attributes.find_pv("worldToNDC", OIIO::TypeMatrix44);
  if (w2n) {
    const float* n = static_cast<const float*>(w2n->data());
    Mat4 ndc{};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) ndc[i * 4 + j] = n[j * 4 + i];
    // camera -> NDC. Writers disagree on the NDC range: OpenEXR/RenderMan use [0,1] with
    // (0,0) top left, OpenGL-style writers [-1,1] with y up. The optical axis lands on the
    // screen centre, 0.5 in the first and 0 in the second, which tells them apart; the span of
    // a unit step in camera y at depth 1 over the screen height then gives the field of view.
    Mat4 proj = mul(ndc, inverse(c.world_to_camera));
    auto ndc_y = [&](double y) {
      double p[4] = {0, y, -1, 1}, r[4] = {0, 0, 0, 0};
      for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 4; ++k) r[i] += proj[i * 4 + k] * p[k];
      return r[1] / r[3];
    };
    const double screen = std::abs(ndc_y(0.0)) < 0.25 ? 2.0 : 1.0;  // [-1,1] or [0,1]
    double span = std::abs(ndc_y(1.0) - ndc_y(-1.0)) / screen;
    if (span > 0) c.yfov_deg = 2.0 * std::atan(1.0 / span) * 180.0 / M_PI;
  }
  return c;
}

void set_camera_attributes(Image& img, const Camera& cam) {
  float m[16], n[16];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m[j * 4 + i] = float(cam.world_to_camera[i * 4 + j]);
  // NDC: x,y in [0,1], (0,0) top left; perspective divide by -z.
  double t = std::tan(cam.yfov_deg * M_PI / 360.0);
  double a = double(cam.width) / cam.height;
  Mat4 p{0.5 / (t * a), 0, -0.5, 0,  //
         0, -0.5 / t, -0.5, 0,      //
         0, 0, -1, 0,               //
         0, 0, -1, 0};
  Mat4 w2n = mul(p, cam.world_to_camera);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) n[j * 4 + i] = float(w2n[i * 4 + j]);
  img.attributes.remove("worldToCamera");
  img.attributes.remove("worldToNDC");
  img.attributes.push_back(OIIO::ParamValue("worldToCamera", OIIO::TypeMatrix44, 1, m));
  img.attributes.push_back(OIIO::ParamValue("worldToNDC", OIIO::TypeMatrix44, 1, n));
}

}  // namespace isg::io
