// Soft shadows from the light's shadow map (shadows.method = pcss): GPU against the double
// reference, the parallel-planes case against its closed form, and the shared case `contact`.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "effects/params.h"
#include "effects/shadowmaps/sat.h"
#include "effects/shadowmaps/shadowmap.h"
#include "run/job.h"
#include "support/gpu_fixture.h"
#include "support/shadow_planes.h"
#include "support/images.h"
#include "support/synth_case.h"
#include "effects/shadows/settings.h"
#include "io/scene.h"

using isg::test::GpuTest;
namespace gpu = isg::gpu;
namespace fx = isg::effects;

namespace {
class ShadowmapGpu : public GpuTest {};
using isg::test::Planes;
using isg::test::mismatches;
using isg::test::run_gpu;
using isg::test::kPi;
}  // namespace

TEST(Shadowmap, TapsStayInTheUnitDisk) {
  for (const char* pat : {"poisson", "stratified"}) {
    auto t = fx::shadowmap_taps(32, pat);
    EXPECT_EQ(t.size(), pat[0] == 'p' ? 64u : 72u) << pat;  // stratified: 6² taps
    for (size_t k = 0; k < t.size(); k += 2) EXPECT_LE(t[k] * t[k] + t[k + 1] * t[k + 1], 1.0001f);
  }
}

TEST_F(ShadowmapGpu, PcssMatchesDoubleReference) {
  for (double slope : {0.0, 0.6}) {
    for (const char* pat : {"poisson", "stratified"}) {
      Planes pl;
      pl.slope = slope;
      auto map = pl.shadowmap();
      auto in = pl.inputs();
      in.fg[5] = 0.0f;  // background keeps the hard shadow (marked)
      in.hard[5] = 0.5f;
      auto s = pl.settings(25, pat);
      fx::ShadowmapStats sr, sg;
      auto want = fx::pcss_reference(in, map, s, &sr);
      auto got = run_gpu(ctx(), in, map, s, &sg);
      double md;
      size_t bad = mismatches(got, want, &md);
      EXPECT_EQ(got[5], 0.5f);
      std::printf("slope %.1f %s: %zu of %zu pixels differ by more than 1e-3 (max %.3f)\n", slope,
                  pat, bad, want.size(), md);
      EXPECT_LE(bad, want.size() / 200) << "slope " << slope << " " << pat << ", max diff " << md;
      EXPECT_EQ(sg.pixels, sr.pixels);
      EXPECT_NEAR(double(sg.skipped), double(sr.skipped), 0.005 * double(sr.pixels));
    }
  }
}

TEST_F(ShadowmapGpu, PcssFromDepthAndCameraMatchesReference) {
  // The camera at the light, looking down -Z: P from Z through f_px, eye, rotation.
  Planes pl;
  auto map = pl.shadowmap();
  auto in = pl.inputs();
  in.position.clear();
  in.depth.assign(size_t(in.w) * in.h, float(pl.z_r));
  auto s = pl.settings(16, "stratified");
  s.f_px = 0.5 * in.h / std::tan(30.0 * kPi / 180.0);
  auto want = fx::pcss_reference(in, map, s);
  auto got = run_gpu(ctx(), in, map, s, nullptr);
  double md;
  EXPECT_LE(mismatches(got, want, &md), want.size() / 200) << "max diff " << md;
}

TEST_F(ShadowmapGpu, PcssParallelPlanesMatchesClosedForm) {
  Planes pl;
  auto map = pl.shadowmap();
  auto in = pl.inputs();
  for (const char* pat : {"poisson", "stratified"}) {
    auto s = pl.settings(64, pat);
    fx::ShadowmapStats st;
    auto got = run_gpu(ctx(), in, map, s, &st);
    double e = 0;
    for (int y = 0; y < in.h; ++y)
      for (int x = 0; x < in.w; ++x) {
        double v = pl.visible(in, size_t(y) * in.w + x);
        e += std::pow(got[size_t(y) * in.w + x] - v, 2);
      }
    e = std::sqrt(e / double(in.w * in.h));
    std::printf("parallel planes, pcss %s 64 taps: RMSE %.4f, %.1f%% skipped\n", pat, e,
                100 * st.skipped_fraction());
    EXPECT_LT(e, 0.015) << pat;  // measured 0.0111 (poisson), 0.0131 (stratified)
    EXPECT_GT(st.skipped_fraction(), 0.3);  // the lit half skips the PCF
  }
}

