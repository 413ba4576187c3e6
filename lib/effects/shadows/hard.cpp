#include "effects/shadows/hard.h"

#include "isg/shaders/shadows_hard.spv.h"
#include "shadows_hard_io.h"

namespace isg::effects {

std::vector<float> shadows_hard_reference(const std::vector<float>& shadow) { return shadow; }

ShadowsHardPass::ShadowsHardPass(gpu::Context& ctx)
    : kernel_(ctx, "shadows.hard", isg_spv_shadows_hard, {gpu::Slot::buffer, gpu::Slot::buffer},
              sizeof(shaders::ShadowsHardPush), SHADOWS_HARD_LOCAL, SHADOWS_HARD_LOCAL) {}

void ShadowsHardPass::record(gpu::Sequence& seq, const gpu::Buffer& shadow,
                             const gpu::Buffer& soft, uint32_t w, uint32_t h,
                             const std::string& label) {
  shaders::ShadowsHardPush pc{w, h};
  seq.dispatch(kernel_, {gpu::Binding::of(shadow), gpu::Binding::of(soft)}, pc, w, h, label);
}

}  // namespace isg::effects
