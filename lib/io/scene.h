// The scene file (contract input 3) and the camera, from the scene file or the EXR header.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/image.h"

namespace isg::io {

// Row-major 4x4, column vectors: p_cam = M * p_world.
using Mat4 = std::array<double, 16>;
using Vec3 = std::array<double, 3>;

Mat4 identity4();
Mat4 mul(const Mat4& a, const Mat4& b);
Mat4 inverse(const Mat4& m);  // throws IoError if singular
Vec3 transform_point(const Mat4& m, const Vec3& p);

struct Camera {
  Mat4 world_to_camera = identity4();  // camera looks down -Z, +Y up
  std::string projection = "perspective";
  double yfov_deg = 40.0;
  int width = 0, height = 0;
  double near_clip = 0.1, far_clip = 1000.0;
  double focus_distance = 5.0, fstop = 2.8, focal_length_mm = 50.0, sensor_width_mm = 36.0;
  std::string source;  // "scene file" or "EXR header"

  // Pixel (x + 0.5, y + 0.5) of a point in world space, and its planar depth.
  std::array<double, 3> project(const Vec3& world) const;
  // World-space size of one pixel at planar depth z (perspective).
  double pixel_size_at(double z) const;
};

// A light's shadow map (contract input 2). Perspective: yfov_deg; orthographic (a sun's): the
// map covers width_m x height_m scene units centred on the view axis. Either way Z is planar
// depth along the axis (the light's -Z).
struct ShadowMap {
  std::filesystem::path file;
  Mat4 world_to_light = identity4();
  std::string projection = "perspective";  // perspective | orthographic
  double yfov_deg = 90.0, near_clip = 0.05, far_clip = 100.0;
  double width_m = 0.0, height_m = 0.0;    // orthographic
  int width = 0, height = 0;
  bool orthographic() const { return projection == "orthographic"; }
};

enum class LightType { sphere, disk, rect, point, spot, sun };
const char* to_string(LightType t);

struct Light {
  std::string name;
  LightType type = LightType::point;
  Vec3 position{0, 0, 0};   // every light but a sun
  double radius = 0.0;      // sphere, disk, spot
  Vec3 normal{0, 0, -1};    // disk, rect; a spot's axis (the way it shines)
  std::array<double, 2> size{0, 0};
  Vec3 u_axis{1, 0, 0};
  double spot_angle_deg = 180.0, spot_blend = 0.0;  // spot: the cone (shapes L.direct only)
  Vec3 direction{0, 0, 1};  // sun: unit vector from the scene toward it
  double angle_deg = 0.0;   // sun: the full angle its disk subtends, (0, 90)
  std::optional<ShadowMap> shadowmap;
  bool distant() const { return type == LightType::sun; }
};

// One line on a light for `isg info`: its kind, size and shadow map, e.g. "sun: 2° disk toward
// (0, 0.6, 0.8); orthographic map 40 x 30 m, 2048x1536".
std::string describe(const Light& l);

struct Scene {
  std::filesystem::path path;
  std::string units = "m";
  double scene_radius = 1.0;
  std::optional<Camera> camera;
  std::vector<Light> lights;
  const Light* light(const std::string& name) const;
};

// Strict: unknown keys, wrong types and out-of-range values are errors naming the key.
Scene read_scene(const std::filesystem::path& path);
Scene parse_scene(const std::string& json_text, const std::filesystem::path& path_for_errors);

// Camera from the OpenEXR standard attributes worldToCamera and worldToNDC, if present.
std::optional<Camera> camera_from_header(const Image& img);

// Writes the camera as worldToCamera / worldToNDC header attributes (Imath row-vector layout).
void set_camera_attributes(Image& img, const Camera& cam);

}  // namespace isg::io
