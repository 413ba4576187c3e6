// Convolution soft shadow maps (shadows.method = cssm, thesis ch. 5): GPU against the double
// reference, the parallel-planes case against its closed form, and the shared case `contact`.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "effects/params.h"
#include "effects/shadowmaps/shadowmap.h"
#include "io/image.h"
#include "run/job.h"
#include "support/gpu_fixture.h"
#include "support/images.h"
#include "support/shadow_planes.h"
#include "support/synth_case.h"

using isg::test::GpuTest;
namespace fx = isg::effects;

namespace {
class CssmGpu : public GpuTest {};
using isg::test::mismatches;
using isg::test::Planes;
using isg::test::planes_rmse;
using isg::test::run_gpu;

fx::ShadowmapSettings cssm_settings(const Planes& pl, int order, const char* filter) {
  auto s = pl.settings(16, "stratified", "cssm");
  s.cssm_order = order;
  s.cssm_filter = filter;
  return s;
}
}  // namespace

TEST_F(CssmGpu, MatchesDoubleReference) {
  for (double slope : {0.0, 1.5}) {
    for (const char* filter : {"sat", "mipmap"}) {
      for (int order : {4, 8, 16}) {
        Planes pl;
        pl.slope = slope;
        pl.far = 8.0;  // the sloped receiver ends there: the depth range CSSM normalises over
        pl.w = pl.h = 48;
        pl.map = 128;
        auto map = pl.shadowmap();
        auto in = pl.inputs();
        in.fg[5] = 0.0f;  // background keeps the hard shadow (marked)
        in.hard[5] = 0.5f;
        const auto s = cssm_settings(pl, order, filter);
        fx::ShadowmapStats sr, sg;
        const auto want = fx::cssm_reference(in, map, s, &sr);
        const auto got = run_gpu(ctx(), in, map, s, &sg);
        double md;
        const size_t bad = mismatches(got, want, &md);
        std::printf("cssm slope %.1f %s M=%d: %zu of %zu pixels differ by more than 1e-3 "
                    "(max %.4f); %.1f%% skipped, %llu clamped\n",
                    slope, filter, order, bad, want.size(), md, 100 * sr.skipped_fraction(),
                    static_cast<unsigned long long>(sr.clamped));
        EXPECT_EQ(got[5], 0.5f);
        EXPECT_LE(bad, want.size() / 100) << slope << " " << filter << " " << order;
        EXPECT_EQ(sg.pixels, sr.pixels);
        EXPECT_NEAR(double(sg.skipped), double(sr.skipped), 0.005 * double(sr.pixels));
        EXPECT_NEAR(double(sg.clamped), double(sr.clamped), 0.005 * double(sr.pixels));
        if (slope > 0) {  // the sloped receiver is split into sub-kernels (shadows.cssm_split)
          auto s1 = s;
          s1.cssm_split = 1;
          double d1;
          const size_t split = mismatches(fx::cssm_reference(in, map, s1, nullptr), want, &d1);
          std::printf("  %zu pixels change with one receiver depth a kernel (max %.4f)\n", split, d1);
          EXPECT_GT(split, want.size() / 10) << "no pixel split its kernel: " << filter << " " << order;
        }
      }
    }
  }
}

