// Soft shadows from the light's shadow map (contract input 2): shadows.method = pcss (thesis
// §2.4.2). What every shadow-map method shares: the light's projection, the receiver-plane
// depth bias, the tap patterns, the host-side map, and the settings the planner resolves.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "gpu/gpu.h"
#include "effects/view.h"
#include "io/scene.h"
#include "params/params.h"
#include "shadowmap_io.h"

namespace isg::effects {
namespace detail {
class ShadowmapMethod;
}

struct ShadowmapSettings {
  std::string method = "pcss";
  std::filesystem::path file;             // the map's EXR (channel Z)
  io::Mat4 world_to_light = io::identity4();
  double yfov_deg = 90.0;
  double far_clip = 1e30;                 // the map's far plane: depths beyond it are background
  double light_radius = 0.0;              // world units (light_size() of the light)
  int taps = 32;                          // shadows.pcss_taps
  std::string pattern = "stratified";     // shadows.pcss_pattern: stratified | poisson
  bool rotate = true;                     // shadows.rotate
  double bias = 2.0;                      // shadows.bias, receiver texel footprints
  double slope_max = 4.0;                 // shadows.slope_max
  double spread_bias = 2.0;               // shadows.spread_bias
  double depth_ulps = 1.0;                // shadows.depth_ulps
  double max_radius = 64.0;               // shadows.smap_max_radius, texels
  double scene_radius = 1.0;              // the scene file's scene_radius (r of §7.5.4-7.5.5)
  // vssm (thesis ch. 7)
  int vssm_m = 5;           // shadows.vssm_m: m×m uniform sub-kernels, blocker search (§7.4.2)
  int vssm_h = 3;           // shadows.vssm_h: quad-tree height H, shadow (Algorithm 3)
  int vssm_leaf_taps = 4;   // shadows.vssm_leaf_taps: PCF taps per non-planar leaf (0: lit)
  double vssm_flat = 1e-4;  // shadows.vssm_flat: σ² below it·r is planar (§7.5.5)
  double vssm_contact = 0.01;  // shadows.vssm_contact: d − z_avg below it·r: PCF (§7.5.4)
  // cssm (thesis ch. 5)
  int cssm_order = 8;                 // shadows.cssm_order: M, Fourier terms (eq. 5.2, 5.10)
  std::string cssm_filter = "sat";    // shadows.cssm_filter: sat | mipmap (§5.3.1)
  int cssm_max_basis = 1024;          // shadows.cssm_max_basis: basis images' largest side
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

// From the light, the camera (may be null when P is given; any resolution: f_px is for
// `height` rows) and the preset.
ShadowmapSettings shadowmap_settings(const io::Light& light, const io::Camera* cam,
                                     double scene_radius, const params::Params& p,
                                     const std::string& method, int height);

// `n` points in the unit disk, x y interleaved: pattern "stratified" (a square grid of
// round(sqrt(n))² cells through the concentric map, so n is rounded) or "poisson" (dart
// throwing, fixed seed).
std::vector<float> shadowmap_taps(int n, const std::string& pattern);

// The map on the host: depths (row 0 at the top), size, nearest depth (1e30 if empty).
struct ShadowmapData {
  int width = 0, height = 0;
  std::vector<float> z;
  double min_depth = 1e30;
  uint64_t nonfinite = 0;  // NaN/Inf texels load_shadowmap repaired
};
// The map of `s.file`; texels beyond `s.far_clip` become background, as in a map the renderer
// clipped at its far plane (a backdrop 1e6 away must not set the SAT methods' depth range).
// NaN/Inf texels are repaired with their farthest finite neighbour (counted in `nonfinite`).
ShadowmapData load_shadowmap(const ShadowmapSettings& s);
ShadowmapData make_shadowmap(int width, int height, std::vector<float> z);

// The per-pixel inputs: position (3 planes) or depth; fg; the hard shadow kept outside the
// map and on the background.
struct ShadowmapInputs {
  int w = 0, h = 0;
  std::vector<float> position, depth, fg, hard;
};

struct ShadowmapStats {
  uint64_t pixels = 0, skipped = 0, clamped = 0, contact = 0;
  double skipped_fraction() const { return pixels ? double(skipped) / double(pixels) : 0.0; }
};

// Double-precision PCSS, the same taps and decisions as the GPU pass.
std::vector<float> pcss_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                  const ShadowmapSettings& s, ShadowmapStats* stats = nullptr);

// Double-precision VSSM (thesis ch. 7) and CSSM (ch. 5), the same decisions as their GPU
// passes (lib/effects/shadows/vssm.cpp, cssm.cpp).
std::vector<float> vssm_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                  const ShadowmapSettings& s, ShadowmapStats* stats = nullptr);
std::vector<float> cssm_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                  const ShadowmapSettings& s, ShadowmapStats* stats = nullptr);

// The parameters every shadowmap_* pass reads (shaders/shadowmap_io.h); `taps`: tap count.
// The map's own precision in world units (shadows.depth_ulps float32 steps at the light's
// distance from the world origin), added to every receiver's depth uncertainty.
double depth_eps(const ShadowmapSettings& s);
shaders::ShadowmapParams shadowmap_params(const ShadowmapSettings& s, const ShadowmapData& map,
                                          uint32_t w, uint32_t h, bool has_position,
                                          uint32_t taps);

// Pass shadows.derive (shaders/shadowmap_derive.comp), double precision: L.shadow (the hard
// test at the receiver's texel, the filtering passes' bias) and L.occluder (distance from P to
// the nearest blocker among the 3×3 texels around, along the ray to the light's centre) from
// the shadow map, for method isg when the renderer wrote no occluder distances.
struct DerivedShadow {
  std::vector<float> shadow, occluder;
};
DerivedShadow shadowmap_derive_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                         const ShadowmapSettings& s);


// The GPU pass of one light: owns its kernel, parameters, taps and counters; the map is the
// plan's resource L.shadowmap (filled by the caller with ShadowmapData::z).
class ShadowmapPass {
 public:
  ShadowmapPass(gpu::Context& ctx, const ShadowmapSettings& s, const ShadowmapData& map,
                uint32_t w, uint32_t h, bool has_position);
  ~ShadowmapPass();
  void record(gpu::Sequence& seq, const gpu::Buffer& geo, const gpu::Buffer& fg,
              const gpu::Buffer& hard, const gpu::Buffer& map, const gpu::Buffer& soft,
              const std::string& label);
  ShadowmapStats stats() const;  // after the sequence ran
  uint64_t gpu_bytes() const;      // the method's own buffers (SATs, basis images, HSM, ...)

 private:
  std::unique_ptr<detail::ShadowmapMethod> method_;
};

}  // namespace isg::effects
