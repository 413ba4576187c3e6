// GPU summed-area tables (thesis §7: the SATs of z and z² behind VSSM's filtering) in 64-bit
// fixed point: parallel prefix sums over rows, then columns, of integers with the mean
// subtracted, so that any rectangle sum, up to the whole map, is exact in the integers and
// off from the double sum by at most area · 0.5 / scale.
#pragma once

#include <cstdint>
#include <vector>

#include "gpu/gpu.h"

namespace isg::effects {

struct SatFixedPoint {
  int power = 1;         // 1: z, 2: z²
  double offset = 0.0;   // subtracted before scaling (the mean of min(z, far)^power)
  double scale = 1.0;    // integer units per unit of value
  double far_z = 1e30;   // depths are clamped to it first (no-hit texels)
  double shift = 0.0;    // then shifted: (min(z, far) − shift)^power (z² about the mean: VSSM)
};

// Offset and scale for a w x h map: the mean, and the largest |deviation| mapped to 2^30.
SatFixedPoint sat_fixed_point(const std::vector<float>& z, int power, double far_z,
                              double shift = 0.0);

// One texel's integer as shaders/sat_quantize.comp makes it, in the same float arithmetic (its
// parameters as the float push constants carry them): (min(z, far) − shift)^power, less the
// offset, times the scale, rounded.
int64_t sat_quantize(float z, const SatFixedPoint& fp);

// Rectangle sum [x0, x1) x [y0, y1) of a table of int64 (row-major, inclusive prefix sums), in
// value units (offset added back).
double sat_rect_sum(const std::vector<int64_t>& sat, int w, int x0, int y0, int x1, int y1,
                    const SatFixedPoint& fp);

// In-place SATs of 32-bit integers in wrapping arithmetic (shaders/sat_scan32.comp): w x h
// entries of `words` interleaved uints (CSSM's basis images, shadowmap_cssm_io.h).
class SatScan32 {
 public:
  explicit SatScan32(gpu::Context& ctx);
  // rows = false: the columns only (rows already summed, e.g. by cssm's basis pass).
  void record(gpu::Sequence& seq, const gpu::Binding& sat, uint32_t w, uint32_t h, uint32_t words,
              const std::string& label, bool rows = true);

 private:
  gpu::Kernel scan_;
};

class SatPass {
 public:
  explicit SatPass(gpu::Context& ctx);
  // Records quantize, row scan and column scan: `sat` (w·h·8 bytes) from `map` (w·h floats).
  void record(gpu::Sequence& seq, const gpu::Buffer& map, const gpu::Buffer& sat, uint32_t w,
              uint32_t h, const SatFixedPoint& fp, const std::string& label);

 private:
  gpu::Kernel quantize_, scan_;
};

}  // namespace isg::effects