// The narrowed blocker searches of pcss and vssm (shadows.pcss_narrow, shadowmap_pcss.comp;
// shadows.vssm_narrow, shadowmap_vssm.glsl). The parallel planes (occluder at 2 over x < 0,
// receivers at 4, light radius 0.2, 128² map: the occluder's cone is 3.2 texels, the penumbra
// map columns 61-67) with a strip at depth 1 in front of the occluder, map columns 44-56 (x/z
// from -0.31 to -0.125). Every ray from a receiver to the light that passes the occluder crosses
// depth 1 at x/z >= -0.1, so the strip shadows nothing the occluder does not: the truth is the
// strip-free map's result. But it sets the map's nearest depth, so the first search (the cone at
// it, 9.6 texels) takes it in for receivers in the penumbra, and their mean blocker depth moves
// towards 1. Narrowed to the cone at the mean, the search leaves the strip out: the result is the
// strip-free map's at every pixel, where the single search's is not, and receivers whose cone
// misses the occluder skip as lit. GPU and reference alike.
TEST_F(ShadowmapGpu, MapMethodsNarrowTheBlockerSearchToTheBlockersCone) {
  Planes pl;
  pl.w = pl.h = 64;
  pl.map = 128;
  const auto plain = pl.shadowmap();
  const auto map = pl.shadowmap_with(44, 56, 0, pl.map, 1.0f);  // the strip
  const auto in = pl.inputs();
  for (const std::string method : {"pcss", "vssm"}) {
    auto s = pl.settings(32, "stratified", method);
    s.scene_radius = 4.0;  // vssm's thresholds (flat, contact) in the scene's units
    ASSERT_EQ(s.pcss_narrow, 1);  // the defaults
    ASSERT_EQ(s.vssm_narrow, 2);
    auto n0 = s;
    n0.pcss_narrow = n0.vssm_narrow = 0;
    auto ref = [&](const fx::ShadowmapData& m, const fx::ShadowmapSettings& st, fx::ShadowmapStats* out) {
      return method == "pcss" ? fx::pcss_reference(in, m, st, out) : fx::vssm_reference(in, m, st, out);
    };
    fx::ShadowmapStats sr, sg, s0;
    const auto want = ref(map, s, &sr);
    const auto got = run_gpu(ctx(), in, map, s, &sg);
    const auto truth = ref(plain, s, nullptr);  // the strip-free map
    const auto thesis = ref(map, n0, &s0);
    double md, mt, m0;
    const size_t bad = mismatches(got, want, &md);
    const size_t off = mismatches(want, truth, &mt);
    const size_t off0 = mismatches(thesis, truth, &m0);
    std::printf("narrowed search, %s: %zu pixels off the strip-free map's result (max %.4f), "
                "single search %zu (max %.4f); %.1f%% skipped (single search %.1f%%); GPU and "
                "reference differ at %zu pixels (max %.4f)\n",
                method.c_str(), off, mt, off0, m0, 100 * sr.skipped_fraction(),
                100 * s0.skipped_fraction(), bad, md);
    EXPECT_LE(bad, want.size() / 200) << method;
    EXPECT_EQ(sg.pixels, sr.pixels) << method;
    EXPECT_NEAR(double(sg.skipped), double(sr.skipped), 0.005 * double(sr.pixels)) << method;
    EXPECT_EQ(off, 0u) << method;
    EXPECT_GT(off0, want.size() / 20) << method;  // the strip does move the single search
    EXPECT_GT(sr.skipped, s0.skipped + sr.pixels / 20) << method;  // the lit side skips
  }
}

