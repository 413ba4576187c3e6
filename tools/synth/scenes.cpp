// The built-in scenes, option validation and the camera/light matrices.
#include <algorithm>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>

#include "synth.h"

namespace isg::synth {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

struct Builder {
  Scene s;
  int material(Material m) {
    s.materials.push_back(m);
    return int(s.materials.size()) - 1;
  }
  void sphere(std::string name, Vec3 c, double r, int m) {
    s.prims.push_back({Primitive::Kind::sphere, std::move(name), c, r, {}, {}, {}, m});
  }
  void box(std::string name, Vec3 c, Vec3 size, int m) {
    s.prims.push_back({Primitive::Kind::box, std::move(name), c, 0, size * 0.5, {}, {}, m});
  }
  void cylinder(std::string name, Vec3 c, double r, double height, int m) {
    s.prims.push_back(
        {Primitive::Kind::cylinder, std::move(name), c, r, {0, 0, height / 2}, {}, {}, m});
  }
  void quad(std::string name, Vec3 c, Vec3 u, Vec3 v, int m) {
    s.prims.push_back({Primitive::Kind::quad, std::move(name), c, 0, {}, u, v, m});
  }
  void floor(double size, int m) { quad("floor", {}, {size / 2, 0, 0}, {0, size / 2, 0}, m); }
  void camera(Vec3 pos, Vec3 target, double focal_mm, double fstop) {
    s.camera.position = pos;
    s.camera.target = target;
    s.camera.focal_length_mm = focal_mm;
    s.camera.sensor_width_mm = 36;
    s.camera.fstop = fstop;
    s.camera.focus_distance = length(target - pos);
  }
};

Material diffuse(Vec3 albedo) { return {albedo, Material::Spec::none, {}, 1.5, 0, 1.0, {}}; }
Material glossy_floor(Vec3 albedo, double roughness, double weight) {
  return {albedo, Material::Spec::constant, {0.95, 0.95, 0.95}, 1.5, weight, roughness, {}};
}

// Cycles' contact case (cases/contact/README.md), except the floor's gloss is rough (0.2) so
// that the glossy reference differs from the sharp reflection.
Scene contact(int frame) {
  Builder b;
  b.s.name = "contact";
  b.floor(
      14.0,
      b.material({{0.55, 0.53, 0.5}, Material::Spec::fresnel, {1.0, 0.92, 0.8}, 1.5, 0, 0.2, {}}));
  // The moving object: the sphere rolls along +X by 0.1 per frame.
  b.sphere("sphere0", {-1.1 + 0.1 * frame, 0.5, 0.5}, 0.5, b.material(diffuse({0.75, 0.32, 0.22})));
  b.box("box1", {0.9, 0.7, 0.925}, {0.8, 0.8, 0.25}, b.material(diffuse({0.25, 0.45, 0.75})));
  b.cylinder("cylinder2", {0.05, -0.6, 0.8}, 0.04, 1.6, b.material(diffuse({0.8, 0.8, 0.75})));
  // Cycles' 1100 W point light: intensity 1100/(4π) W/sr.
  const double watts = 1100.0 / (4 * std::numbers::pi);
  b.s.lights = {{Light::Type::sphere,
                 {2.6, -1.2, 4.6},
                 0.4,
                 {0, 0, -1},
                 {1, 0, 0},
                 1,
                 1,
                 {watts, watts, watts}}};
  b.camera({0.4, -6.4, 3.1}, {0.0, 0.3, 0.35}, 40, 2.8);
  return b.s;
}

// Disk light parallel to an occluder half-plane (x < 0 at z = 1.2) and a receiver (z = 0):
// the configuration in which PCSS / CSSM / VSSM are exact.
Scene parallel_planes(int frame) {
  Builder b;
  b.s.name = "parallel-planes";
  b.floor(12.0, b.material(diffuse({0.6, 0.6, 0.6})));
  const double edge = 0.05 * frame;  // the occluder's edge slides along +X
  b.quad("occluder", {edge - 4.0, 0, 1.2}, {4.0, 0, 0}, {0, 6.0, 0},
         b.material(diffuse({0.3, 0.5, 0.3})));
  b.s.lights = {
      {Light::Type::disk, {-1.0, 0, 4.0}, 1.0, {0, 0, -1}, {1, 0, 0}, 1, 1, {60, 60, 60}}};
  b.s.parallel_planes = ParallelPlanes{0.0, 1.2, edge};
  b.camera({3.0, -5.0, 3.0}, {0.4, 0, 0.3}, 35, 2.8);
  return b.s;
}

// Blockers at several heights over one receiver, under a rect light.
Scene stack(int frame) {
  Builder b;
  b.s.name = "stack";
  b.floor(12.0, b.material(diffuse({0.6, 0.58, 0.55})));
  b.box("low", {-1.0 + 0.05 * frame, 0.2, 0.25}, {0.5, 0.5, 0.1},
        b.material(diffuse({0.7, 0.3, 0.25})));
  b.box("mid", {0.0, 0.0, 0.9}, {0.6, 0.4, 0.08}, b.material(diffuse({0.3, 0.6, 0.3})));
  b.box("high", {0.9, -0.2, 1.8}, {0.5, 0.7, 0.06}, b.material(diffuse({0.3, 0.4, 0.75})));
  b.cylinder("post", {0.0, 0.0, 0.43}, 0.03, 0.86, b.material(diffuse({0.8, 0.8, 0.75})));
  b.sphere("ball", {1.3, 0.9, 0.3}, 0.3, b.material(diffuse({0.8, 0.7, 0.3})));
  b.s.lights = {{Light::Type::rect,
                 {0.8, -0.3, 4.0},
                 0.5,
                 normalize(Vec3{-0.15, 0.05, -1}),
                 normalize(Vec3{1, 0, -0.15}),
                 0.9,
                 0.6,
                 {70, 70, 70}}};
  b.camera({1.0, -6.0, 3.6}, {0.2, 0.1, 0.4}, 38, 2.8);
  return b.s;
}

// A mirror-like floor in two halves (roughness 0.1 for x < 0, 0.35 for x > 0) with objects
// at several heights above it.
Scene gloss(int frame) {
  Builder b;
  b.s.name = "gloss";
  const int left = b.material(glossy_floor({0.12, 0.12, 0.14}, 0.1, 0.7));
  const int right = b.material(glossy_floor({0.12, 0.12, 0.14}, 0.35, 0.7));
  b.quad("floor_left", {-3.5, 0, 0}, {3.5, 0, 0}, {0, 7, 0}, left);
  b.quad("floor_right", {3.5, 0, 0}, {3.5, 0, 0}, {0, 7, 0}, right);
  b.sphere("ball_on", {-1.2, 0.6, 0.45}, 0.45, b.material(diffuse({0.8, 0.3, 0.2})));
  b.sphere("ball_float", {1.2 + 0.05 * frame, 0.8, 1.1}, 0.35,
           b.material(diffuse({0.2, 0.7, 0.3})));
  b.box("box_low", {0.2, -0.3, 0.35}, {0.5, 0.5, 0.3}, b.material(diffuse({0.25, 0.45, 0.8})));
  b.cylinder("pillar", {-0.3, 1.8, 0.9}, 0.15, 1.8, b.material(diffuse({0.85, 0.85, 0.8})));
  b.box("back_wall", {0.0, 4.0, 1.5}, {10, 0.2, 3}, b.material(diffuse({0.7, 0.65, 0.55})));
  b.s.lights = {
      {Light::Type::sphere, {-2.0, -1.5, 4.5}, 0.4, {0, 0, -1}, {1, 0, 0}, 1, 1, {70, 70, 70}}};
  b.s.fill = {0.12, 0.13, 0.15};
  b.camera({0.3, -6.0, 2.2}, {0.0, 0.8, 0.5}, 35, 2.8);
  return b.s;
}

// Foreground, in-focus and background objects, small bright emitters (40× the rest).
Scene dof(int frame) {
  Builder b;
  b.s.name = "dof";
  b.s.depth_of_field = true;
  b.floor(40.0, b.material(diffuse({0.5, 0.5, 0.5})));
  b.sphere("fore", {-0.22, -4.2, 0.75}, 0.15, b.material(diffuse({0.8, 0.25, 0.2})));
  b.sphere("focus", {0.1 + 0.03 * frame, 0.0, 0.5}, 0.5, b.material(diffuse({0.3, 0.7, 0.35})));
  b.box("focus_box", {1.0, 0.3, 0.4}, {0.5, 0.5, 0.8}, b.material(diffuse({0.3, 0.4, 0.8})));
  b.box("back", {-1.5, 9.0, 1.5}, {3, 1, 3}, b.material(diffuse({0.75, 0.7, 0.55})));
  b.cylinder("back_pole", {2.5, 7.0, 1.0}, 0.2, 2.0, b.material(diffuse({0.8, 0.8, 0.8})));
  Material lamp = diffuse({0.1, 0.1, 0.1});
  for (int i = 0; i < 5; ++i) {
    lamp.emission = i % 2 ? Vec3{20, 14, 6} : Vec3{8, 12, 20};
    b.sphere("lamp" + std::to_string(i), {-2.0 + 1.1 * i, 8.3 - 0.2 * i, 0.6 + 0.25 * (i % 3)},
             0.05, b.material(lamp));
  }
  b.s.lights = {
      {Light::Type::sphere, {2.5, -2.0, 5.0}, 0.4, {0, 0, -1}, {1, 0, 0}, 1, 1, {90, 90, 90}}};
  b.camera({0.0, -6.0, 1.0}, {0.1, 0.0, 0.5}, 85, 1.4);
  return b.s;
}

void translate(Scene& s, Vec3 t) {
  for (auto& p : s.prims) p.centre += t;
  for (auto& l : s.lights)
    if (l.type != Light::Type::sun) l.position += t;
  s.camera.position += t;
  s.camera.target += t;
}

Scene far_world(int frame) {
  Scene s = contact(frame);
  s.name = "far-world";
  translate(s, {1e5, 1e5, 1e5});
  return s;
}

// contact 1e6 from the origin, where P's float32 step (62.5 mm) spans pixels (issue 19).
Scene far_world_1e6(int frame) {
  Scene s = contact(frame);
  s.name = "far-world-1e6";
  translate(s, {1e6, 1e6, 1e6});
  return s;
}

// contact seen from just above the floor: the camera 0.55 m high and 9.8 m back, so the floor
// meets the view at 75° to 89° from its normal and penumbrae are squeezed on screen.
Scene grazing(int frame) {
  Scene s = contact(frame);
  s.name = "grazing";
  s.camera.position = {0.4, -9.5, 0.55};
  s.camera.focus_distance = length(s.camera.target - s.camera.position);
  return s;
}

// contact with a backdrop wall 1e6 m behind it that fills the rest of the frame: depth spans
// 1.5 to 1e6 m in one image (and the far plane moves out to 1e7 m). The wall faces the camera
// and the key; it is left out of scene_radius, as a renderer's scene scale would leave the sky.
Scene depth_range(int frame) {
  Builder b;
  b.s = contact(frame);
  b.s.name = "depth-range";
  const double far = 1e6;
  b.quad("backdrop", {0, far, 0}, {2 * far, 0, 0}, {0, 0, 2 * far},
         b.material(diffuse({0.5, 0.5, 0.5})));
  b.s.prims.back().backdrop = true;
  b.s.camera.far = 1e7;
  return b.s;
}

// A low sun (30° elevation, from the front right) with a 2.5° disk: penumbrae widen 4.4 cm per
// metre from the occluder. Irradiance 3.5 W/m² facing it, about contact's key on the floor.
Light sun_light(double irradiance) {
  Light l;
  l.type = Light::Type::sun;
  l.name = "sun";
  const double elevation = 30 * kDeg, azimuth = -45 * kDeg;
  l.direction = normalize(Vec3{std::cos(elevation) * std::cos(azimuth),
                               std::cos(elevation) * std::sin(azimuth), std::sin(elevation)});
  l.angle_deg = 2.5;
  l.intensity = {irradiance, irradiance, irradiance};
  return l;
}

// contact's geometry, materials and camera under the sun alone.
Scene sun(int frame) {
  Scene s = contact(frame);
  s.name = "sun";
  s.lights = {sun_light(3.5)};
  return s;
}

// contact's geometry under a spot (r = 0.3, 60° cone, blend 0.3) above and to the right, aimed
// at the floor behind the objects so that the cone's soft edge crosses the floor in frame.
Scene spot(int frame) {
  Scene s = contact(frame);
  s.name = "spot";
  Light l;
  l.type = Light::Type::spot;
  l.name = "spot";
  l.position = {2.0, -1.5, 3.5};
  l.normal = normalize(Vec3{-0.3, 0.6, 0} - l.position);
  l.radius = 0.3;
  l.spot_angle_deg = 60;
  l.spot_blend = 0.3;
  l.intensity = {80, 80, 80};
  s.lights = {l};
  return s;
}

// contact's key, a weaker sun and a rect fill from the front left.
Scene three_lights(int frame) {
  Scene s = contact(frame);
  s.name = "three-lights";
  Light fill;
  fill.type = Light::Type::rect;
  fill.name = "fill";
  fill.position = {-3.0, -2.5, 2.5};
  fill.normal = normalize(Vec3{0.0, 0.3, 0.35} - fill.position);
  fill.u_axis = normalize(cross(Vec3{0, 0, 1}, fill.normal));
  fill.size_u = 1.5;
  fill.size_v = 1.0;
  fill.intensity = {25, 25, 25};
  s.lights.push_back(sun_light(1.2));
  s.lights.push_back(fill);
  return s;
}

using Maker = Scene (*)(int);
struct Entry {
  Maker make;
  const char* description;
};
const std::map<std::string, Entry>& registry() {
  static const std::map<std::string, Entry> r = {
      {"parallel-planes",
       {parallel_planes,
        "disk light parallel to an occluder half-plane and a receiver (closed form)"}},
      {"contact", {contact, "sphere on a plane, floating box, thin pole (like cases/contact)"}},
      {"stack", {stack, "blockers at several heights over one receiver, rect light"}},
      {"gloss",
       {gloss, "mirror-like floor, roughness 0.1 / 0.35 halves, objects at varied heights"}},
      {"dof", {dof, "foreground, in-focus and background objects, small bright emitters"}},
      {"far-world", {far_world, "contact translated by (1e5, 1e5, 1e5)"}},
      {"far-world-1e6", {far_world_1e6, "contact translated by (1e6, 1e6, 1e6)"}},
      {"grazing", {grazing, "contact seen from 0.55 m above the floor (75-89 deg to its normal)"}},
      {"depth-range", {depth_range, "contact before a backdrop 1e6 m away (depth 1.5 to 1e6 m)"}},
      {"sun", {sun, "contact under a low sun (30 deg elevation, 2.5 deg disk), light 'sun'"}},
      {"spot",
       {spot, "contact under a spot (60 deg cone, blend 0.3) whose edge crosses the floor"}},
      {"three-lights", {three_lights, "contact lit by its key, a weaker sun and a rect fill"}},
  };
  return r;
}

void check(bool ok, const std::string& message) {
  if (!ok) throw std::runtime_error(message);
}

// Row-major view matrix from `pos` looking along unit `f`, with +Y up; world +Z up unless
// looking along it.
std::array<double, 16> look_along(Vec3 pos, Vec3 f) {
  Vec3 up{0, 0, 1};
  if (std::abs(dot(f, up)) > 0.999) up = {0, 1, 0};
  const Vec3 r = normalize(cross(f, up));
  const Vec3 u = cross(r, f);
  return {r.x,  r.y,  r.z,  -dot(r, pos), u.x, u.y, u.z, -dot(u, pos),
          -f.x, -f.y, -f.z, dot(f, pos),  0,   0,   0,   1};
}

std::array<double, 16> look_at(Vec3 pos, Vec3 target) {
  return look_along(pos, normalize(target - pos));
}

// The corners of a primitive's bounding box (a quad's four corners).
template <class F>
void for_each_corner(const Primitive& p, F&& f) {
  if (p.kind == Primitive::Kind::quad) {
    for (double a : {-1.0, 1.0})
      for (double b : {-1.0, 1.0}) f(p.centre + a * p.u + b * p.v);
    return;
  }
  Vec3 h = p.half;
  if (p.kind == Primitive::Kind::sphere) h = {p.radius, p.radius, p.radius};
  if (p.kind == Primitive::Kind::cylinder) h = {p.radius, p.radius, p.half.z};
  for (double a : {-1.0, 1.0})
    for (double b : {-1.0, 1.0})
      for (double c : {-1.0, 1.0}) f(p.centre + Vec3{a * h.x, b * h.y, c * h.z});
}

}  // namespace

