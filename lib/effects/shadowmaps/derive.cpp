#include "effects/shadowmaps/derive.h"

#include "isg/shaders/shadowmap_derive.spv.h"
#include "shadowmap_derive_io.h"

namespace isg::effects {

ShadowmapDerivePass::ShadowmapDerivePass(gpu::Context& ctx, const ShadowmapSettings& s,
                                         const ShadowmapData& map, uint32_t w, uint32_t h,
                                         bool has_position)
    : kernel_(ctx, "shadows.derive", isg_spv_shadowmap_derive,
              {gpu::Slot::buffer, gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels,
               gpu::Slot::buffer, gpu::Slot::buffer},
              sizeof(shaders::ShadowmapDerivePush), SHADOWMAP_LOCAL, SHADOWMAP_LOCAL),
      w_(w),
      h_(h) {
  const shaders::ShadowmapParams p = shadowmap_params(s, map, w, h, has_position, 0);
  params_ = gpu::Buffer(ctx, sizeof(p), "shadows.derive.params");
  params_.upload(&p, sizeof(p));
}

void ShadowmapDerivePass::record(gpu::Sequence& seq, const gpu::Buffer& geo,
                                 const gpu::Buffer& fg, const gpu::Buffer& map,
                                 const gpu::Buffer& shadow, bool write_shadow,
                                 const gpu::Buffer& occluder, const std::string& label) {
  shaders::ShadowmapDerivePush pc{w_, h_, write_shadow ? 1u : 0u};
  seq.dispatch(kernel_,
               {gpu::Binding::of(params_), gpu::Binding::floats(geo), gpu::Binding::floats(fg),
                gpu::Binding::floats(map), gpu::Binding::of(shadow), gpu::Binding::of(occluder)},
               pc, w_, h_, label);
}

}  // namespace isg::effects
