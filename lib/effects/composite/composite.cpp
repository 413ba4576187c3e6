#include "effects/composite/composite.h"

#include "composite_term_io.h"
#include "foreground_io.h"
#include "isg/shaders/composite_term.spv.h"
#include "isg/shaders/foreground.spv.h"

namespace isg::effects {

void composite_term_reference(std::vector<float>& C, const std::vector<float>& W,
                              const std::vector<float>& X, const std::vector<float>& Y,
                              int x_planes, const std::vector<float>& fg, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    if (fg[i] == 0.0f) continue;
    for (size_t c = 0; c < 3; ++c) {
      size_t xc = x_planes == 1 ? 0 : c;
      double d = double(X[xc * n + i]) - double(Y[xc * n + i]);
      C[c * n + i] = float(double(C[c * n + i]) + double(W[c * n + i]) * d);
    }
  }
}

ForegroundPass::ForegroundPass(gpu::Context& ctx)
    : kernel_(ctx, "foreground", isg_spv_foreground,
              {gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::buffer},
              sizeof(shaders::ForegroundPush), FOREGROUND_LOCAL, FOREGROUND_LOCAL) {}

void ForegroundPass::record(gpu::Sequence& seq, const gpu::Buffer& composite, bool has_alpha,
                            const gpu::Buffer* depth, const gpu::Buffer& fg, uint32_t w,
                            uint32_t h) {
  shaders::ForegroundPush pc{w, h, has_alpha ? 1u : 0u, depth ? 1u : 0u};
  // Without depth the slot is bound to the composite and never read.
  const gpu::Buffer& d = depth ? *depth : composite;
  seq.dispatch(kernel_,
               {gpu::Binding::floats(composite), gpu::Binding::floats(d), gpu::Binding::of(fg)}, pc,
               w, h, "foreground");
}

CompositeTermPass::CompositeTermPass(gpu::Context& ctx)
    : kernels_(ctx, "composite_term", isg_spv_composite_term,
              {gpu::Slot::buffer, gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels,
               gpu::Slot::texels},
              sizeof(shaders::CompositeTermPush),
              COMPOSITE_TERM_LOCAL, COMPOSITE_TERM_LOCAL) {}

void CompositeTermPass::record(gpu::Sequence& seq, const gpu::Buffer& C, const gpu::Buffer& W,
                               const gpu::Buffer& X, const gpu::Buffer& Y, uint32_t x_planes,
                               const gpu::Buffer& fg, uint32_t w, uint32_t h,
                               const std::string& label) {
  shaders::CompositeTermPush pc{w, h};
  // Four pixels a lane where the planes split into whole 16-byte texels (shaders/composite_term).
  const uint64_t n = uint64_t(w) * h;
  const uint32_t lane_pixels = n % 4 == 0 ? 4u : 1u;
  const uint64_t lanes = n / lane_pixels;
  auto view = [&](const gpu::Buffer& b) {
    return lane_pixels == 4 ? gpu::Binding::float4s(b) : gpu::Binding::floats(b);
  };
  seq.dispatch(kernels_.at({x_planes, lane_pixels}),
               {gpu::Binding::of(C), view(W), view(X), view(Y), view(fg)}, pc, COMPOSITE_TERM_ROW,
               uint32_t((lanes + COMPOSITE_TERM_ROW - 1) / COMPOSITE_TERM_ROW), label);
}

}  // namespace isg::effects