TEST_F(CssmGpu, ParallelPlanesMatchesClosedForm) {
  Planes pl;
  const auto map = pl.shadowmap();
  const auto in = pl.inputs();
  struct Case {
    const char* filter;
    int order;
    double bound;
  };
  // Measured (lavapipe): sat 0.0210 / 0.0307 / 0.0106, mipmap 0.0234 / 0.0337 / 0.0104 for
  // M = 4 / 8 / 16 (box kernels and ringing suppression narrow the penumbra a little; M = 8's
  // shifted step x0 sits less well against the two plane depths than 4's or 16's).
  for (const Case& c : {Case{"sat", 4, 0.028}, Case{"sat", 8, 0.040}, Case{"sat", 16, 0.014},
                        Case{"mipmap", 4, 0.031}, Case{"mipmap", 8, 0.044},
                        Case{"mipmap", 16, 0.014}}) {
    auto s = cssm_settings(pl, c.order, c.filter);
    // The thesis's filter against the closed form: with shadows.input_edges (its 10 % of the hard
    // verdict in this 6-texel penumbra) 0.0140 -> 0.0165 at the tightest bound.
    s.input_edges = 0.0;
    fx::ShadowmapStats st;
    const auto got = run_gpu(ctx(), in, map, s, &st);
    const double e = planes_rmse(pl, in, got);
    std::printf("parallel planes, cssm %s M=%d: RMSE %.4f, %.1f%% skipped\n", c.filter, c.order,
                e, 100 * st.skipped_fraction());
    EXPECT_LT(e, c.bound) << c.filter << " " << c.order;
  }
}

// A blocker nearer its receiver than x0 / s_z of the map's depth range (here 0.3 m of 36 m: a
// backdrop patch in a corner of the map, out of every kernel's reach, stretches the range) shadows
// it by under half in the expansion: its penumbra (3.9 pixels, 2.6 map texels a side) is wider
// than shadows.input_edges' 2 texels but narrower than the 15 texels a blocker x0 / s_z in front
// casts, so the input's edge stands there (Shaded::r_min, issue 19). The GPU follows the
// reference, and the result is no worse than the input's hard edge. Measured against the closed
// form: 0.0725, the hard input's own; the expansion alone 0.1987 with the SAT's fractional boxes,
// 0.0512 with the boxes snapped to whole texels (issue 51: the patch's 4 texels then fall
// wholly in or out of a box instead of leaking a fraction into every one); with input_edges' 2
// texels as the only floor (before r_min) 0.1032, worse than doing nothing.
TEST_F(CssmGpu, BlockersTheExpansionCannotResolveKeepTheInputsEdge) {
  Planes pl;
  pl.d_o = 3.7;
  pl.R = 1.0;
  const auto map = pl.shadowmap_with(0, 4, 0, 4, 40.0f);  // a patch in the map's corner
  const auto in = pl.inputs();
  const auto s = cssm_settings(pl, 8, "sat");
  const auto want = fx::cssm_reference(in, map, s, nullptr);
  const auto got = run_gpu(ctx(), in, map, s, nullptr);
  double md;
  const size_t bad = mismatches(got, want, &md);
  const double e = planes_rmse(pl, in, got), eh = planes_rmse(pl, in, in.hard);
  auto s0 = s;
  s0.input_edges = 0.0;  // the expansion alone
  const double e0 = planes_rmse(pl, in, fx::cssm_reference(in, map, s0, nullptr));
  std::printf("near blocker, cssm M=8 sat: RMSE %.4f against the closed form (the expansion alone "
              "%.4f, the hard input %.4f); GPU and reference differ at %zu pixels (max %.4f)\n",
              e, e0, eh, bad, md);
  EXPECT_LE(bad, want.size() / 200);
  EXPECT_LE(e, eh + 1e-4);
}