std::vector<std::string> scene_names() {
  // Presentation order rather than alphabetical.
  return {"parallel-planes", "contact", "stack",       "gloss", "dof",  "far-world",
          "far-world-1e6",   "grazing", "depth-range", "sun",   "spot", "three-lights"};
}

std::string scene_description(const std::string& name) {
  const auto it = registry().find(name);
  check(it != registry().end(), "scene: unknown scene '" + name + "'");
  return it->second.description;
}

void validate(const Options& o) {
  std::string names;
  for (const auto& n : scene_names()) names += (names.empty() ? "" : ", ") + n;
  check(registry().count(o.scene),
        "scene: unknown scene '" + o.scene + "' (one of: " + names + ")");
  auto range = [](const char* opt, double v, double lo, double hi) {
    check(v >= lo && v <= hi, std::string(opt) + " must be in [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "] (got " + std::to_string(v) + ")");
  };
  range("--width", o.width, 1, 16384);
  range("--height", o.height, 1, 16384);
  range("--aov-spp", o.aov_spp, 1, 65536);
  range("--ref-spp", o.ref_spp, 1, 1 << 20);
  range("--threads", o.threads, 0, 1024);
  range("--shadowmap-size", o.shadowmap_size, 16, 16384);
  range("--frame", o.frame, -100000, 100000);
  if (o.light_radius) {
    check(std::isfinite(*o.light_radius) && *o.light_radius > 0,
          "--light-radius must be > 0 (got " + std::to_string(*o.light_radius) + ")");
  }
  if (o.sun_angle) {
    check(std::isfinite(*o.sun_angle) && *o.sun_angle > 0 && *o.sun_angle <= 90,
          "--sun-angle must be in (0, 90] degrees (got " + std::to_string(*o.sun_angle) + ")");
  }
  if (o.roughness) range("--roughness", *o.roughness, 0, 1);
  if (o.fstop) {
    check(std::isfinite(*o.fstop) && *o.fstop > 0,
          "--fstop must be > 0 (got " + std::to_string(*o.fstop) + ")");
  }
}

