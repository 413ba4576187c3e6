// Min-max hierarchical shadow map (thesis §7.5.1, mipmap variant), shared by VSSM (its
// blocker and shadow verdicts) and CSSM (its fully lit / umbra test): the GPU pass that builds
// it (shaders/shadowmap_hsm.comp), its layout (shaders/shadowmap_hsm_io.h) and the double
// mirror of its range query (shaders/shadowmap_hsm.h).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "effects/shadows/settings.h"
#include "gpu/gpu.h"
#include "shadowmap_hsm_io.h"

namespace isg::effects {

// Levels of a w x h map, level 0 the map itself (at most HSM_MAX_LEVELS).
struct HsmLayout {
  double far_z = 1e30;  // depths clamped to it (in float, as the GPU reads them)
  std::vector<int> w, h;
  std::vector<size_t> off;  // level k's first texel, counting level 0's
  size_t texels = 0;        // all levels, level 0 included
  // Levels 1... as the GPU stores them (from offset 0 of their buffer), for a pass's params.
  shaders::HsmLevels gpu() const;
  size_t stored_texels() const { return texels - (off.size() > 1 ? off[1] : texels); }
};
HsmLayout hsm_layout(int w, int h, double far_z);

// The double mirror: every level, level 0 included, from the map's floats.
class HsmRef {
 public:
  HsmRef(const ShadowmapData& map, const HsmLayout& layout);
  // Min and max depth over the texels the rectangle [lo, hi) (map texels) touches
  // (shaders/shadowmap_hsm.h's hsm_range).
  std::array<double, 2> range(std::array<double, 2> lo, std::array<double, 2> hi) const;

 private:
  HsmLayout l_;
  std::vector<std::array<float, 2>> t_;
};

class HsmPass {
 public:
  explicit HsmPass(gpu::Context& ctx);
  // Records levels 1... into `hsm` (layout.stored_texels() · 8 bytes) from `map`, a dispatch
  // each, labelled label + ".hsm<k>".
  void record(gpu::Sequence& seq, const gpu::Buffer& map, const gpu::Buffer& hsm,
              const HsmLayout& layout, const std::string& label);

 private:
  gpu::Kernel k_;
};

}  // namespace isg::effects
