#include <gtest/gtest.h>

#include <random>

#include "effects/composite/composite.h"
#include "support/gpu_fixture.h"

using isg::test::GpuTest;
namespace gpu = isg::gpu;

namespace {
std::vector<float> random_planes(size_t n, int planes, unsigned seed, float lo, float hi) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> v(n * planes);
  for (float& x : v) x = u(rng);
  return v;
}
gpu::Buffer upload(gpu::Context& ctx, const std::vector<float>& v, const char* name) {
  gpu::Buffer b(ctx, v.size() * sizeof(float), name);
  b.upload(std::span<const float>(v));
  return b;
}
}  // namespace

TEST_F(GpuTest, ForegroundMatchesReference) {
  const uint32_t w = 33, h = 17;
  const size_t n = w * h;
  auto beauty = random_planes(n, 4, 1, 0.f, 1.f);
  std::vector<float> depth(n);
  for (size_t i = 0; i < n; ++i) {
    depth[i] = float(i % 5 == 0 ? 1e10 : i % 7 == 0 ? -1.0 : i % 11 == 0 ? 0.0 : 1.0 + i);
    if (i % 13 == 0) beauty[3 * n + i] = 0.0f;
  }
  auto bb = upload(ctx(), beauty, "composite"), db = upload(ctx(), depth, "depth");
  gpu::Buffer fg(ctx(), n * 4, "fg");
  isg::effects::ForegroundPass pass(ctx());
  for (int variant = 0; variant < 2; ++variant) {
    gpu::Sequence seq(ctx());
    pass.record(seq, bb, variant == 0, variant == 0 ? &db : nullptr, fg, w, h);
    seq.submit();
    auto want = isg::effects::foreground_reference(variant == 0 ? beauty.data() + 3 * n : nullptr,
                                                   variant == 0 ? depth.data() : nullptr, n);
    EXPECT_EQ(fg.download_as<float>(n), want) << "variant " << variant;
  }
}

// 45x23: a pixel a lane; 44x23 (a multiple of 4 pixels): four pixels a lane, through texel views
// of four pixels a texel.
TEST_F(GpuTest, CompositeTermMatchesDoubleReference) {
  for (const uint32_t w : {45u, 44u})
  for (int x_planes : {1, 3}) {
    const uint32_t h = 23;
    const size_t n = w * h;
    auto C = random_planes(n, 4, 2, 0.f, 2.f);
    auto W = random_planes(n, 3, 3, 0.f, 5.f);
    auto X = random_planes(n, x_planes, 4, 0.f, 1.f);
    auto Y = random_planes(n, x_planes, 5, 0.f, 1.f);
    std::vector<float> fg(n, 1.0f);
    for (size_t i = 0; i < n; i += 9) fg[i] = 0.0f;
    auto cb = upload(ctx(), C, "C"), wb = upload(ctx(), W, "W"), xb = upload(ctx(), X, "X"),
         yb = upload(ctx(), Y, "Y"), fb = upload(ctx(), fg, "fg");
    isg::effects::CompositeTermPass pass(ctx());
    gpu::Sequence seq(ctx());
    pass.record(seq, cb, wb, xb, yb, uint32_t(x_planes), fb, w, h, "composite");
    seq.submit();
    auto got = cb.download_as<float>(4 * n);
    auto want = C;
    isg::effects::composite_term_reference(want, W, X, Y, x_planes, fg, n);
    double worst = 0;
    for (size_t i = 0; i < 4 * n; ++i) worst = std::max(worst, double(std::abs(got[i] - want[i])));
    EXPECT_LT(worst, 1e-5) << w << "x" << h << ", x_planes " << x_planes;
    for (size_t i = 0; i < n; i += 9)  // background untouched, bit for bit
      for (int c = 0; c < 4; ++c) EXPECT_EQ(got[c * n + i], C[c * n + i]);
    for (size_t i = 0; i < n; ++i) EXPECT_EQ(got[3 * n + i], C[3 * n + i]);  // alpha kept
  }
}
