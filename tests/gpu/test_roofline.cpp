#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <stdexcept>

#include "roofline/roofline.h"
#include "support/gpu_fixture.h"

using isg::test::GpuTest;
namespace gpu = isg::gpu;
namespace rl = isg::roofline;

TEST(Roofline, LatticeHoldsTheCentreAndStaysInTheRadius) {
  for (int taps : {9, 49, 81}) {
    for (int radius : {4, 16, 64}) {
      auto o = rl::lattice_offsets(taps, radius);
      ASSERT_EQ(o.size(), 2u * taps);
      bool centre = false;
      for (size_t k = 0; k < o.size(); k += 2) {
        centre = centre || (o[k] == 0 && o[k + 1] == 0);
        // Rounding may push a point half a pixel past the circle.
        EXPECT_LE(std::hypot(o[k], o[k + 1]), radius + 0.75) << taps << " taps, radius " << radius;
      }
      EXPECT_TRUE(centre) << taps << " taps";
    }
  }
  EXPECT_THROW(rl::lattice_offsets(48, 8), std::invalid_argument);
  EXPECT_THROW(rl::lattice_offsets(64, 8), std::invalid_argument);  // even grid: no centre
}

TEST_F(GpuTest, RooflineGatherMatchesDoubleReference) {
  const int w = 64, h = 48;
  const auto img = rl::test_image(w, h);
  gpu::Buffer src(ctx(), img.size() * sizeof(float), "src"), dst(ctx(), img.size() * sizeof(float), "dst");
  src.upload(std::span<const float>(img));
  rl::GatherPass pass(ctx());
  // Radius 64 reaches past every border of a 64x48 image: the clamping is exercised too.
  for (int taps : {49, 81}) {
    for (int radius : {0, 4, 16, 64}) {
      const auto o = rl::lattice_offsets(taps, radius);
      gpu::Buffer ob(ctx(), o.size() * sizeof(int32_t), "offsets");
      ob.upload(std::span<const int32_t>(o));
      gpu::Sequence seq(ctx());
      pass.record(seq, ob, src, dst, w, h, uint32_t(taps), rl::kFalloff);
      seq.submit();
      const auto got = dst.download_as<float>(img.size());
      const auto want = rl::gather_reference(img, w, h, o, rl::kFalloff);
      for (size_t i = 0; i < got.size(); ++i) {
        // rgb is a weighted mean of values in [0, 1]; the weight sum lies in [1, taps].
        const double tol = i % 4 == 3 ? 1e-5 * want[i] : 1e-5;
        const double err = std::abs(double(got[i]) - double(want[i]));
        ASSERT_LE(err, tol) << taps << " taps, radius " << radius << ", pixel " << i / 4
                            << " component " << i % 4 << ": " << got[i] << " vs " << want[i];
      }
      // The image's depth steps make some taps count and others not: a gather, not a box.
      double wmin = taps, wmax = 0;
      for (size_t i = 3; i < want.size(); i += 4) {
        wmin = std::min(wmin, double(want[i]));
        wmax = std::max(wmax, double(want[i]));
      }
      if (radius >= 4) {
        EXPECT_LT(wmin, 0.5 * wmax) << taps << " taps, radius " << radius;
      }
    }
  }
}

TEST_F(GpuTest, RooflineMeasuresEveryRow) {
  rl::Options opt;
  opt.width = 96;
  opt.height = 64;
  opt.taps = {9, 49};
  opt.radii = {4, 32};
  opt.repeats = 2;
  int seen = 0;
  auto rep = rl::measure(ctx(), opt, [&](const rl::Row&) { ++seen; });
  ASSERT_EQ(rep.rows.size(), 4u);
  EXPECT_EQ(seen, 4);
  EXPECT_FALSE(rep.device.empty());
  for (const auto& r : rep.rows) {
    EXPECT_EQ(r.ms.size(), 2u);
    EXPECT_GT(r.best_ms, 0.0);
    EXPECT_GT(r.taps_per_second, 0.0);
  }
  EXPECT_EQ(rep.rows[1].taps, 9);
  EXPECT_EQ(rep.rows[1].radius, 32);
  EXPECT_GT(rl::roofline_taps_per_second(ctx(), 96, 64), 0.0);
  opt.taps = {48};
  EXPECT_THROW(rl::measure(ctx(), opt), std::invalid_argument);
}