Scene build_scene(const Options& o) {
  validate(o);
  Scene s = registry().at(o.scene).make(o.frame);
  s.camera.width = o.width;
  s.camera.height = o.height;
  if (o.light_radius) {
    Light& l = s.lights.front();
    check(l.type != Light::Type::sun, "--light-radius: the first light of scene '" + o.scene +
                                          "' is a sun, which has an angle (--sun-angle)");
    if (l.type == Light::Type::rect) {
      const double aspect = l.size_v / l.size_u;
      l.size_u = 2 * *o.light_radius;
      l.size_v = l.size_u * aspect;
    }
    l.radius = *o.light_radius;
  }
  if (o.sun_angle) {
    bool any = false;
    for (auto& l : s.lights) {
      if (l.type != Light::Type::sun) continue;
      l.angle_deg = *o.sun_angle;
      any = true;
    }
    check(any, "--sun-angle: scene '" + o.scene + "' has no sun light");
  }
  if (o.roughness) {
    for (auto& m : s.materials) {
      if (m.spec != Material::Spec::none) m.roughness = *o.roughness;
    }
  }
  if (o.fstop) {
    s.camera.fstop = *o.fstop;
    s.depth_of_field = true;
  }
  return s;
}

std::array<double, 16> world_to_camera(const Camera& cam) {
  return look_at(cam.position, cam.target);
}

