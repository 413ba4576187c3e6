#include "effects/shadowmaps/sat.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "isg/shaders/sat_quantize.spv.h"
#include "isg/shaders/sat_scan.spv.h"
#include "isg/shaders/sat_scan32.spv.h"
#include "sat_io.h"

namespace isg::effects {

SatFixedPoint sat_fixed_point(const std::vector<float>& z, int power, double far_z,
                              double shift) {
  SatFixedPoint fp;
  fp.power = power;
  fp.far_z = far_z;
  fp.shift = double(float(shift));  // what the shader subtracts
  double sum = 0, lo = 1e300, hi = -1e300;
  for (float v : z) {
    double c = std::min(double(v), far_z) - fp.shift;
    double w = power == 2 ? c * c : c;
    sum += w;
    lo = std::min(lo, w);
    hi = std::max(hi, w);
  }
  fp.offset = z.empty() ? 0.0 : sum / double(z.size());
  // float(offset) is what the shader subtracts; leave room for its rounding and float's.
  const double dev = std::max({hi - fp.offset, fp.offset - lo, 1e-30});
  // A power of two: the shader's float copy of it is exact, so a texel's quantized value and the
  // sums the shaders rebuild from it are the reference's (VSSM's variance in double).
  fp.scale = std::ldexp(1.0, 30 - std::ilogb(dev * 1.001) - 1);
  return fp;
}

int64_t sat_quantize(float z, const SatFixedPoint& fp) {
  const float v = std::min(z, float(std::min(fp.far_z, 1e30))) - float(fp.shift);
  const float w = fp.power == 2 ? v * v : v;
  const float d = (w - float(fp.offset)) * float(fp.scale);
  return int64_t(std::floor(d + 0.5f));
}

double sat_rect_sum(const std::vector<int64_t>& sat, int w, int x0, int y0, int x1, int y1,
                    const SatFixedPoint& fp) {
  auto at = [&](int x, int y) -> int64_t {
    return (x <= 0 || y <= 0) ? 0 : sat[size_t(y - 1) * size_t(w) + size_t(x - 1)];
  };
  // Modular int64 arithmetic: exact whatever the intermediate overflow.
  const uint64_t s = uint64_t(at(x1, y1)) - uint64_t(at(x0, y1)) - uint64_t(at(x1, y0)) +
                     uint64_t(at(x0, y0));
  const double area = double(x1 - x0) * double(y1 - y0);
  return double(int64_t(s)) / fp.scale + area * double(float(fp.offset));
}

SatPass::SatPass(gpu::Context& ctx)
    : quantize_(ctx, "sat.quantize", isg_spv_sat_quantize, {gpu::Slot::buffer, gpu::Slot::buffer},
                sizeof(shaders::SatPush), SAT_LOCAL, 1),
      scan_(ctx, "sat.scan", isg_spv_sat_scan, {gpu::Slot::buffer}, sizeof(shaders::SatPush),
            SAT_LINES, 1) {}

void SatPass::record(gpu::Sequence& seq, const gpu::Buffer& map, const gpu::Buffer& sat,
                     uint32_t w, uint32_t h, const SatFixedPoint& fp, const std::string& label) {
  shaders::SatPush pc{w, h, 0u, uint32_t(fp.power), float(fp.offset), float(fp.scale),
                      float(std::min(fp.far_z, 1e30)), float(fp.shift), 1u, 0u};
  seq.dispatch(quantize_, {gpu::Binding::of(map), gpu::Binding::of(sat)}, pc, w, h,
               label + ".quantize");
  seq.dispatch(scan_, {gpu::Binding::of(sat)}, pc, h, 1, label + ".rows");  // a lane a line
  pc.axis = 1u;
  seq.dispatch(scan_, {gpu::Binding::of(sat)}, pc, w, 1, label + ".columns");
}

SatScan32::SatScan32(gpu::Context& ctx)
    : scan_(ctx, "sat.scan32", isg_spv_sat_scan32, {gpu::Slot::buffer}, sizeof(shaders::SatPush),
            SAT_LINES, 1) {}

void SatScan32::record(gpu::Sequence& seq, const gpu::Binding& sat, uint32_t w, uint32_t h,
                       uint32_t words, const std::string& label, bool rows) {
  shaders::SatPush pc{w, h, 0u, 1u, 0.0f, 1.0f, 1e30f, 0.0f, words, 0u};
  if (rows) seq.dispatch(scan_, {sat}, pc, h * words, 1, label + ".rows");
  pc.axis = 1u;
  seq.dispatch(scan_, {sat}, pc, w * words, 1, label + ".columns");
}

}  // namespace isg::effects
