// Depth of field (paper §3.3, eq. 15–17), applied last on the composite.
//   isg:     dof.coc → dof.tiles → dof.search (eq. 16) → dof.gather (eq. 17)
//   layered: dof.coc → dof.tiles → dof.layered (near and far fields, near composited over far)
// Each pass has a double-precision reference below, written from the same equations.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "effects/dof/settings.h"
#include "gpu/gpu.h"

namespace isg::effects {

// ---- C++ double-precision references (planes of w·h floats, RGBA = 4 planes) ----

// Eq. 15, clamped to ±max_coc; background (depth <= 0, >= 1e9, or alpha 0) gets c_inf.
std::vector<float> dof_coc_reference(const std::vector<float>& depth, const float* alpha,
                                     const DofSettings& s);
// Per 16×16 tile: min CoC, max CoC, max |CoC| reaching the tile, cheap flag (4 floats a tile).
std::vector<float> dof_tiles_reference(const std::vector<float>& coc, int w, int h,
                                       const DofSettings& s);
// The isg method: parameter search (eq. 16) then gather (eq. 17); returns RGBA.
std::vector<float> dof_isg_reference(const std::vector<float>& rgba, const std::vector<float>& coc,
                                     const std::vector<float>& tiles, int w, int h,
                                     const DofSettings& s);
// The layered method; returns RGBA.
std::vector<float> dof_layered_reference(const std::vector<float>& rgba,
                                         const std::vector<float>& coc,
                                         const std::vector<float>& tiles, int w, int h,
                                         const DofSettings& s);
// Fraction of tiles that took the cheap path.
double dof_cheap_fraction(const std::vector<float>& tiles);


// ---- GPU passes ----

class DofPass {
 public:
  DofPass(gpu::Context& ctx, const DofSettings& s);
  ~DofPass();
  // dof.coc: coc = eq. 15; input = a copy of the composite (the gathers read it).
  void record_coc(gpu::Sequence& seq, const gpu::Buffer& composite, bool has_alpha,
                  const gpu::Buffer& depth, const gpu::Buffer& coc, const gpu::Buffer& input,
                  uint32_t w, uint32_t h);
  void record_tiles(gpu::Sequence& seq, const gpu::Buffer& coc, const gpu::Buffer& tiles,
                    uint32_t w, uint32_t h);
  void record_search(gpu::Sequence& seq, const gpu::Buffer& coc, const gpu::Buffer& tiles,
                     const gpu::Buffer& radius, uint32_t w, uint32_t h);
  void record_gather(gpu::Sequence& seq, const gpu::Buffer& input, const gpu::Buffer& coc,
                     const gpu::Buffer& tiles, const gpu::Buffer& radius,
                     const gpu::Buffer& composite, uint32_t w, uint32_t h);
  void record_layered(gpu::Sequence& seq, const gpu::Buffer& input, const gpu::Buffer& coc,
                      const gpu::Buffer& tiles, const gpu::Buffer& composite, uint32_t w,
                      uint32_t h);
  // After submit: the fraction of tiles that took the cheap path.
  static double cheap_fraction(const gpu::Buffer& tiles, uint32_t w, uint32_t h);

 private:
  struct Kernels;
  // Specialization constant 0 of the passes that draw the aperture (shaders/dof_common.h).
  std::vector<uint32_t> blades() const { return {uint32_t(s_.blades)}; }
  gpu::Context& ctx_;
  DofSettings s_;
  std::unique_ptr<Kernels> k_;
};

}  // namespace isg::effects
