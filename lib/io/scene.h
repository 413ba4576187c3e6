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

struct ShadowMap {
  std::filesystem::path file;
  Mat4 world_to_light = identity4();
  std::string projection = "perspective";
  double yfov_deg = 90.0, near_clip = 0.05, far_clip = 100.0;
  int width = 0, height = 0;
};

enum class LightType { sphere, disk, rect, point };
const char* to_string(LightType t);

struct Light {
  std::string name;
  LightType type = LightType::point;
  Vec3 position{0, 0, 0};
  double radius = 0.0;
  Vec3 normal{0, 0, -1};
  std::array<double, 2> size{0, 0};
  Vec3 u_axis{1, 0, 0};
  std::optional<ShadowMap> shadowmap;
};

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