// A ramp rising out of a floor, both lit at grazing angles (the own Cycles case `grazing`, issue
// 19): in light space (light at the origin looking down -z, 90 degree map) the floor lies at
// depth z_f(x) = 8 + 7x (lit 8 degrees above its plane) and the ramp, from the line x = 0 where it
// meets the floor to x = 0.5, at 8 + 2.75x (lit at 20 degrees). Nothing lies between either and
// the light (the floor in front of the ramp is nearer the light than any ramp point, the ramp
// behind every floor point in front of it): closed form 1 everywhere. The ramp's receiver plane,
// extended towards the light, passes under the floor there, so the filters of PCSS and of VSSM's
// PCF taps counted those floor texels as blockers and darkened the ramp along the seam; with
// shadows.reach (the light's cone from the receiver must reach the texel) it stays lit. GPU and
// reference alike.
TEST_F(ShadowmapGpu, MapMethodsKeepARampOverAGrazingFloorLit) {
  const double z0 = 8.0, s_floor = 7.0, s_ramp = 2.75, x1 = 0.5;
  const int map = 512, w = 96, h = 32;
  std::vector<float> z(size_t(map) * map);
  for (int j = 0; j < map; ++j)
    for (int i = 0; i < map; ++i) {
      const double a = 2.0 * (i + 0.5) / map - 1.0;  // x/z along the texel's ray
      double d = 1e30;
      if (1.0 - s_floor * a > 0.0) d = std::min(d, z0 / (1.0 - s_floor * a));
      if (1.0 - s_ramp * a > 0.0) {
        const double zr = z0 / (1.0 - s_ramp * a), x = a * zr;
        if (x >= 0.0 && x <= x1) d = std::min(d, zr);
      }
      z[size_t(j) * map + i] = float(d > 100.0 ? 1e30 : d);
    }
  const auto smap = fx::make_shadowmap(map, map, std::move(z));
  // Receivers on Planes' grid scaled to x in [-0.5, 0.5], y in [-0.25, 0.25]: the floor left of
  // the seam, the ramp right of it.
  Planes pl;
  pl.w = w;
  pl.h = h;
  pl.R = 0.2;
  auto in = pl.inputs();
  const size_t n = in.fg.size();
  std::fill(in.hard.begin(), in.hard.end(), 1.0f);
  for (size_t i = 0; i < n; ++i) {
    const double px = 0.5 * in.position[i];
    in.position[i] = float(px);
    in.position[n + i] *= 0.25f;
    in.position[2 * n + i] = float(-(z0 + (px < 0.0 ? s_floor : s_ramp) * px));
  }
  // Within two texels of the seam (0.031 wide at depth 8) a blocker within the reach's margin
  // may stand: there the receiver touches the floor (contact).
  const double band = 2.0 * 2.0 * z0 / map;
  for (const std::string method : {"pcss", "vssm"}) {
    double dark[2] = {0, 0}, mean[2] = {0, 0};
    for (int r = 0; r < 2; ++r) {
      auto s = pl.settings(64, "stratified", method);
      s.reach = r ? 2.0 : 0.0;
      s.pcss_narrow = s.vssm_narrow = 0;  // the reach test alone (the narrowed searches: below)
      fx::ShadowmapStats st;
      const auto got = run_gpu(ctx(), in, smap, s, &st);
      const auto want = method == "pcss" ? fx::pcss_reference(in, smap, s, nullptr)
                                         : fx::vssm_reference(in, smap, s, nullptr);
      double md, dark_floor = 0;
      size_t n_ramp = 0;
      for (int y = 1; y < h - 1; ++y)
        for (int x = 1; x < w - 1; ++x) {
          const size_t i = size_t(y) * w + x;
          const double v = 1.0 - double(got[i]), px = in.position[i];
          if (px < 0.0) dark_floor = std::max(dark_floor, v);
          if (std::abs(px) >= band) dark[r] = std::max(dark[r], v);
          if (px >= 0.0) {
            mean[r] += v;
            ++n_ramp;
          }
        }
      mean[r] /= double(n_ramp);
      const size_t bad = mismatches(got, want, &md);
      std::printf("ramp over a grazing floor, %s, reach %.0f: darkest %.3f beyond %.3f of the seam, "
                  "ramp mean %.4f, floor darkest %.3f (closed form 0); GPU and reference differ at "
                  "%zu pixels (max %.3f)\n",
                  method.c_str(), s.reach, dark[r], band, mean[r], dark_floor, bad, md);
      EXPECT_EQ(st.pixels, n) << method;
      EXPECT_LE(bad, n / 100) << method << " " << s.reach;
      // Where they differ (the first few), for the device at hand.
      for (size_t i = 0, k = 0; bad > n / 100 && i < n && k < 16; ++i) {
        if (std::abs(double(got[i]) - want[i]) <= 1e-3) continue;
        std::printf("  (%zu, %zu) x %.4f: GPU %.4f reference %.4f\n", i % size_t(w), i / size_t(w),
                    double(in.position[i]), double(got[i]), double(want[i]));
        ++k;
      }
    }
    EXPECT_LE(dark[1], 0.02) << method;
    EXPECT_LE(mean[1], 0.5 * mean[0]) << method;
    // Without the reach test the ramp is dark past the seam's band: the test sees what it guards.
    EXPECT_GE(dark[0], 0.05) << method;
  }
  // The narrowed searches (shadows.pcss_narrow, shadows.vssm_narrow) leave those floor texels
  // out of the mean blocker depth, and so keep the ramp lit without the reach test too.
  for (const std::string method : {"pcss", "vssm"}) {
    auto s = pl.settings(64, "stratified", method);
    s.reach = 0.0;
    ASSERT_GT(method == "pcss" ? s.pcss_narrow : s.vssm_narrow, 0);
    const auto got = run_gpu(ctx(), in, smap, s, nullptr);
    const auto want = method == "pcss" ? fx::pcss_reference(in, smap, s, nullptr)
                                       : fx::vssm_reference(in, smap, s, nullptr);
    double md, dark = 0;
    for (int y = 1; y < h - 1; ++y)
      for (int x = 1; x < w - 1; ++x) {
        const size_t i = size_t(y) * w + x;
        if (std::abs(in.position[i]) >= band) dark = std::max(dark, 1.0 - double(got[i]));
      }
    const size_t bad = mismatches(got, want, &md);
    std::printf("ramp over a grazing floor, %s narrowed, reach 0: darkest %.3f beyond %.3f of the "
                "seam; GPU and reference differ at %zu pixels (max %.3f)\n",
                method.c_str(), dark, band, bad, md);
    EXPECT_LE(dark, 0.02) << method;
    EXPECT_LE(bad, n / 100) << method;
  }
}

