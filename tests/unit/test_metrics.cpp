#include <gtest/gtest.h>

#include <cmath>

#include "metrics/compare.h"

using isg::metrics::compare_planes;

TEST(Metrics, ClosedFormsForAConstantOffset) {
  const int w = 20, h = 10;
  std::vector<float> a(w * h, 0.25f), b(w * h, 0.75f);
  auto m = compare_planes(a, b, w, h, {}, "x");
  EXPECT_EQ(m.pixels, size_t(w * h));
  EXPECT_NEAR(m.rmse, 0.5, 1e-12);
  EXPECT_NEAR(m.mean_abs, 0.5, 1e-12);
  EXPECT_NEAR(m.max_abs, 0.5, 1e-12);
  EXPECT_NEAR(m.psnr, 10 * std::log10(1 / 0.25), 1e-9);
  // SSIM of two constants: luminance term only, (2ab + C1) / (a² + b² + C1).
  double C1 = 1e-4;
  EXPECT_NEAR(m.ssim, (2 * 0.25 * 0.75 + C1) / (0.0625 + 0.5625 + C1), 1e-9);
}

TEST(Metrics, IdenticalImagesAreExact) {
  const int w = 16, h = 16;
  std::vector<float> a(w * h);
  for (int i = 0; i < w * h; ++i) a[i] = float(std::sin(i * 0.37));
  auto m = compare_planes(a, a, w, h, {}, "x");
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_TRUE(std::isinf(m.psnr));
  EXPECT_NEAR(m.ssim, 1.0, 1e-12);
}

TEST(Metrics, MaskSelectsPixels) {
  const int w = 4, h = 1;
  std::vector<float> a = {0, 0, 0, 0}, b = {1, 1, 0.5f, 0.5f}, mask = {0, 0, 1, 1};
  auto m = compare_planes(a, b, w, h, mask, "x");
  EXPECT_EQ(m.pixels, 2u);
  EXPECT_NEAR(m.rmse, 0.5, 1e-12);
  EXPECT_NEAR(m.max_abs, 0.5, 1e-12);
}
