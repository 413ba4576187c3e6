#include "roofline/roofline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>
#include <stdexcept>

#include "effects/sampling.h"
#include "isg/shaders/roofline_gather.spv.h"
#include "roofline_gather_io.h"

namespace isg::roofline {

std::vector<int32_t> lattice_offsets(int taps, int radius) {
  const int grid = int(std::lround(std::sqrt(double(std::max(taps, 0)))));
  // An odd grid holds the centre, which keeps every pixel's weight sum at least 1.
  if (taps < 1 || grid * grid != taps || grid % 2 == 0) {
    throw std::invalid_argument("roofline: taps must be an odd square (9, 25, 49, 81, ...), got " +
                                std::to_string(taps));
  }
  if (radius < 0) throw std::invalid_argument("roofline: radius must be >= 0");
  std::vector<int32_t> o(2 * size_t(taps));
  for (int k = 0; k < taps; ++k) {
    auto c = effects::concentric(k, grid);
    o[2 * k] = int32_t(std::lround(c[0] * radius));
    o[2 * k + 1] = int32_t(std::lround(c[1] * radius));
  }
  return o;
}

std::vector<float> test_image(int w, int h) {
  std::vector<float> v(4 * size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float* t = &v[4 * (size_t(y) * w + x)];
      t[0] = float(0.5 + 0.5 * std::sin(0.11 * x + 0.07 * y));
      t[1] = float(0.5 + 0.5 * std::cos(0.05 * x - 0.13 * y));
      t[2] = float((x * 7 + y * 13) % 17) / 16.0f;
      // A gentle slope (weights just under 1) with 0.3-unit steps every 16 pixels (weights ~0).
      t[3] = float(1.0 + 0.002 * x + 0.001 * y + 0.3 * ((x / 16 + y / 16) % 3));
    }
  }
  return v;
}

std::vector<float> gather_reference(const std::vector<float>& src, int w, int h,
                                    const std::vector<int32_t>& offsets, float falloff) {
  std::vector<float> dst(src.size());
  const size_t taps = offsets.size() / 2;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const uint32_t r = effects::pixel_hash(uint32_t(x), uint32_t(y)) >> 29;
      const bool swap = r & 1u;
      const int sx = r & 2u ? -1 : 1, sy = r & 4u ? -1 : 1;
      const double z0 = src[4 * (size_t(y) * w + x) + 3];
      double acc[4] = {0, 0, 0, 0};
      for (size_t k = 0; k < taps; ++k) {
        int ox = offsets[2 * k], oy = offsets[2 * k + 1];
        if (swap) std::swap(ox, oy);
        const int qx = std::clamp(x + ox * sx, 0, w - 1), qy = std::clamp(y + oy * sy, 0, h - 1);
        const float* t = &src[4 * (size_t(qy) * w + qx)];
        const double d = double(t[3]) - z0;
        const double wt = std::exp(-d * d * double(falloff));
        for (int c = 0; c < 3; ++c) acc[c] += wt * double(t[c]);
        acc[3] += wt;
      }
      float* o = &dst[4 * (size_t(y) * w + x)];
      for (int c = 0; c < 3; ++c) o[c] = float(acc[c] / acc[3]);
      o[3] = float(acc[3]);
    }
  }
  return dst;
}

GatherPass::GatherPass(gpu::Context& ctx)
    : kernel_(ctx, "roofline_gather", isg_spv_roofline_gather,
              {gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::buffer},
              sizeof(shaders::RooflinePush), ROOFLINE_LOCAL_X, ROOFLINE_LOCAL_Y) {}

void GatherPass::record(gpu::Sequence& seq, const gpu::Buffer& offsets, const gpu::Buffer& src,
                        const gpu::Buffer& dst, uint32_t w, uint32_t h, uint32_t taps,
                        float falloff, const std::string& label) {
  shaders::RooflinePush pc{w, h, taps, falloff};
  seq.dispatch(kernel_,
               {gpu::Binding::texels(offsets, VK_FORMAT_R32G32_UINT), gpu::Binding::float4s(src),
                gpu::Binding::of(dst)},
               pc, w, h, label);
}

namespace {

// The device's image and output, and one timed dispatch at a time on them.
struct Bench {
  gpu::Context& ctx;
  int w, h;
  GatherPass pass;
  gpu::Buffer src, dst;
  // Positive sizes: check() or roofline_taps_per_second saw to it before the buffers.
  Bench(gpu::Context& c, int width, int height)
      : ctx(c),
        w(width),
        h(height),
        pass(c),
        src(c, 16 * VkDeviceSize(width) * VkDeviceSize(height), "roofline.src"),
        dst(c, 16 * VkDeviceSize(width) * VkDeviceSize(height), "roofline.dst") {
    auto img = test_image(w, h);
    src.upload(std::span<const float>(img));
  }
  // One submission per dispatch, so that without timestamps the submission's wall time is
  // still the dispatch's alone.
  double time_ms(const gpu::Buffer& offsets, int taps) {
    gpu::Sequence seq(ctx);
    pass.record(seq, offsets, src, dst, uint32_t(w), uint32_t(h), uint32_t(taps), kFalloff);
    auto t0 = std::chrono::steady_clock::now();
    auto passes = seq.submit();
    double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return ctx.timestamps() && !passes.empty() ? passes.front().ms : wall;
  }
};

gpu::Buffer upload_offsets(gpu::Context& ctx, const std::vector<int32_t>& o) {
  gpu::Buffer b(ctx, o.size() * sizeof(int32_t), "roofline.offsets");
  b.upload(std::span<const int32_t>(o));
  return b;
}

}  // namespace

void check(const Options& opt) {
  if (opt.width < 1 || opt.height < 1) throw std::invalid_argument("roofline: empty image");
  if (opt.repeats < 1) throw std::invalid_argument("roofline: repeats must be >= 1");
  for (int taps : opt.taps)
    for (int r : opt.radii) lattice_offsets(taps, r);
}

Report measure(gpu::Context& ctx, const Options& opt,
               const std::function<void(const Row&)>& progress) {
  // Before the device spends seconds on the first rows.
  check(opt);
  Bench b(ctx, opt.width, opt.height);
  Report rep{ctx.info().name, ctx.info().type_name, opt.width, opt.height,
             b.pass.local_x(), b.pass.local_y(), ctx.timestamps(), {}};
  for (int taps : opt.taps) {
    for (int radius : opt.radii) {
      auto offsets = upload_offsets(ctx, lattice_offsets(taps, radius));
      b.time_ms(offsets, taps);  // warm-up: first touch of the output, caches
      Row row{taps, radius, {}, 0, 0};
      for (int i = 0; i < opt.repeats; ++i) row.ms.push_back(b.time_ms(offsets, taps));
      row.best_ms = *std::min_element(row.ms.begin(), row.ms.end());
      row.taps_per_second = double(opt.width) * opt.height * taps / (row.best_ms * 1e-3);
      rep.rows.push_back(row);
      if (progress) progress(row);
    }
  }
  return rep;
}

double roofline_taps_per_second(gpu::Context& ctx, int w, int h) {
  constexpr int kTaps = 49, kRadius = 16;
  if (w < 1 || h < 1) throw std::invalid_argument("roofline: empty image");
  Bench b(ctx, w, h);
  auto offsets = upload_offsets(ctx, lattice_offsets(kTaps, kRadius));
  return double(w) * h * kTaps / (b.time_ms(offsets, kTaps) * 1e-3);
}

}  // namespace isg::roofline
