// Soft-shadow settings of method isg that the planner resolves from the light, the camera and
// the preset (no GPU here).
#pragma once

#include <array>
#include <string>

#include "effects/view.h"
#include "io/scene.h"
#include "params/params.h"

namespace isg::effects {

struct ShadowSettings {
  int grid_search = 5;        // search samples = grid_search², concentric disk, rotated per pixel
  int grid_gather = 7;        // gather samples = grid_gather²
  double sigma = 0.01;        // eq. 6 (l in units of scene_radius)
  double scene_radius = 1.0;
  double max_radius = 64;     // search and gather radius clamp, pixels (clamps are counted)
  bool rotate = true;         // per-pixel rotation of the sample grid (pixel hash)
  bool search_reach = true;   // the search counts only occluders whose penumbra reaches p_0
  bool tile_skip = true;      // tiles with no shadow boundary within reach copy L.shadow
  // The light: centre and L, the radius of eq. 5 and 8 (see light_size()).
  std::array<double, 3> light{0, 0, 0};
  double light_size = 0.0;
  // Disk and rect lights: the penumbra's cross-section lies in the light's plane (normal
  // light_normal); sphere lights: across the ray.
  bool oriented = false;
  std::array<double, 3> light_normal{0, 0, -1};
  // Camera: focal length in pixels of the image filtered, position, world-to-camera rotation.
  double f_px = 1.0;
  std::array<double, 3> eye{0, 0, 0};
  std::array<double, 9> rot{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Window window;            // a tile of a larger frame (principal point, hash origin)
  double d_max_floor = 0.0; // a tile: the whole frame's largest occluder distance (eq. 8)
};

// L of eq. 5 and 8, the light's radius in world units: a sphere's or a disk's radius (a disk is
// taken as seen face-on, as the parallel-planes assumption of §3.1 has it); a rect light's
// area-equivalent radius from its half-extents a, b: sqrt(4ab / π), so the round kernel covers
// the rect's area. 0 for a point light.
double light_size(const io::Light& light);

// Why method isg cannot run for this light ("" when it can).
std::string shadows_isg_unsupported(const io::Light* light);

// From the light, the camera (any resolution: f_px is for `height` rows) and the preset.
ShadowSettings shadow_settings(const io::Light& light, const io::Camera& cam, double scene_radius,
                               const params::Params& p, int height);

}  // namespace isg::effects
