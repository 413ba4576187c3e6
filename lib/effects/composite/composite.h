// The contract's composite (AOV_CONTRACT.md "Output"):
//   C = beauty + Σ_L L.direct·(L.softshadow − L.shadow) + refl.weight·(refl.glossy − refl)
// as one term pass applied per effect that ran, after the foreground classification.
#pragma once

#include <cstddef>
#include <vector>

#include "effects/composite/effect.h"
#include "gpu/gpu.h"

namespace isg::effects {

// ---- C++ double-precision references ----

// foreground_reference: effects/composite/effect.h (the planner side uses it too).

// C (4 planes) += W (3 planes) · (X − Y) on foreground pixels; X, Y have x_planes (1 or 3).
void composite_term_reference(std::vector<float>& C, const std::vector<float>& W,
                              const std::vector<float>& X, const std::vector<float>& Y,
                              int x_planes, const std::vector<float>& fg, size_t n);

// ---- GPU passes ----

class ForegroundPass {
 public:
  explicit ForegroundPass(gpu::Context& ctx);
  // `composite` holds the beauty (A at plane 3 when has_alpha); depth may be null.
  void record(gpu::Sequence& seq, const gpu::Buffer& composite, bool has_alpha,
              const gpu::Buffer* depth, const gpu::Buffer& fg, uint32_t w, uint32_t h);

 private:
  gpu::Kernel kernel_;
};

class CompositeTermPass {
 public:
  explicit CompositeTermPass(gpu::Context& ctx);
  void record(gpu::Sequence& seq, const gpu::Buffer& C, const gpu::Buffer& W, const gpu::Buffer& X,
              const gpu::Buffer& Y, uint32_t x_planes, const gpu::Buffer& fg, uint32_t w,
              uint32_t h, const std::string& label);

 private:
  gpu::KernelVariants kernels_;  // specialised on x_planes and the pixels a lane
};

}  // namespace isg::effects
