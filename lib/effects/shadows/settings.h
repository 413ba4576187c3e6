// Soft-shadow settings that the planner resolves from the light, the camera and the preset:
// method isg's, the shadow-map methods', and the shadow map as the load stage reads it (no GPU
// here).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>
#include <string>

#include "effects/view.h"
#include "io/roles.h"
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
  bool search_reach = true;   // the search counts only occluders in p_0's cone to the light
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

// L of eq. 5 and 8, the light's radius in world units: a sphere's, a disk's or a spot's radius
// (a disk is taken as seen face-on, as the parallel-planes assumption of §3.1 has it); a rect
// light's area-equivalent radius from its half-extents a, b: sqrt(4ab / π), so the round kernel
// covers the rect's area. 0 for a point light. A sun: tan of its half angle, its radius per unit
// of distance.
double light_size(const io::Light& light);

// The light's centre and (radius) L for eq. 5 and 8: its position and light_size(); a sun's
// stand-in, a sphere kSunDistance times `scale` (the set's size or distance) from the eye along
// its direction that subtends its angle (settings.cpp).
std::array<double, 3> light_centre_for(const io::Light& light, const std::array<double, 3>& eye,
                                       double scale, double* radius);

// Why method isg cannot run for this light ("" when it can).
std::string shadows_isg_unsupported(const io::Light* light);

// From the light, the camera (any resolution: f_px is for `height` rows) and the preset.
ShadowSettings shadow_settings(const io::Light& light, const io::Camera& cam, double scene_radius,
                               const params::Params& p, int height);

// 16x16 tiles (SHADOWS_ISG_TILE) of a w x h image, and the uint32 words of the tiles buffer
// (flags, cheap-path marks, statistics, the list of shadows.isg.list).
uint32_t shadows_isg_tiles(uint32_t w, uint32_t h);
uint32_t shadows_isg_tiles_words(uint32_t w, uint32_t h);