// shadows.input_edges: a near-point light (penumbra 0.004 texels wide) and a 32² map whose texel is
// 12 pixels wide on the receiver, the occluder's edge 0.28 texel past a texel's centre: the map
// puts the shadow's edge up to half a texel off, the renderer's L.shadow (here the closed form's
// centre ray) exactly. Without the input's edges the columns between the two edges are wrong
// (RMSE 0.20, 0.16, 0.16); with them the penumbra, 0.004 texel wide, is within
// shadows.input_edges and every method gives the input's L.shadow, here the closed form.
TEST_F(ShadowmapGpu, MapMethodsTakeEdgesTheMapCannotPlaceFromTheInput) {
  Planes pl;
  pl.map = 32;
  pl.R = 1e-3;
  pl.edge = 0.04;  // texel 16's centre is at 0.03125, its far side at 0.0625
  const auto smap = pl.shadowmap();
  const auto in = pl.inputs();
  for (const std::string method : {"pcss", "vssm", "cssm"}) {
    double e[2] = {0, 0};
    for (int on = 0; on < 2; ++on) {
      auto s = pl.settings(32, "stratified", method);
      s.input_edges = on ? 2.0 : 0.0;
      const auto got = run_gpu(ctx(), in, smap, s, nullptr);
      const auto want = method == "pcss"   ? fx::pcss_reference(in, smap, s, nullptr)
                        : method == "vssm" ? fx::vssm_reference(in, smap, s, nullptr)
                                           : fx::cssm_reference(in, smap, s, nullptr);
      double md;
      const size_t bad = mismatches(got, want, &md);
      e[on] = planes_rmse(pl, in, got);
      std::printf("edge 0.28 texel off a 32² map's texel centre, %s, input edges %s: RMSE %.4f "
                  "against the closed form; GPU and reference differ at %zu pixels (max %.3f)\n",
                  method.c_str(), on ? "on" : "off", e[on], bad, md);
      EXPECT_LE(bad, want.size() / 200) << method << " " << on;
    }
    EXPECT_GE(e[0], 0.1) << method;  // the map alone misplaces the edge: the test sees it
    EXPECT_LE(e[1], 0.02) << method;
  }
}