// A map larger than shadows.cssm_max_basis: the basis averaged in 8x8 blocks (204 = 25.5 blocks:
// the last block covers half of one), prefiltered and looked up in block units on both sides.
// The GPU follows the double reference, and on the parallel planes the error stays near the
// full-resolution basis's (the penumbra here is ~20 map texels wide, 2.5 blocks).
TEST_F(CssmGpu, BlockAveragedBasisMatchesReferenceAndKeepsTheError) {
  for (const char* filter : {"sat", "mipmap"}) {
    Planes pl;
    pl.slope = 0.6;
    pl.w = pl.h = 48;
    pl.map = 204;
    const auto map = pl.shadowmap();
    const auto in = pl.inputs();
    auto s = cssm_settings(pl, 8, filter);
    s.cssm_max_basis = 32;  // 204 -> 26 blocks of 8 texels
    fx::ShadowmapStats sr, sg;
    const auto want = fx::cssm_reference(in, map, s, &sr);
    const auto got = run_gpu(ctx(), in, map, s, &sg);
    double md;
    const size_t bad = mismatches(got, want, &md);
    std::printf("cssm %s, 204² map in 8x8 blocks: %zu of %zu pixels differ by more than 1e-3 "
                "(max %.4f)\n", filter, bad, want.size(), md);
    EXPECT_LE(bad, want.size() / 100) << filter;
  }
  Planes pl;  // 256² map, 96² image
  const auto map = pl.shadowmap();
  const auto in = pl.inputs();
  auto s = cssm_settings(pl, 8, "sat");
  const auto a = run_gpu(ctx(), in, map, s, nullptr);
  s.cssm_max_basis = 128;  // 2x2 blocks
  const auto b = run_gpu(ctx(), in, map, s, nullptr);
  const double full = planes_rmse(pl, in, a), half = planes_rmse(pl, in, b);
  double moved = 0;
  for (size_t i = 0; i < a.size(); ++i) moved = std::max(moved, double(std::abs(a[i] - b[i])));
  std::printf("parallel planes, cssm M=8: RMSE %.5f full-resolution basis, %.5f in 2x2 blocks "
              "(largest change %.2e)\n", full, half, moved);
  EXPECT_GT(moved, 0.0);  // the blocks are in use
  EXPECT_LT(half, 1.25 * full);
}

TEST_F(CssmGpu, OnContactCaseHalvesTheHardShadowError) {
  auto dir = isg::test::shared_case("contact");
  if (dir.empty()) GTEST_SKIP() << "no ../shared/cases/contact";
  auto ref = isg::io::read_exr(dir / "ref" / "softshadow_key.exr");
  // The defaults: M = 8 and a sharpening confined to real contact (B = 100). With M = 4, A = 30,
  // B = 10 (the thesis's figure) the exponent of eq. 5.9 darkens the box's and sphere's whole
  // penumbrae, as the map's depth range (the 14 m floor) makes every d − z_avg small (RMSE
  // 0.077, above the hard shadow's 0.0435); M 4, B 100: 0.0326; M 8, B 100: 0.0158.
  for (const char* filter : {"sat"}) {
    isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
    job.params.set_text("shadows.method", "cssm", "test");
    job.params.set_text("shadows.cssm_filter", filter, "test");
    auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
    auto st = isg::run::process_frame(ctx(), job, f);
    const auto e = isg::test::shadow_error(f.img, ref);
    const double es = e.soft, eh = e.hard;
    const size_t n = e.pixels;
    const auto* r = st.report("shadows[key] (cssm)");
    ASSERT_TRUE(r);
    std::printf("contact cssm %s: key.softshadow RMSE %.5f, hard %.5f (mask, %zu px), %.1f%% "
                "skipped\n",
                filter, es, eh, n, 100 * r->get("skipped") / r->get("pixels"));
    EXPECT_LT(es, 0.5 * eh) << filter;
  }
}