struct ShadowmapSettings {
  std::string method = "pcss";
  std::filesystem::path file;             // the map's EXR (channel Z)
  io::Mat4 world_to_light = io::identity4();
  double yfov_deg = 90.0;
  // A sun's orthographic map (contract input 3): it covers width_m x height_m around its axis.
  bool ortho = false;
  double width_m = 0.0, height_m = 0.0;
  double far_clip = 1e30;                 // the map's far plane: depths beyond it are background
  // World units (light_size() of the light); a sun: tan of its half angle, its radius per unit
  // of distance (a cone widens by that per unit of depth along the map's axis).
  double light_radius = 0.0;
  bool facing = true;                     // a sphere light (its disk faces the receiver), not a
                                          // disk or rect light (in the map's plane)
  int taps = 32;                          // shadows.pcss_taps
  int pcss_narrow = 1;  // shadows.pcss_narrow: blocker searches narrowed to the blockers' cone
  std::string pattern = "stratified";     // shadows.pcss_pattern: stratified | poisson
  double reach = 2.0;                     // shadows.reach: pcss's and vssm's filter taps (0: off)
  double input_edges = 2.0;               // shadows.input_edges, texels (0: off)
  bool rotate = true;                     // shadows.rotate
  double bias = 2.0;                      // shadows.bias, receiver texel footprints
  double slope_max = 16.0;                // shadows.slope_max
  double spread_bias = 2.0;               // shadows.spread_bias
  double depth_ulps = 1.0;                // shadows.depth_ulps
  double max_radius = 64.0;               // shadows.smap_max_radius, texels
  double scene_radius = 1.0;              // the scene file's scene_radius (r of §7.5.4-7.5.5)
  // vssm (thesis ch. 7)
  int vssm_m = 5;           // shadows.vssm_m: m×m uniform sub-kernels, blocker search (§7.4.2)
  int vssm_m_wide = 3;      // shadows.vssm_m_wide: the first search's, where narrowed ones follow
  // shadows.vssm_h: quad-tree height H, shadow (Algorithm 3). 2: with each sub-kernel tested on
  // its own (shadowmap_vssm.glsl's chebyshev), H 3 -> 2 took own grazing 0.542 -> 0.490 of doing
  // nothing, grazing-sm4096 0.436 -> 0.434, lowlight 0.461 -> 0.462; the shared cases unchanged.
  int vssm_h = 2;
  int vssm_leaf_taps = 4;   // shadows.vssm_leaf_taps: PCF taps per non-planar leaf (0: lit)
  double vssm_flat = 1e-4;  // shadows.vssm_flat: σ² below it·r is planar (§7.5.5)
  double vssm_contact = 0.01;  // shadows.vssm_contact: d − z_avg below it·r: PCF (§7.5.4)
  int vssm_narrow = 2;  // shadows.vssm_narrow: blocker searches narrowed to the blockers' cone
  // cssm (thesis ch. 5)
  int cssm_order = 8;                 // shadows.cssm_order: M, Fourier terms (eq. 5.2, 5.10)
  std::string cssm_filter = "sat";    // shadows.cssm_filter: sat | mipmap (§5.3.1)
  int cssm_max_basis = 1024;          // shadows.cssm_max_basis: basis images' largest side
  int cssm_split = 4;  // shadows.cssm_split: most sub-kernels a side (receiver depth per sub-kernel)
  int cssm_narrow = 2;  // shadows.cssm_narrow: blocker searches narrowed to the blockers' cone
  double cssm_a = 30.0, cssm_b = 100.0;  // shadows.cssm_sharpen_a/b: eq. 5.9
  // Camera (depth -> position; facing test): focal length in pixels, eye, world-to-camera
  // rotation. Without a camera, P is required and no facing test is made.
  bool has_camera = false;
  double f_px = 1.0;
  std::array<double, 3> eye{0, 0, 0};
  std::array<double, 9> rot{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Window window;  // a tile of a larger frame (principal point, hash origin)
};

// Why the shadow-map methods cannot run for this light ("" when they can).
std::string shadowmap_unsupported(const io::Light* light, const std::string& name);

// shadows.method = auto (issue 19): isg or pcss for one light, from the frame's pixels and the
// scene, and why. pcss is the better on the shared cases where the light stands well above the
// receivers near the world origin; isg holds everywhere measured, so it takes the scenes pcss
// cannot: no usable shadow map; a scene so far from the origin that float32 positions step by
// more than a shadow-map texel there; or light that grazes most receivers (the median angle of
// the light above the lit receivers under 14 degrees, where the map's texels stretch over the
// receivers and isg measured better); or penumbrae narrower than 3 map texels (their radius from
// L.occluder, median: issue 52, a sun's map over a whole scene), where the input's hard edge
// stands in pcss. Without a camera, which isg needs and pcss does not (given P), pcss.
struct ShadowAuto {
  std::string method, why;
};
ShadowAuto choose_shadow_method(const io::Image& img, const io::Roles& roles, const io::Light* light,
                                const std::string& name, const io::Camera* cam);

// From the light, the camera (may be null when P is given; any resolution: f_px is for
// `height` rows) and the preset.
ShadowmapSettings shadowmap_settings(const io::Light& light, const io::Camera* cam,
                                     double scene_radius, const params::Params& p,
                                     const std::string& method, int height);

// The map on the host: depths (row 0 at the top), size, nearest depth (1e30 if empty).
struct ShadowmapData {
  int width = 0, height = 0;
  std::vector<float> z;
  double min_depth = 1e30;
  uint64_t nonfinite = 0;  // NaN/Inf texels load_shadowmap repaired
  // The depths' own noise (world units), measured: the 90th percentile over the texels where
  // the depth changes of |Δ²(1/z)|·z²/√6 along rows and columns (the standard deviation of
  // independent per-texel noise; 0 on exact planes, 0.4 of the step on a plane rounded to float
  // steps). A renderer far from the world origin computes the map's depths in float and leaves
  // such steps (own contact-far1e5: 0.0032 m, contact-far1e6: 0.013 m; the same scene rendered
  // at the origin: 5e-7).
  double noise = 0;
};
// The map of `s.file`; texels beyond `s.far_clip` become background, as in a map the renderer
// clipped at its far plane (a backdrop 1e6 away must not set the SAT methods' depth range).
// NaN/Inf texels are repaired with their farthest finite neighbour (counted in `nonfinite`).
ShadowmapData load_shadowmap(const ShadowmapSettings& s);
// ortho_texel: a sun's orthographic map, its texel in world units (0: a perspective map).
ShadowmapData make_shadowmap(int width, int height, std::vector<float> z, double ortho_texel = 0.0);

}  // namespace isg::effects
