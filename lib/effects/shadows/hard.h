// Soft-shadow method `hard`: the placeholder that keeps the renderer's hard shadow
// (L.softshadow = L.shadow), so the whole pipeline runs before the soft methods exist.
#pragma once

#include <vector>

#include "gpu/gpu.h"

namespace isg::effects {

std::vector<float> shadows_hard_reference(const std::vector<float>& shadow);

class ShadowsHardPass {
 public:
  explicit ShadowsHardPass(gpu::Context& ctx);
  void record(gpu::Sequence& seq, const gpu::Buffer& shadow, const gpu::Buffer& soft, uint32_t w,
              uint32_t h, const std::string& label);

 private:
  gpu::Kernel kernel_;
};

}  // namespace isg::effects
