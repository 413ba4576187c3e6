// The roofline benchmark (issue 18): a plain cross-bilateral gather — per tap one 16-byte texel
// read through a texel view of a buffer (gpu.h's Slot::texels, as the passes read), one exp
// range weight — timed on the device in taps/s, the yardstick the isg gather passes are
// measured against. Not part of the effect pipeline. With the texel read from a storage buffer
// instead, lavapipe (Mesa 22.3) reached 41-44 M taps/s at 1920x1080, radii 4-64: llvmpipe loads
// a storage buffer one lane and one component at a time; through the texel view 240-370 M.
//
// Workgroup shapes tried on lavapipe (an earlier machine, storage-buffer reads; llvmpipe, LLVM 15,
// 256-bit; 2 cores shared with other builds, load 4-8, so best of 2 rounds of 8 dispatches,
// 960x540, 49 taps), M taps/s at radius
// 16 / 64: 8x8 187/122, 16x16 184/141, 32x1 136/119, 64x1 126/122, 8x4 152/110, 4x4 97/91,
// 16x4 130/113, 16x2 129/142, 32x2 139/125. On the quiet machine 8x8 gave 390 M taps/s at
// 1920x1080 (16x4 the same); the load, not the shape, moves the rest. 8x8 is kept
// (shaders/roofline_gather_io.h).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "gpu/gpu.h"

namespace isg::roofline {

// ---- the gather and its C++ double-precision reference ----

// A concentric-disk lattice of `taps` points (an odd square: 9, 25, 49, 81, ...) scaled by
// `radius` pixels and rounded: x0, y0, x1, y1, ... Throws std::invalid_argument otherwise.
std::vector<int32_t> lattice_offsets(int taps, int radius);

// A deterministic test image, w*h texels of rgb + depth (interleaved, 4 floats a texel), with
// depth edges so the range weight is neither all 1 nor all 0.
std::vector<float> test_image(int w, int h);

// The default range falloff 1/(2σ²), σ = 0.1 depth units.
inline constexpr float kFalloff = 50.0f;

// What the shader computes, in double: per pixel rgb = Σ w·rgb / Σ w, a = Σ w.
std::vector<float> gather_reference(const std::vector<float>& src, int w, int h,
                                    const std::vector<int32_t>& offsets, float falloff);

class GatherPass {
 public:
  explicit GatherPass(gpu::Context& ctx);
  // `offsets` from lattice_offsets; src and dst hold w*h vec4.
  void record(gpu::Sequence& seq, const gpu::Buffer& offsets, const gpu::Buffer& src,
              const gpu::Buffer& dst, uint32_t w, uint32_t h, uint32_t taps, float falloff,
              const std::string& label = "roofline_gather");
  uint32_t local_x() const { return kernel_.local_x(); }
  uint32_t local_y() const { return kernel_.local_y(); }

 private:
  gpu::Kernel kernel_;
};

// ---- the measurement ----

struct Options {
  int width = 1920, height = 1080;
  std::vector<int> taps{49, 81};
  std::vector<int> radii{4, 8, 16, 32, 64};
  int repeats = 3;  // timed dispatches after one warm-up; the best counts
};

struct Row {
  int taps = 0, radius = 0;
  std::vector<double> ms;  // GPU time of each timed dispatch
  double best_ms = 0;
  double taps_per_second = 0;  // width · height · taps / best
};

struct Report {
  std::string device, device_type;
  int width = 0, height = 0;
  uint32_t local_x = 0, local_y = 0;
  bool timestamps = true;  // false: wall time of each submission instead
  std::vector<Row> rows;
};

// Throws std::invalid_argument where `opt` cannot be measured (taps not an odd square, ...).
void check(const Options& opt);

// Every taps x radius of `opt`, in that order; `progress` (if set) sees each row as it lands.
Report measure(gpu::Context& ctx, const Options& opt,
               const std::function<void(const Row&)>& progress = {});

// One quick measurement (49 taps, radius 16, one timed dispatch and no warm-up) of
// a w x h image, for `isg run --timings` to set a frame's passes against: taps per second.
double roofline_taps_per_second(gpu::Context& ctx, int w, int h);

}  // namespace isg::roofline