TEST_F(ShadowmapGpu, PcssOnContactCaseHalvesTheHardShadowError) {
  auto dir = isg::test::shared_case("contact");
  if (dir.empty()) GTEST_SKIP() << "no ../shared/cases/contact";
  auto ref = isg::io::read_exr(dir / "ref" / "softshadow_key.exr");
  isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
  job.params.set_text("shadows.method", "pcss", "test");
  auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
  auto st = isg::run::process_frame(ctx(), job, f);
  const auto e = isg::test::shadow_error(f.img, ref);
  const double es = e.soft, eh = e.hard;
  const size_t n = e.pixels;
  const auto* r = st.report("shadows[key] (pcss)");
  ASSERT_TRUE(r);
  std::printf("contact pcss: key.softshadow RMSE %.5f, hard %.5f (mask, %zu px), %.1f%% skipped\n",
              es, eh, n, 100 * r->get("skipped") / r->get("pixels"));
  EXPECT_NEAR(eh, 0.0435, 0.0005);
  EXPECT_LT(es, 0.5 * eh);  // measured 0.0118 (defaults: 36 stratified taps, bias 2, spread 2)
}

// SAT of z and z² in 64-bit fixed point against double prefix sums, on a 4096² map, with
// rectangles up to the whole map: |GPU − double| <= area · (0.5/scale + float rounding of the
// deviation), the quantisation of each entry; the integer table itself is exact.
TEST_F(ShadowmapGpu, SatMatchesDoubleSatOnLargeMap) {
  const int w = 4096, h = 4096;
  const double far_z = 100.0;
  std::vector<float> z(size_t(w) * h);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      z[size_t(y) * w + x] = (x * 7 + y * 3) % 997 == 0 ? 1e10f
                                                       : 3.0f + 2.0f * std::sin(0.01f * x) + u(rng);
  fx::SatPass pass(ctx());
  gpu::Buffer mb(ctx(), z.size() * sizeof(float), "map");
  mb.upload(std::span<const float>(z));
  gpu::Buffer sb(ctx(), z.size() * sizeof(int64_t), "sat");
  for (int power : {1, 2}) {
    auto fp = fx::sat_fixed_point(z, power, far_z);
    gpu::Sequence seq(ctx());
    pass.record(seq, mb, sb, w, h, fp, "sat");
    auto t = seq.submit();
    double ms = 0;
    for (const auto& p : t) ms += p.ms;
    auto sat = sb.download_as<int64_t>(z.size());
    // Double SAT (row-major, one extra row and column of zeros).
    std::vector<double> ref(size_t(w + 1) * (h + 1), 0.0);
    double vmax = 0;
    for (int y = 0; y < h; ++y) {
      double row = 0;
      for (int x = 0; x < w; ++x) {
        double c = std::min(double(z[size_t(y) * w + x]), far_z);
        double v = power == 2 ? c * c : c;
        vmax = std::max(vmax, v);
        row += v;
        ref[size_t(y + 1) * (w + 1) + x + 1] = ref[size_t(y) * (w + 1) + x + 1] + row;
      }
    }
    auto rsum = [&](int x0, int y0, int x1, int y1) {
      auto R = [&](int x, int y) { return ref[size_t(y) * (w + 1) + x]; };
      return R(x1, y1) - R(x0, y1) - R(x1, y0) + R(x0, y0);
    };
    const double per = 0.5 / fp.scale + std::ldexp(2.0 * (vmax + std::abs(fp.offset)), -24);
    std::mt19937 r2(11);
    double worst = 0;
    for (int k = 0; k < 2000; ++k) {
      int x0, y0, x1, y1;
      if (k == 0) { x0 = 0; y0 = 0; x1 = w; y1 = h; }
      else {
        x0 = int(r2() % w); x1 = x0 + 1 + int(r2() % (w - x0));
        y0 = int(r2() % h); y1 = y0 + 1 + int(r2() % (h - y0));
      }
      double area = double(x1 - x0) * double(y1 - y0);
      double got = fx::sat_rect_sum(sat, w, x0, y0, x1, y1, fp), want = rsum(x0, y0, x1, y1);
      worst = std::max(worst, std::abs(got - want) / (area * per));
      ASSERT_LE(std::abs(got - want), area * per + 1e-9 * std::abs(want))
          << "power " << power << " rect " << x0 << "," << y0 << " " << x1 << "," << y1;
    }
    std::printf("SAT %dx%d power %d: GPU %.1f ms, worst error %.3f of its bound\n", w, h, power,
                ms, worst);
  }
}

