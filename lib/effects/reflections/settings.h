// Glossy-reflection settings the planner resolves from the camera and the preset (no GPU here).
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "effects/view.h"
#include "io/scene.h"
#include "params/params.h"

namespace isg::effects {

struct ReflSettings {
  std::string method = "isg";  // "isg" or "blur"
  int grid_search = 5;         // search samples = grid_search², concentric disk, rotated per 4x4 block
  int grid_gather = 7;         // gather samples = grid_gather²
  double roughness = 0.25;     // where the roughness channel is absent (or overridden)
  bool roughness_override = false;
  double energy = 0.99;                   // fraction of the GGX lobe inside the cone θ_max
  double a = 1.0, b = 1.0, sigma = 0.01;  // eq. 10 (l in units of scene_radius)
  double scene_radius = 1.0;
  double max_radius = 256;     // footprint clamp, pixels
  double blur_radius = 16;     // method blur, pixels
  bool search_reach = true;    // the search counts only reflections whose footprint reaches p_0
  bool search_misses = false;  // misses (t = 1, eq. 13's limit) take part in the search
  bool masking = true;         // the lobe's masking-shadowing loss (Smith) scales refl.glossy
  bool anisotropic = true;     // eq. 14 across the plane of incidence only
  // Camera: focal length in pixels of the image filtered, position, world-to-camera rotation.
  double f_px = 1.0;
  std::array<double, 3> eye{0, 0, 0};
  std::array<double, 9> rot{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Window window;  // a tile of a larger frame (principal point, hash origin)
};

// From the camera (any resolution: f_px is for `height` rows) and the preset.
ReflSettings refl_settings(const io::Camera& cam, double scene_radius, const params::Params& p,
                           int height);

// tan θ_h of the GGX cone holding the fraction E of the NDF's projected area: the CDF in θ_h
// is P(θ_h ≤ t) = tan²t / (α² + tan²t), so tan θ_h = α·sqrt(E / (1 − E)). θ_max = 2·θ_h.
double ggx_cone_tan(double alpha, double energy);

// 16x16 tiles (REFL_TILE) of a w x h image (refl.tiles: statistics and a list of them, then method
// isg's records, shaders/reflections_isg_io.h).
uint32_t refl_tiles(uint32_t w, uint32_t h);
// The words of refl.tiles (shaders/reflections_isg_io.h); `records`: with the quads' and blocks'
// records method isg's four dispatches pass on (method blur has none).
uint32_t refl_tiles_words(uint32_t w, uint32_t h, bool records);
// The 16-byte texels of refl.pack.geo and refl.pack.color: the image's, then its REFL_COARSE²
// cells' (shaders/reflections_isg_io.h).
uint64_t refl_pack_texels(uint32_t w, uint32_t h);

}  // namespace isg::effects
