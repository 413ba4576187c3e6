// Soft-shadow method `isg` (paper §3.1, eq. 4-9): L.softshadow from the renderer's hard shadow
// L.shadow, the occluder distance L.occluder, P (or Z and the camera) and the light.
//   shadows.isg.tiles: per 16×16 tile, lit/shadowed foreground flags and the image's largest
//                      occluder distance d_max;
//   shadows.isg:       per pixel, the parameter search over occluder distances within R_p (eq.
//                      5-7; R_p covers the widest penumbra the occluders of the tiles around can
//                      cast, so lit pixels next to a shadow find it), then the gather over the
//                      shadow bits within R_g (eq. 8-9), both with the consistent estimator eq.
//                      4 (centre tap included); tiles with no shadow boundary within reach copy
//                      L.shadow.
// World radii become pixels through the camera at the receiver's depth (Camera::pixel_size_at),
// widened by 1 / cos θ_i (the receiver's normal from P's screen derivatives) since the penumbra
// lies stretched on a receiver inclined to the light; the gather keeps only points within R_s
// of p_0 in the penumbra's cross-section, so grazing receivers do not blur along the surface.
// The composite term L.direct·(L.softshadow − L.shadow) is the shared composite_term pass.
#pragma once

#include <map>
#include <memory>
#include <utility>

#include <cstdint>
#include <string>
#include <vector>

#include "effects/shadows/settings.h"
#include "gpu/gpu.h"

namespace isg::effects {

// The inputs, as planes of w·h floats (position: 3 planes, or depth: 1 plane; fg: 1
// foreground, 0 background).
struct ShadowInputs {
  int w = 0, h = 0;
  std::vector<float> shadow, occluder, position, depth, fg;
};

struct ShadowIsgStats {
  double skipped_fraction = 0;  // tiles that took the cheap path
  // Tiles shadows.isg was dispatched on (shadows.isg.list): at least those that did not take the
  // cheap path. GPU only (the reference decides per tile).
  double dispatched_fraction = 0;
  uint64_t full_pixels = 0;     // pixels that ran the search and gather
  uint64_t searches = 0;        // parameter searches (one per 2x2 quad, more at edges)
  uint64_t gathers = 0;         // gathers (one per quad for wide penumbrae, more at edges)
  uint64_t clamped_pixels = 0;  // pixels whose search or gather radius exceeded max_radius
  uint64_t borrowed = 0;        // pixels that took the quads' around occluder distance (their
                                // quad's search found none: SHADOWS_ISG_BORROW_MIN)
  double d_max = 0;             // the largest occluder distance
};

// C++ double-precision reference of passes shadows.isg.tiles and shadows.isg (same sample
// pattern, same rotation hash); returns L.softshadow.
std::vector<float> shadows_isg_reference(const ShadowInputs& in, const ShadowSettings& s,
                                         ShadowIsgStats* stats = nullptr);

class ShadowsIsgPass {
 public:
  // part_lanes: the lanes that take one search or gather sum of shadows.isg.quads and .own (a
  // power of two up to the subgroup size, shaders/shadows_isg.h; any two agree within float
  // rounding); 0: by the device, 1 on a CPU implementation (lavapipe), SHADOWS_ISG_PART_LANES (or
  // the subgroup size, if smaller) on a GPU.
  explicit ShadowsIsgPass(gpu::Context& ctx, uint32_t part_lanes = 0);
  ~ShadowsIsgPass();
  // geo: P (has_position) or Z. `tiles` holds shadows_isg_tiles_words(w, h) words; it is
  // cleared here (a host upload, before the sequence runs). `pack` (4 planes) receives the
  // taps' texels from shadows.isg.tiles.
  void record(gpu::Sequence& seq, const ShadowSettings& s, const gpu::Buffer& shadow,
              const gpu::Buffer& occluder, const gpu::Buffer& geo, bool has_position,
              const gpu::Buffer& fg, gpu::Buffer& tiles, const gpu::Buffer& pack,
              const gpu::Buffer& soft, uint32_t w, uint32_t h, const std::string& label);
  // After submit.
  static ShadowIsgStats stats(const gpu::Buffer& tiles, uint32_t w, uint32_t h);

 private:
  const gpu::Buffer& samples(int grid_search, int grid_gather);
  gpu::Context& ctx_;
  gpu::KernelVariants tiles_kernel_;  // specialised on SHADOWS_ISG_HAS_POSITION
  gpu::Kernel list_kernel_;
  // shadows.isg's four dispatches (.reach, .quads, the pixels', .own), specialised on the
  // SHADOWS_ISG_* settings.
  gpu::KernelVariants reach_kernel_, quads_kernel_, kernel_, own_kernel_;
  uint32_t part_lanes_;  // specialization constant 1 of .quads and .own
  std::map<std::pair<int, int>, std::unique_ptr<gpu::Buffer>> samples_;
};

}  // namespace isg::effects
