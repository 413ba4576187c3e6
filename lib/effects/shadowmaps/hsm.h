// The min-max hierarchical shadow map (thesis §7.5.1, mipmap variant) that vssm and cssm test a
// kernel against before filtering it: level 0 is the map (depths clamped to far_z, its
// farthest surface, where the background stands), each level above the min and max of the up
// to 2x2 texels below. The GPU pass (shaders/shadowmap_hsm.comp) and its double mirror.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "effects/shadows/settings.h"
#include "gpu/gpu.h"
#include "shadowmap_hsm_io.h"

namespace isg::effects::detail {

struct HsmLevels {
  double far_z = 0;  // the map's farthest surface (float-rounded), where depths are clamped
  std::vector<int> w, h;
  std::vector<size_t> off;  // first texel of each level (level 0: the map)
  size_t texels = 0;
};
HsmLevels hsm_levels(const ShadowmapData& map);
// The shaders' table of the levels (level 0 the map itself, not stored: levels 1... from 0).
shaders::HsmLevelsGpu hsm_levels_gpu(const HsmLevels& v);

// The double mirror.
class HsmRef {
 public:
  HsmRef(const ShadowmapData& map, const HsmLevels& v);
  // Min and max depth over the texels [lo, hi) touches (sm_hsm_range).
  std::array<double, 2> range(std::array<double, 2> lo, std::array<double, 2> hi) const;

 private:
  const HsmLevels& v_;
  std::vector<std::array<float, 2>> t_;
};

// The GPU levels 1...: one dispatch each.
class HsmPass {
 public:
  HsmPass(gpu::Context& ctx, const HsmLevels& v);
  void record(gpu::Sequence& seq, const gpu::Buffer& map, const std::string& label);
  const gpu::Buffer& buffer() const { return hsm_; }

 private:
  HsmLevels v_;
  gpu::Kernel k_;
  gpu::Buffer hsm_;
};

}  // namespace isg::effects::detail
