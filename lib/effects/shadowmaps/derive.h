// Pass shadows.derive: L.shadow and L.occluder from the light's shadow map, so that method isg
// (paper §3.1) runs on inputs that carry a shadow map but no occluder distances (issue 4). Its
// double-precision reference is shadowmap_derive_reference (shadowmap.h).
#pragma once

#include <cstdint>
#include <string>

#include "effects/shadowmaps/shadowmap.h"
#include "gpu/gpu.h"

namespace isg::effects {

class ShadowmapDerivePass {
 public:
  ShadowmapDerivePass(gpu::Context& ctx, const ShadowmapSettings& s, const ShadowmapData& map,
                      uint32_t w, uint32_t h, bool has_position);
  // geo: P or Z; map: the map's depths; shadow: L.shadow, written when `write_shadow` (else
  // the renderer's, kept); occluder: L.occluder, written.
  void record(gpu::Sequence& seq, const gpu::Buffer& geo, const gpu::Buffer& fg,
              const gpu::Buffer& map, const gpu::Buffer& shadow, bool write_shadow,
              const gpu::Buffer& occluder, const std::string& label);

 private:
  gpu::Kernel kernel_;
  gpu::Buffer params_;
  uint32_t w_, h_;
};

}  // namespace isg::effects