ShadowMapView shadowmap_view(const Scene& s, size_t light) {
  const Light& l = s.lights.at(light);
  ShadowMapView v;
  switch (l.type) {
    case Light::Type::sun: {
      // From beyond the bounding sphere on the sun's side, looking down −direction: the map
      // camera's −Z axis is −direction and the sphere lies between near and far.
      const auto [c, r] = bounding_sphere(s);
      const double margin = 0.05 * r + 1e-3;
      v.world_to_light = look_along(c + l.direction * (r + margin), -l.direction);
      v.orthographic = true;
      v.width_m = v.height_m = 2 * r * 1.02;
      v.near = 0;
      v.far = 2 * (r + margin);
      break;
    }
    case Light::Type::spot:
      v.world_to_light = look_along(l.position, normalize(l.normal));
      // 90° unless the cone is wider.
      v.yfov_deg = l.spot_angle_deg <= 80 ? 90.0 : std::min(l.spot_angle_deg + 10, 170.0);
      break;
    default:
      v.world_to_light = look_at(l.position, s.camera.target);
      break;
  }
  return v;
}

std::array<double, 16> world_to_light(const Scene& s, size_t light) {
  return shadowmap_view(s, light).world_to_light;
}

double yfov_deg(const Camera& cam) {
  const double tan_x = cam.sensor_width_mm / (2 * cam.focal_length_mm);
  const double tan_y = tan_x * cam.height / cam.width;
  return 2 * std::atan(tan_y) * 180 / std::numbers::pi;
}

