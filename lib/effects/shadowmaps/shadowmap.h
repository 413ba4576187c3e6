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
#include "effects/shadows/settings.h"
#include "effects/view.h"
#include "io/scene.h"
#include "params/params.h"
#include "shadowmap_io.h"

namespace isg::effects {
namespace detail {
class ShadowmapMethod;
}

// `n` points in the unit disk, x y interleaved: pattern "stratified" (a square grid of
// round(sqrt(n))² cells through the concentric map, so n is rounded) or "poisson" (dart
// throwing, fixed seed).
std::vector<float> shadowmap_taps(int n, const std::string& pattern);

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
// passes (lib/effects/shadowmaps/vssm.cpp, cssm.cpp).
std::vector<float> vssm_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                  const ShadowmapSettings& s, ShadowmapStats* stats = nullptr);
std::vector<float> cssm_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                  const ShadowmapSettings& s, ShadowmapStats* stats = nullptr);

// The parameters every shadowmap_* pass reads (shaders/shadowmap_io.h); `taps`: tap count.
// The map's own precision in world units (SHADOWMAP_NOISE_EPS times its measured depth noise),
// added to every receiver's depth uncertainty with the receiver's own input step (Geom).
double depth_eps(const ShadowmapData& map);
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