// A sun's orthographic map (issue 52, contract input 3): the parallel planes under a sun overhead
// (Planes::ortho; the occluder's edge at x = 0, 2 above the receiver; a sun of tan(half angle)
// 0.1, so the penumbra is 0.4 wide, ±20 texels of the 256² map 2.5 across). Each shadow-map
// method on the GPU against its double reference, and against the closed form (the part of the
// sun's disk of directions seen past the edge); the derived L.occluder is the planes' gap along
// the sun's direction.
TEST_F(ShadowmapGpu, SunOrthographicMapMatchesReferencesAndClosedForm) {
  Planes pl;
  pl.ortho = true;
  pl.extent = 2.5;
  pl.R = 0.1;
  const auto map = pl.shadowmap();
  const auto in = pl.inputs();
  const double hard = isg::test::planes_rmse(pl, in, in.hard);
  for (const std::string method : {"pcss", "vssm", "cssm"}) {
    auto s = pl.settings(64, "stratified", method);
    s.scene_radius = 4.0;
    fx::ShadowmapStats sr, sg;
    const auto want = method == "pcss"   ? fx::pcss_reference(in, map, s, &sr)
                      : method == "vssm" ? fx::vssm_reference(in, map, s, &sr)
                                         : fx::cssm_reference(in, map, s, &sr);
    const auto got = run_gpu(ctx(), in, map, s, &sg);
    double md;
    const size_t bad = mismatches(got, want, &md);
    const double e = isg::test::planes_rmse(pl, in, got);
    std::printf("sun, orthographic map, %s: RMSE %.4f against the closed form (hard shadow %.4f); GPU "
                "and reference differ at %zu of %zu pixels (max %.4f)\n",
                method.c_str(), e, hard, bad, want.size(), md);
    EXPECT_LE(bad, want.size() / 200) << method;
    EXPECT_EQ(sg.pixels, sr.pixels) << method;
    EXPECT_LT(e, 0.2 * hard) << method;
  }
  // shadows.derive: the blocker 2 below the sun's side of the receiver, along its axis.
  auto s = pl.settings(16, "stratified", "derive");
  const auto D = fx::shadowmap_derive_reference(in, map, s);
  const auto G = isg::test::run_derive_gpu(ctx(), in, map, s);
  size_t shadowed = 0, off = 0, differ = 0;
  for (size_t i = 0; i < G.shadow.size(); ++i) {
    if (G.shadow[i] != D.shadow[i] || std::abs(G.occluder[i] - D.occluder[i]) > 1e-4f) ++differ;
    if (D.shadow[i] == 0.0f && ++shadowed && std::abs(D.occluder[i] - 2.0f) > 1e-5f) ++off;
  }
  EXPECT_GT(shadowed, G.shadow.size() / 3);
  EXPECT_EQ(off, 0u);
  EXPECT_LE(differ, G.shadow.size() / 1000);
}