std::array<double, 16> world_to_ndc(const Camera& cam) {
  const double tan_x = cam.sensor_width_mm / (2 * cam.focal_length_mm);
  const double tan_y = tan_x * cam.height / cam.width;
  const double n = cam.near, f = cam.far;
  const std::array<double, 16> p = {
      1 / tan_x, 0, 0,  0, 0, 1 / tan_y, 0, 0, 0, 0, -(f + n) / (f - n), -2 * f * n / (f - n),
      0,         0, -1, 0};
  const auto v = world_to_camera(cam);
  std::array<double, 16> m{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) m[i * 4 + j] += p[i * 4 + k] * v[k * 4 + j];
  return m;
}

double scene_radius(const Scene& s) {
  // Farthest of: every light with a position, every primitive's bounding-box corners.
  const Vec3 c = s.camera.target;
  double r = 0;
  for (const auto& l : s.lights)
    if (l.type != Light::Type::sun) r = std::max(r, length(l.position - c));
  for (const auto& p : s.prims) {
    if (p.backdrop) continue;
    for_each_corner(p, [&](Vec3 q) { r = std::max(r, length(q - c)); });
  }
  return r;
}

std::pair<Vec3, double> bounding_sphere(const Scene& s) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi = -lo;
  auto each = [&](auto&& f) {
    for (const auto& p : s.prims)
      if (!p.backdrop) for_each_corner(p, f);
  };
  each([&](Vec3 q) {
    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
  });
  if (lo.x > hi.x) return {s.camera.target, 1.0};  // no primitives
  const Vec3 c = (lo + hi) * 0.5;
  double r = 0;
  each([&](Vec3 q) { r = std::max(r, length(q - c)); });
  return {c, r};
}

Image::Image(int w, int h, std::vector<std::string> names)
    : width(w),
      height(h),
      channels(std::move(names)),
      pixels(size_t(w) * h * channels.size(), 0.0f) {}

int Image::channel(const std::string& name) const {
  const auto it = std::find(channels.begin(), channels.end(), name);
  check(it != channels.end(), "image has no channel '" + name + "'");
  return int(it - channels.begin());
}

}  // namespace isg::synth