// A 1024² map in 8x8 blocks (shadows.cssm_max_basis 128), every term of M = 8 (issue 51): on
// isg-synth contact against its ray-traced reference the error stays near the full-resolution
// basis's and under half the hard shadow's. The basis pass once built terms 3-8 by rotating
// term 1, which lavapipe ran wrong in blocks of 4x4 texels and more (lanes of one SIMD group on
// different terms): 0.17 against 0.011 here, every other test passing. Measured: 0.0108 full,
// 0.0224 in blocks (the snapped box is a whole 8-texel block at least), hard 0.0546.
TEST_F(CssmGpu, BlockAveragedBasisKeepsEveryTermOnASynthCase) {
  const auto dir = isg::test::synth_case({"contact", 192, 108, 64, 1, 1024}, "cssm-blocks");
  auto ref = isg::io::read_exr(dir / "ref" / "softshadow_key.exr");
  double es[2] = {0, 0}, eh = 0;
  for (int k = 0; k < 2; ++k) {
    isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
    job.params.set_text("shadows.method", "cssm", "test");
    job.params.set_text("shadows.cssm_max_basis", k == 0 ? "1024" : "128", "test");
    auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
    isg::run::process_frame(ctx(), job, f);
    const auto e = isg::test::shadow_error(f.img, ref);
    es[k] = e.soft;
    eh = e.hard;
  }
  std::printf("synth contact, 1024² map, cssm M=8: RMSE %.5f full-resolution basis, %.5f in 8x8 "
              "blocks, hard %.5f\n", es[0], es[1], eh);
  EXPECT_LT(es[0], 0.5 * eh);
  EXPECT_LT(es[1], 0.5 * eh);
  EXPECT_LT(es[1], 3.0 * es[0]);
}

// The narrowed blocker search (shadows.cssm_narrow, cssm.cpp): a patch 0.5 from the light in a
// corner of the map, out of every receiver's reach, makes PCSS's search region (sized for the
// nearest depth in the map) about five times the cone of the occluder at 2 over the receivers
// at 4. Narrowed to that cone, the search finds no blocker for the receivers whose cone misses
// the occluder, which then skip as lit; GPU and reference alike. What it costs here, measured
// against the closed form: RMSE 0.0652 against the single search's 0.0302 (the hard input
// 0.1160). At the penumbra's outer rim the narrowed box holds a sliver of the occluder, and
// CSM-Z's mean depth from a sliver lies nearer the light than the occluder (0.15 of the depth
// range against 0.43): the penumbra widens into the lit side. A check that drops such an
// estimate (its cone wider than the box it came from) restores 0.0316 here but gives back most
// of the gain on the Cycles cases (grazing 0.43 -> 0.50, lowlight 0.50 -> 0.73, overlap 0.26 ->
// 0.35 of doing nothing), where the wider penumbrae are right: the bound is doing nothing's.
TEST_F(CssmGpu, NarrowedBlockerSearchMatchesReference) {
  Planes pl;
  pl.w = pl.h = 64;
  pl.map = 128;
  const auto map = pl.shadowmap_with(0, 4, 0, 4, 0.5f);  // a patch in the map's corner
  const auto in = pl.inputs();
  auto s = cssm_settings(pl, 8, "sat");
  ASSERT_EQ(s.cssm_narrow, 2);  // the default
  fx::ShadowmapStats sr, sg, s0;
  const auto want = fx::cssm_reference(in, map, s, &sr);
  const auto got = run_gpu(ctx(), in, map, s, &sg);
  double md;
  const size_t bad = mismatches(got, want, &md);
  auto n0 = s;
  n0.cssm_narrow = 0;
  const auto thesis = fx::cssm_reference(in, map, n0, &s0);
  const double e = planes_rmse(pl, in, got), e0 = planes_rmse(pl, in, thesis), eh = planes_rmse(pl, in, in.hard);
  std::printf("narrowed search, cssm M=8 sat: %.1f%% skipped (single search %.1f%%); RMSE %.4f "
              "against the closed form (single search %.4f, the hard input %.4f); GPU and "
              "reference differ at %zu pixels (max %.4f)\n",
              100 * sr.skipped_fraction(), 100 * s0.skipped_fraction(), e, e0, eh, bad, md);
  EXPECT_LE(bad, want.size() / 100);
  EXPECT_NEAR(double(sg.skipped), double(sr.skipped), 0.005 * double(sr.pixels));
  EXPECT_GT(sr.skipped, s0.skipped + sr.pixels / 20);  // the narrowing is in use
  EXPECT_LT(e, 0.75 * eh);
}