// A sun's map over kilometres (issue 52): 2 km across at 2048² (a texel is 0.98 m), the map's
// camera 1 km above the receiver and a 10 cm penumbra (the occluder 2 m above, a sun of tan 0.025).
// No texel can place that edge: every method finds the blocker and keeps the input's ray-traced
// edge (shadows.input_edges) rather than smearing a texel's worth of penumbra, GPU and reference
// alike, with no NaN; the derived occluder distance holds its 2 m to float32's step at 1 km. The
// map's only depth steps are the 2 m edge: its noise measure must not take them for noise (an
// orthographic map's silhouettes are steps of over 2 texels), or the bias would hide the blocker.
TEST_F(ShadowmapGpu, SunMapKilometresAcrossKeepsACentimetrePenumbra) {
  Planes pl;
  pl.ortho = true;
  pl.extent = 2000.0;
  pl.map = 2048;
  pl.z_r = 1000.0;
  pl.d_o = 998.0;
  pl.R = 0.025;
  pl.w = pl.h = 64;
  const auto map = pl.shadowmap();
  const auto in = pl.inputs();
  const double hard = isg::test::planes_rmse(pl, in, in.hard);
  std::printf("sun, 2 km map: measured depth noise %.3f m\n", map.noise);
  for (const std::string method : {"pcss", "vssm", "cssm"}) {
    auto s = pl.settings(32, "stratified", method);
    s.scene_radius = 1000.0;
    const auto want = method == "pcss"   ? fx::pcss_reference(in, map, s, nullptr)
                      : method == "vssm" ? fx::vssm_reference(in, map, s, nullptr)
                                         : fx::cssm_reference(in, map, s, nullptr);
    const auto got = run_gpu(ctx(), in, map, s, nullptr);
    double md;
    const size_t bad = mismatches(got, want, &md);
    const double e = isg::test::planes_rmse(pl, in, got);
    size_t nonfinite = 0;
    for (float v : got) nonfinite += std::isfinite(v) ? 0 : 1;
    std::printf("sun, 2 km map, 10 cm penumbra, %s: RMSE %.4f (hard shadow %.4f); GPU and "
                "reference differ at %zu pixels (max %.4f)\n", method.c_str(), e, hard, bad, md);
    EXPECT_EQ(nonfinite, 0u) << method;
    EXPECT_LE(bad, want.size() / 200) << method;
    EXPECT_LE(e, 1.02 * hard) << method;
  }
  EXPECT_EQ(map.noise, 0.0);
  auto s = pl.settings(16, "stratified", "derive");
  const auto D = fx::shadowmap_derive_reference(in, map, s);
  const auto G = isg::test::run_derive_gpu(ctx(), in, map, s);
  size_t shadowed = 0, off = 0, differ = 0;
  for (size_t i = 0; i < D.shadow.size(); ++i) {
    if (G.shadow[i] != D.shadow[i] || std::abs(G.occluder[i] - D.occluder[i]) > 1e-3f) ++differ;
    if (D.shadow[i] == 0.0f && ++shadowed && std::abs(D.occluder[i] - 2.0f) > 1e-3f) ++off;
  }
  EXPECT_GT(shadowed, D.shadow.size() / 3);
  EXPECT_EQ(off, 0u);
  EXPECT_LE(differ, D.shadow.size() / 1000);
}

// shadows.method=auto under a sun (issue 52): isg-synth `sun` at 480x270, its map over the whole
// 20 m scene. At 1024² the 4-9 cm penumbrae span 1.5 texels (radius, median), where the input's
// hard edge stands in pcss (0.95 of doing nothing's error, isg 0.36): auto takes isg and says
// why. At 4096² (6 texels; pcss 0.26) it takes pcss.
TEST(ShadowmapAuto, ASunMapCoarserThanTheImageTakesIsg) {
  for (const int size : {1024, 4096}) {
    const auto dir = isg::test::synth_case({"sun", 480, 270, 0, 1, size}, "auto-sun-" + std::to_string(size));
    isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
    const auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
    ASSERT_TRUE(job.scene.camera);
    const auto a = fx::choose_shadow_method(f.img, f.roles, job.scene.light("sun"), "sun", &*job.scene.camera);
    std::printf("sun, %d² map: auto takes %s: %s\n", size, a.method.c_str(), a.why.c_str());
    EXPECT_EQ(a.method, size == 1024 ? "isg" : "pcss") << a.why;
    EXPECT_NE(a.why.find(size == 1024 ? "too coarse for these penumbrae" : "the shadow map's pcss"), std::string::npos) << a.why;
  }
}
