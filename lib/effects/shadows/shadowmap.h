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
#include "io/scene.h"
#include "params/params.h"
#include "shadowmap_io.h"

namespace isg::effects {

struct ShadowmapSettings {
  std::string method = "pcss";
  std::filesystem::path file;             // the map's EXR (channel Z)
  io::Mat4 world_to_light = io::identity4();
  double yfov_deg = 90.0;
  double light_radius = 0.0;              // world units (light_size() of the light)
  int taps = 32;                          // shadows.pcss_taps
  std::string pattern = "stratified";     // shadows.pcss_pattern: stratified | poisson
  bool rotate = true;                     // shadows.rotate
  double bias = 2.0;                      // shadows.bias, receiver texel footprints
  double slope_max = 4.0;                 // shadows.slope_max
  double spread_bias = 2.0;               // shadows.spread_bias
  double max_radius = 64.0;               // shadows.smap_max_radius, texels
  // Camera (depth -> position; facing test): focal length in pixels, eye, world-to-camera
  // rotation. Without a camera, P is required and no facing test is made.
  bool has_camera = false;
  double f_px = 1.0;
  std::array<double, 3> eye{0, 0, 0};
  std::array<double, 9> rot{1, 0, 0, 0, 1, 0, 0, 0, 1};
};

// Why the shadow-map methods cannot run for this light ("" when they can).
std::string shadowmap_unsupported(const io::Light* light, const std::string& name);

// From the light, the camera (may be null when P is given; any resolution: f_px is for
// `height` rows) and the preset.
ShadowmapSettings shadowmap_settings(const io::Light& light, const io::Camera* cam,
                                     const params::Params& p, const std::string& method,
                                     int height);

// `n` points in the unit disk, x y interleaved: pattern "stratified" (a square grid of
// round(sqrt(n))² cells through the concentric map, so n is rounded) or "poisson" (dart
// throwing, fixed seed).
std::vector<float> shadowmap_taps(int n, const std::string& pattern);

// The map on the host: depths (row 0 at the top), size, nearest depth (1e30 if empty).
struct ShadowmapData {
  int width = 0, height = 0;
  std::vector<float> z;
  double min_depth = 1e30;
};
ShadowmapData load_shadowmap(const std::filesystem::path& file);
ShadowmapData make_shadowmap(int width, int height, std::vector<float> z);

// The per-pixel inputs: position (3 planes) or depth; fg; the hard shadow kept outside the
// map and on the background.
struct ShadowmapInputs {
  int w = 0, h = 0;
  std::vector<float> position, depth, fg, hard;
};

struct ShadowmapStats {
  uint64_t pixels = 0, skipped = 0, clamped = 0;
  double skipped_fraction() const { return pixels ? double(skipped) / double(pixels) : 0.0; }
};

// Double-precision PCSS, the same taps and decisions as the GPU pass.
std::vector<float> pcss_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                  const ShadowmapSettings& s, ShadowmapStats* stats = nullptr);

// The parameters every shadowmap_* pass reads (shaders/shadowmap_io.h); `taps`: tap count.
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

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace isg::effects
