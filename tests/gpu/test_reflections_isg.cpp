// Glossy reflections (issue 7, paper §3.2): the GGX cone in closed form against a numerical
// integral of the lobe, pass reflections.isg against its double reference, and the properties
// the paper asks for (mirrors stay sharp, contact hardening, no bleeding across depth and normal
// discontinuities) on small synthetic AOV sets, and the shared Blender case `gloss`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <sstream>

#include "effects/composite/composite.h"
#include "effects/params.h"
#include "effects/reflections/instance.h"
#include "effects/reflections/reflections.h"
#include "io/image.h"
#include "run/job.h"
#include "support/gpu_fixture.h"
#include "support/images.h"
#include "support/synth_case.h"

using isg::test::GpuTest;
namespace gpu = isg::gpu;
namespace fx = isg::effects;

namespace {

constexpr double kPi = std::numbers::pi;

gpu::Buffer upload(gpu::Context& ctx, const std::vector<float>& v, const char* name) {
  gpu::Buffer b(ctx, std::max<size_t>(v.size(), 1) * sizeof(float), name);
  if (!v.empty()) b.upload(std::span<const float>(v));
  return b;
}

struct GpuOut {
  std::vector<float> glossy;
  double skipped = 0;
  fx::ReflTileStats stats;
};

// `fg_before`: reflections.isg first with this foreground instead of in.fg, into the same
// refl.tiles (a sequence's earlier frame).
GpuOut run_gpu(gpu::Context& ctx, const fx::ReflInputs& in, const fx::ReflSettings& s,
               const std::vector<float>* fg_before = nullptr) {
  const uint32_t w = uint32_t(in.w), h = uint32_t(in.h);
  const size_t n = size_t(w) * h;
  const bool has_p = !in.position.empty();
  auto refl = upload(ctx, in.refl, "refl"), dist = upload(ctx, in.dist, "refl.dist"),
       weight = upload(ctx, in.weight, "refl.weight"), normal = upload(ctx, in.normal, "normal"),
       geo = upload(ctx, has_p ? in.position : in.depth, has_p ? "position" : "depth"),
       fg = upload(ctx, in.fg, "fg");
  std::optional<gpu::Buffer> rough;
  if (!in.roughness.empty()) rough.emplace(upload(ctx, in.roughness, "roughness"));
  gpu::Buffer glossy(ctx, 3 * n * sizeof(float), "refl.glossy"),
      tiles(ctx, fx::refl_tiles_words(w, h, s.method == "isg") * 4, "refl.tiles"),
      pack_geo(ctx, fx::refl_pack_texels(w, h) * 16, "refl.pack.geo"),
      pack_color(ctx, fx::refl_pack_texels(w, h) * 16, "refl.pack.color");
  // refl.tiles starts as a run's leftovers would: every word 100.0f, not zero.
  tiles.upload(std::span<const float>(std::vector<float>(tiles.size() / 4, 100.0f)));
  fx::ReflectionsPass pass(ctx, s);
  auto run = [&](gpu::Buffer& fg_of_run) {
    gpu::Sequence seq(ctx);
    pass.record(seq,
                {refl, dist, weight, normal, geo, has_p, rough ? &*rough : nullptr, fg_of_run,
                 pack_geo, pack_color, glossy, tiles},
                w, h, "reflections.isg");
    seq.submit();
  };
  if (fg_before) {
    auto fg0 = upload(ctx, *fg_before, "fg");
    run(fg0);
  }
  run(fg);
  const auto st = fx::ReflectionsPass::stats(tiles, w, h);
  return {glossy.download_as<float>(3 * n), st.skipped_fraction, st};
}

// A camera at (0, 0, height) looking straight down at the floor z = 0 (world_to_camera is a
// translation), or tilted by `tilt` degrees about +X toward +Y.
fx::ReflSettings settings_for(int h, double cam_z, double tilt_deg = 0) {
  isg::io::Camera cam;
  cam.yfov_deg = 40;
  cam.width = h;
  cam.height = h;
  const double t = tilt_deg * kPi / 180, c = std::cos(t), s = std::sin(t);
  // Rotation about X by -t (camera-from-world), then the translation to (0, 0, cam_z).
  cam.world_to_camera = {1, 0, 0, 0, 0, c, s, -s * cam_z, 0, -s, c, -c * cam_z, 0, 0, 0, 1};
  fx::ReflSettings rs;
  rs.f_px = 0.5 * h / std::tan(cam.yfov_deg * kPi / 360.0);
  const auto inv = isg::io::inverse(cam.world_to_camera);
  rs.eye = {inv[3], inv[7], inv[11]};
  const auto& m = cam.world_to_camera;
  rs.rot = {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
  rs.scene_radius = 10;
  return rs;
}

// A floor seen from straight above: depth cam_z everywhere, N up, refl from `refl_of(x, y)`.
template <class F>
fx::ReflInputs floor_inputs(int w, int h, double cam_z, double dist, double roughness, F refl_of) {
  fx::ReflInputs in;
  in.w = w;
  in.h = h;
  const size_t n = size_t(w) * h;
  in.refl.assign(3 * n, 0.0f);
  in.weight.assign(3 * n, 0.8f);
  in.normal.assign(3 * n, 0.0f);
  in.depth.assign(n, float(cam_z));
  in.dist.assign(n, float(dist));
  in.roughness.assign(n, float(roughness));
  in.fg.assign(n, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      in.normal[2 * n + i] = 1.0f;
      for (int c = 0; c < 3; ++c) in.refl[c * n + i] = float(refl_of(x, y)) * (1.0f - 0.2f * c);
    }
  return in;
}

// GPU against the double reference with point taps: a tap whose position lies within float
// rounding of a pixel edge may pick the neighbour in one and not the other, so a handful of
// values differ by a tap's share; everything else agrees to float precision. Returns the
// fraction of values off by more than `tol` (relative above 1) and prints the worst.
double fraction_off(const std::vector<float>& g, const std::vector<float>& ref, double tol) {
  size_t off = 0;
  double worst = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    const double d = std::abs(double(g[i]) - ref[i]) / std::max(1.0, std::abs(double(ref[i])));
    worst = std::max(worst, d);
    off += d > tol;
  }
  std::printf("GPU vs double reference: %zu of %zu values off by > %.0e (worst %.3g)\n", off,
              g.size(), tol, worst);
  return double(off) / double(g.size());
}

// 10–90 % width of a rising edge along row y of plane 0.
double edge_width(const std::vector<float>& v, int w, int y) {
  const float* row = v.data() + size_t(y) * w;
  const double lo = row[0], hi = row[w - 1];
  auto cross = [&](double f) {
    const double target = lo + f * (hi - lo);
    for (int x = 1; x < w; ++x)
      if (row[x] >= target) return x - 1 + (target - row[x - 1]) / (row[x] - row[x - 1]);
    return double(w);
  };
  return cross(0.9) - cross(0.1);
}

// A random glossy scene: a tilted floor with "objects" (other depths and normals, zero weight),
// misses, varied roughness, a background corner.
fx::ReflInputs random_scene(int w, int h, bool with_position, unsigned seed,
                            const fx::ReflSettings& s) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  const size_t n = size_t(w) * h;
  fx::ReflInputs in;
  in.w = w;
  in.h = h;
  in.refl.resize(3 * n);
  in.weight.resize(3 * n);
  in.normal.resize(3 * n);
  in.depth.resize(n);
  in.dist.resize(n);
  in.roughness.resize(n);
  in.fg.assign(n, 1.0f);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const bool object =
          (x - 0.6 * w) * (x - 0.6 * w) + (y - 0.4 * h) * (y - 0.4 * h) < 0.04 * w * w;
      const bool bg = x < w / 8 && y < h / 8;
      in.fg[i] = bg ? 0.0f : 1.0f;
      in.depth[i] = float(bg ? 1e10 : object ? 2.0 + 0.3 * U(rng) : 4.0 + 0.01 * y);
      const double nx = object ? (x - 0.6 * w) / (0.2 * w) : 0.0;
      in.normal[i] = float(nx);
      in.normal[n + i] = object ? 0.3f : 0.0f;
      in.normal[2 * n + i] = float(object ? std::sqrt(std::max(0.0, 1 - nx * nx - 0.09)) : 1.0);
      const double wgt = object || bg ? 0.0 : 0.5 + 0.4 * U(rng);
      for (int c = 0; c < 3; ++c) {
        in.refl[c * n + i] = float(((x / 6 + y / 5) % 2 ? 2.0 : 0.1) * (0.5 + 0.5 * U(rng)));
        in.weight[c * n + i] = float(wgt * (1.0 - 0.1 * c));
      }
      in.dist[i] = float(object || bg ? 0.0 : (x % 17 < 3 ? -1.0 : 0.05 + 3.0 * U(rng)));
      in.roughness[i] = float(object ? 1.0 : 0.05 + 0.5 * double(x) / w);
    }
  }
  if (with_position) {
    in.position.resize(3 * n);
    for (size_t i = 0; i < n; ++i) {
      // Unproject as the pass does, plus a little noise: P and Z then both describe the scene.
      const double z = in.depth[i];
      const double px = double(i % w) + 0.5, py = double(i / w) + 0.5;
      const double c[3] = {(px - 0.5 * w) / s.f_px * z, -(py - 0.5 * h) / s.f_px * z, -z};
      const auto& r = s.rot;
      for (int k = 0; k < 3; ++k)
        in.position[k * n + i] =
            float(r[k] * c[0] + r[3 + k] * c[1] + r[6 + k] * c[2] + s.eye[k] + 1e-3 * U(rng));
    }
  }
  return in;
}

}  // namespace

// The closed-form cone against the NDF integrated numerically: GGX's D(h)·cos θ_h integrates
// to 1 over the hemisphere, and the fraction inside θ_h = atan(α·sqrt(E/(1−E))) is E.
TEST(Reflections, GgxConeHoldsTheEnergyFraction) {
  for (double alpha : {0.01, 0.0625, 0.2, 0.5, 1.0}) {
    for (double E : {0.5, 0.9, 0.99}) {
      const double t_h = std::atan(fx::ggx_cone_tan(alpha, E));
      auto D = [&](double th) {
        const double c = std::cos(th), t = std::tan(th);
        const double d = alpha * alpha + t * t;
        return alpha * alpha / (kPi * c * c * c * c * d * d);
      };
      auto integrate = [&](double a, double b) {  // Simpson, 2π·∫ D cos sin dθ
        const int m = 200000;
        const double hstep = (b - a) / m;
        double s = 0;
        for (int k = 0; k <= m; ++k) {
          const double th = a + k * hstep;
          const double f = D(th) * std::cos(th) * std::sin(th);
          s += f * (k == 0 || k == m ? 1 : k % 2 ? 4 : 2);
        }
        return 2 * kPi * s * hstep / 3;
      };
      const double total = integrate(0, kPi / 2 - 1e-9), inside = integrate(0, t_h);
      EXPECT_NEAR(total, 1.0, 1e-4) << alpha;
      EXPECT_NEAR(inside / total, E, 1e-4) << "alpha " << alpha << " E " << E;
    }
  }
}

namespace {

// The 2×2 quads holding a glossy pixel: one search each (reflections.isg.search).
uint64_t glossy_quads(const fx::ReflInputs& in, const fx::ReflSettings& s) {
  uint64_t quads = 0;
  for (int y = 0; y < in.h; y += 2)
    for (int x = 0; x < in.w; x += 2) {
      bool any = false;
      for (int k = 0; k < 4; ++k) {
        const int px = x + (k & 1), py = y + (k >> 1);
        const size_t i = size_t(py) * in.w + px;
        if (px >= in.w || py >= in.h) continue;
        const size_t n = size_t(in.w) * in.h;  // as the reference's glossy(): weight in any channel
        const float wmax = std::max({in.weight[i], in.weight[n + i], in.weight[2 * n + i]});
        any = any || (in.fg[i] != 0.0f && wmax > 0.0f &&
                      (in.roughness.empty() ? s.roughness : in.roughness[i]) > REFL_MIN_ROUGHNESS);
      }
      quads += any ? 1 : 0;
    }
  return quads;
}

// The rough object of random_scene reflects too. Its depth is noisy, so pixels of a quad lie on
// different surfaces (eq. 10) and search for themselves (reflections.isg.own).
void object_reflects(fx::ReflInputs& in) {
  const size_t n = size_t(in.w) * in.h;
  for (size_t i = 0; i < n; ++i)
    if (in.roughness[i] == 1.0f) {
      for (int c = 0; c < 3; ++c) in.weight[c * n + i] = 0.6f;
      in.dist[i] = 0.2f + 0.1f * float(i % 7);
    }
}

}  // namespace

// The shaders keep the cone as tangents (tan 2θ_h = 2τ / (1 − τ²), τ clamped to the tangent of
// half of REFL_MAX_THETA): the constant they clamp at, against the angle the reference clamps.
TEST(Reflections, ConeClampTangentMatchesTheAngle) {
  EXPECT_NEAR(REFL_TAN_HALF_MAX_THETA, std::tan(0.5 * REFL_MAX_THETA), 1e-7);
  const double t = REFL_TAN_HALF_MAX_THETA;
  EXPECT_NEAR(2.0 * t / (1.0 - t * t), std::tan(REFL_MAX_THETA), 1e-6);
}

TEST_F(GpuTest, ReflectionsMatchReference) {
  for (int variant = 0; variant < 6; ++variant) {
    // Variant 4: radii up to 80 pixels, so the wide searches and the far gather taps read the
    // coarse cells (REFL_COARSE_RADIUS, REFL_COARSE_GATHER) and wide lobes reuse the blocks'
    // gathers, on an image whose last cell row and column hold one pixel (4·24 + 1 by 4·16 + 1:
    // the cell keeps the image's last pixel). Its scene is seed 12's: with seed 11 one search tap
    // lands within 1e-3 pixels of a cell edge (the double reference agrees with the GPU once
    // the tap moves by 1e-3), and the block that search sizes moves 147 values by up to 0.06.
    // Variant 5: variant 0's settings from Z on 192x128, where more pixels gather for themselves than one row of
    // reflections.isg.own's dispatch holds (REFL_OWN_ROW · REFL_OWN_LOCAL).
    const int w = variant == 4 ? 97 : variant == 5 ? 192 : 96, h = variant == 4 ? 65 : variant == 5 ? 128 : 64;
    auto s = settings_for(h, 4.0, 25.0);
    s.method = variant == 3 ? "blur" : "isg";
    s.anisotropic = variant != 1;
    s.search_reach = variant != 2;
    s.search_misses = variant != 1;
    s.grid_search = 4;
    s.grid_gather = 5;
    s.max_radius = variant == 4 ? 80 : 24;
    s.sigma = 0.05;
    const bool with_p = variant % 2 == 0;
    auto in = random_scene(w, h, with_p, variant == 4 ? 12u : variant == 5 ? 7u : 7u + unsigned(variant), s);
    if (variant == 2) in.roughness.clear();  // the preset roughness everywhere
    if (variant == 0 || variant >= 4) object_reflects(in);  // pixels that search for themselves
    std::vector<float> ref_tiles;
    fx::ReflTileStats rst;
    auto ref = fx::reflections_reference(in, s, &ref_tiles, &rst);
    auto g = run_gpu(ctx(), in, s);
    EXPECT_LT(fraction_off(g.glossy, ref, 1e-3), 0.005) << "variant " << variant;
    double skipped = 0;
    for (float t : ref_tiles) skipped += t;
    EXPECT_NEAR(g.skipped, skipped / double(ref_tiles.size()), 1e-12);
    // The statistics: method isg's searches (the quads' and, on the list reflections.isg.own
    // finishes, the pixels' own) and gathers as the reference runs them; a float decision at a
    // threshold may flip a few.
    EXPECT_EQ(g.stats.glossy_pixels, rst.glossy_pixels) << "variant " << variant;
    EXPECT_NEAR(double(g.stats.searches), double(rst.searches), 0.01 * double(rst.searches) + 1) << "variant " << variant;
    EXPECT_NEAR(double(g.stats.gathers), double(rst.gathers), 0.01 * double(rst.gathers) + 1) << "variant " << variant;
    const uint64_t quads = glossy_quads(in, s);  // their searches; the rest are the pixels' own
    std::printf("variant %d: %llu searches (%llu quads'), %llu gathers (reference %llu, %llu)\n",
                variant, (unsigned long long)g.stats.searches, (unsigned long long)quads,
                (unsigned long long)g.stats.gathers, (unsigned long long)rst.searches,
                (unsigned long long)rst.gathers);
    if (variant == 0 || variant >= 4) {
      EXPECT_GT(g.stats.searches, quads + 50) << "variant " << variant;
    }
    if (variant == 5) {
      EXPECT_GT(g.stats.gathers, uint64_t(REFL_OWN_ROW * REFL_OWN_LOCAL) + 1000);
    }
    // Roughly half the glossy pixels actually change (the check compares something).
    size_t changed = 0;
    for (size_t i = 0; i < ref.size(); ++i) changed += std::abs(ref[i] - in.refl[i]) > 1e-3;
    EXPECT_GT(changed, ref.size() / 4) << "variant " << variant;
  }
}

// Wide lobes (R_s >= REFL_REUSE_RADIUS, issue 18) take their mean from the 4x4 blocks' gathers
// around them, across tile borders: the GPU matches the double reference on that path too, and
// most glossy pixels do not gather for themselves.
TEST_F(GpuTest, ReflectionsWideLobesReuseTheQuadsGathers) {
  const int w = 96, h = 64;
  for (int variant = 0; variant < 3; ++variant) {
    auto s = settings_for(h, 4.0, 25.0);
    s.grid_search = 4;
    s.grid_gather = 5;
    s.max_radius = 120;  // footprints past REFL_REUSE_RADIUS (64 pixels)
    s.sigma = 0.05;
    s.anisotropic = variant == 0;
    auto in = random_scene(w, h, variant == 0, 11u + unsigned(variant), s);
    // Variant 1: pixels that search for themselves, then take the blocks' means in
    // reflections.isg.own.
    if (variant == 1) object_reflects(in);
    // Variant 2: a column of tiles with nothing glossy (background) between glossy ones, after
    // a frame where it was glossy: the blocks beside it blend across the other tile borders and
    // skip its blocks, whose records in refl.tiles held that frame's gathers until
    // reflections.list marked them empty.
    const std::vector<float> fg_before = in.fg;
    if (variant == 2)
      for (int y = 0; y < h; ++y)
        for (int x = 2 * REFL_TILE; x < 3 * REFL_TILE; ++x) in.fg[size_t(y) * w + x] = 0.0f;
    in.roughness.clear();  // one roughness: lobes of one width, so the footprint test passes
    s.roughness = 0.6;
    fx::ReflTileStats rst;
    auto ref = fx::reflections_reference(in, s, nullptr, &rst);
    auto g = run_gpu(ctx(), in, s, variant == 2 ? &fg_before : nullptr);
    EXPECT_LT(fraction_off(g.glossy, ref, 1e-3), 0.005) << "variant " << variant;
    std::printf("variant %d: %llu glossy pixels, %llu gathers, %llu searches (reference %llu, %llu, %llu)\n",
                variant, (unsigned long long)g.stats.glossy_pixels, (unsigned long long)g.stats.gathers,
                (unsigned long long)g.stats.searches, (unsigned long long)rst.glossy_pixels,
                (unsigned long long)rst.gathers, (unsigned long long)rst.searches);
    EXPECT_GT(g.stats.glossy_pixels, size_t(w * h / 4));
    EXPECT_LT(g.stats.gathers, g.stats.glossy_pixels / 2) << "variant " << variant;
    if (variant == 1) {
      EXPECT_GT(g.stats.searches, glossy_quads(in, s) + 20);
    }
    // The statistics count what the reference runs (the quads' searches and the pixels' own, the
    // blocks' wide gathers and the pixels' own: reflections.isg.own's list); a float decision
    // at a threshold may flip a few.
    EXPECT_EQ(g.stats.glossy_pixels, rst.glossy_pixels);
    EXPECT_NEAR(double(g.stats.searches), double(rst.searches), 0.01 * double(rst.searches) + 1);
    EXPECT_NEAR(double(g.stats.gathers), double(rst.gathers), 0.01 * double(rst.gathers) + 1);
    EXPECT_DOUBLE_EQ(g.skipped, rst.skipped_fraction);
    size_t changed = 0;
    for (size_t i = 0; i < ref.size(); ++i) changed += std::abs(ref[i] - in.refl[i]) > 1e-3;
    EXPECT_GT(changed, ref.size() / 4) << "variant " << variant;
  }
}

TEST_F(GpuTest, ReflectionsRoughnessZeroBackgroundAndUnweightedAreExact) {
  const int w = 64, h = 48;
  auto s = settings_for(h, 4.0, 25.0);
  auto in = random_scene(w, h, true, 3u, s);
  const size_t n = size_t(w) * h;
  for (size_t i = 0; i < n; ++i)
    if (i % w >= size_t(w / 2)) in.roughness[i] = 0.0f;  // a mirror on the right half
  auto g = run_gpu(ctx(), in, s);
  size_t checked = 0;
  for (size_t i = 0; i < n; ++i) {
    const bool untouched = in.roughness[i] == 0.0f || in.fg[i] == 0.0f || in.weight[i] == 0.0f;
    if (!untouched) continue;
    ++checked;
    for (int c = 0; c < 3; ++c) ASSERT_EQ(g.glossy[c * n + i], in.refl[c * n + i]) << i;
  }
  EXPECT_GT(checked, n / 2);
  // A mirror everywhere: every tile takes the cheap path.
  std::fill(in.roughness.begin(), in.roughness.end(), 0.0f);
  g = run_gpu(ctx(), in, s);
  EXPECT_EQ(g.glossy, std::vector<float>(in.refl.begin(), in.refl.end()));
  EXPECT_EQ(g.skipped, 1.0);
}

// Contact hardening: a reflected edge blurs more the farther the reflected object is.
TEST_F(GpuTest, ReflectionsContactHardening) {
  const int w = 128, h = 24;
  auto s = settings_for(h, 4.0);
  s.f_px = 0.5 * 128 / std::tan(20 * kPi / 180);  // square pixels on a wide, short image
  double prev = 0;
  for (double d : {0.05, 0.3, 1.0, 4.0}) {
    auto in = floor_inputs(w, h, 4.0, d, 0.3, [&](int x, int) { return x < w / 2 ? 0.1 : 1.0; });
    auto g = run_gpu(ctx(), in, s);
    const double width = edge_width(g.glossy, w, h / 2);
    EXPECT_GT(width, prev + 0.5) << "refl.dist " << d;
    prev = width;
  }
  EXPECT_GT(prev, 8.0);
  // Per-pixel roughness: at one distance the edge widens with the roughness.
  prev = 0;
  for (double r : {0.1, 0.2, 0.35, 0.5}) {
    auto in = floor_inputs(w, h, 4.0, 1.0, r, [&](int x, int) { return x < w / 2 ? 0.1 : 1.0; });
    const double width = edge_width(run_gpu(ctx(), in, s).glossy, w, h / 2);
    EXPECT_GT(width, prev + 0.5) << "roughness " << r;
    prev = width;
  }
}

// No bleeding: a bright surface at another depth with another normal, next to the floor, must
// not leak into the floor's glossy reflection (eq. 10-12), and unweighted pixels are skipped.
TEST_F(GpuTest, ReflectionsNoBleedingAcrossDiscontinuities) {
  const int w = 96, h = 32;
  auto s = settings_for(h, 4.0);
  s.f_px = 0.5 * 96 / std::tan(20 * kPi / 180);
  s.masking = false;                         // glossy = refl exactly on a uniform floor
  for (int which = 0; which < 2; ++which) {  // 0: depth and normal differ, 1: weight 0
    auto in = floor_inputs(w, h, 4.0, 2.0, 0.4, [&](int x, int) { return x < w / 2 ? 0.2 : 50.0; });
    const size_t n = size_t(w) * h;
    for (size_t i = 0; i < n; ++i) {
      if (i % w < size_t(w / 2)) continue;
      if (which == 0) {
        in.depth[i] = 2.5f;
        in.normal[i] = 1.0f;
        in.normal[2 * n + i] = 0.0f;
      } else {
        for (int c = 0; c < 3; ++c) in.weight[c * n + i] = 0.0f;
      }
    }
    auto g = run_gpu(ctx(), in, s);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w / 2; ++x) {
        const size_t i = size_t(y) * w + x;
        ASSERT_NEAR(g.glossy[i], 0.2, 0.2 * 1e-3) << x << "," << y << " case " << which;
      }
    if (which == 1) continue;
    // The far surface blurs within itself and stays bright.
    EXPECT_NEAR(g.glossy[size_t(h / 2) * w + w - 4], 50.0, 0.05);
  }
}

namespace {
// The case README's mask: foreground (alpha > 0.5, Z < 1e9) and refl.weight luminance > 0.05.
std::vector<char> gloss_mask(const isg::io::Image& aov) {
  const size_t n = aov.pixels();
  std::vector<char> m(n);
  const auto& A = aov.find("A")->data;
  const auto& Z = aov.find("Z")->data;
  const auto& wr = aov.find("refl.weight.R")->data;
  const auto& wg = aov.find("refl.weight.G")->data;
  const auto& wb = aov.find("refl.weight.B")->data;
  for (size_t i = 0; i < n; ++i)
    m[i] = A[i] > 0.5f && Z[i] < 1e9f && 0.2126 * wr[i] + 0.7152 * wg[i] + 0.0722 * wb[i] > 0.05;
  return m;
}
double rgb_rmse(const isg::io::Image& a, const isg::io::Image& ref, const std::vector<char>& m,
                const char* prefix = "") {
  double s = 0;
  size_t k = 0;
  for (const char* c : {"R", "G", "B"}) {
    const auto& x = a.find(std::string(prefix) + c)->data;
    const auto& y = ref.find(c)->data;
    for (size_t i = 0; i < m.size(); ++i) {
      if (!m[i]) continue;
      const double d = double(x[i]) - double(y[i]);
      s += d * d;
      ++k;
    }
  }
  return std::sqrt(s / double(k));
}
}  // namespace

// The shared Blender case: the floor rendered as a mirror, the reference at roughness 0.25.
TEST_F(GpuTest, ReflectionsSharedCaseGloss) {
  auto dir = isg::test::shared_case("gloss");
  if (dir.empty()) GTEST_SKIP() << "no ../shared/cases/gloss";
  auto ref = isg::io::read_exr(dir / "ref" / "beauty.exr");
  // ISG_REFL_REPORT="9x9,25x25,49x49,81x81" prints a Table-1-like sweep (search x gather).
  std::vector<std::pair<int, int>> counts = {{25, 49}};
  if (const char* env = std::getenv("ISG_REFL_REPORT")) {
    counts.clear();
    std::stringstream ss(env);
    for (std::string t; std::getline(ss, t, ',');)
      counts.push_back({std::stoi(t.substr(0, t.find('x'))), std::stoi(t.substr(t.find('x') + 1))});
  }
  std::vector<std::string> methods = {"isg", "blur"};
  double nothing = -1, isg_err = -1, blur_err = -1;
  for (const auto& m : methods) {
    for (auto [search, gather] : counts) {
      isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
      job.params.set_text("reflections.method", m, "test");
      job.params.set_text("reflections.roughness", "0.25", "test");
      job.params.set_text("reflections.roughness_override", "true", "test");
      job.params.set_text("reflections.search_samples", std::to_string(search), "test");
      job.params.set_text("reflections.gather_samples", std::to_string(gather), "test");
      if (const char* extra = std::getenv("ISG_REFL_SET")) {  // "key=value;key=value"
        std::stringstream ss(extra);
        for (std::string kv; std::getline(ss, kv, ';');)
          job.params.set_text(kv.substr(0, kv.find('=')), kv.substr(kv.find('=') + 1), "env");
      }
      auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
      const auto mask = gloss_mask(f.img);
      if (nothing < 0) {
        nothing = rgb_rmse(f.img, ref, mask);
        std::printf("nothing (AOV beauty)          RMSE %.5f\n", nothing);
      }
      auto st = isg::run::process_frame(ctx(), job, f);
      ASSERT_NE(f.img.find("refl.glossy.R"), nullptr);
      const double e = rgb_rmse(f.img, ref, mask);
      double ms = 0;
      for (const auto& p : st.passes)
        if (p.name.starts_with("reflections.")) ms = p.ms;
      std::printf(
          "%-5s search %3d gather %3d  RMSE %.5f  (oracle gap closed %.1f%%)  GPU %.1f ms  tiles "
          "skipped %.1f%%\n",
          m.c_str(), search, gather, e, 100.0 * (nothing - e) / (nothing - 0.0003), ms,
          100.0 * st.report("reflections")->get("skipped"));
      if (m == "isg" && isg_err < 0) {
        isg_err = e;
        // The pass against its double reference on the whole case.
        fx::ReflInputs in;
        in.w = f.img.width;
        in.h = f.img.height;
        auto role = [&](const char* r, int planes) {
          return isg::io::gather_role(f.img, *f.roles.get(r), planes);
        };
        in.refl = role("refl", 3);
        in.dist = role("refl.dist", 1);
        in.weight = role("refl.weight", 3);
        in.normal = role("normal", 3);
        in.position = role("position", 3);
        const auto alpha = f.img.find("input.A")->data, depth = f.img.find("Z")->data;
        in.fg = fx::foreground_reference(alpha.data(), depth.data(), f.img.pixels());
        const auto ref_glossy = fx::reflections_reference(in, f.plan.instance_as<fx::ReflInstance>("reflections")->s);
        std::vector<float> g;
        for (int c = 0; c < 3; ++c) {
          const auto& gc = f.img.find(std::string("refl.glossy.") + "RGB"[c])->data;
          g.insert(g.end(), gc.begin(), gc.end());
        }
        EXPECT_LT(fraction_off(g, ref_glossy, 1e-3), 0.002) << "refl.glossy against the double reference";
      }
      if (m == "blur" && blur_err < 0) blur_err = e;
    }
  }
  // The issue asks for half of doing nothing (and aims at a fifth: 0.0022 measured at 25 x 49),
  // and contact hardening beats the best constant-width blur.
  EXPECT_LT(isg_err, 0.5 * nothing);
  EXPECT_LT(isg_err, blur_err);
}

// isg-synth's gloss scene: per-pixel roughness (0.1 and 0.35 halves), refl.glossy against the
// synth's distribution-ray-traced reference over its mask.
TEST_F(GpuTest, ReflectionsSynthGloss) {
  const auto dir = isg::test::synth_case({"gloss", 160, 90}, "refl-synth-gloss");
  const auto ref = isg::io::read_exr(dir / "ref" / "glossy.exr");
  const auto& mask = ref.find("mask")->data;
  double errs[3] = {0, 0, 0};  // nothing, isg, blur
  for (int m = 0; m < 3; ++m) {
    isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
    job.params.set_text("reflections.method", m == 2 ? "blur" : "isg", "test");
    auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
    isg::run::process_frame(ctx(), job, f);
    double s = 0;
    size_t k = 0;
    for (const char* c : {"R", "G", "B"}) {
      const auto& x = f.img.find(std::string(m == 0 ? "refl." : "refl.glossy.") + c)->data;
      const auto& y = ref.find(std::string("refl.glossy.") + c)->data;
      for (size_t i = 0; i < mask.size(); ++i) {
        if (mask[i] < 0.5f) continue;
        s += (double(x[i]) - double(y[i])) * (double(x[i]) - double(y[i]));
        ++k;
      }
    }
    errs[m] = std::sqrt(s / double(k));
  }
  std::printf("synth gloss refl.glossy RMSE: refl %.5f  isg %.5f  blur %.5f\n", errs[0], errs[1],
              errs[2]);
  EXPECT_LT(errs[1], 0.5 * errs[0]);
  EXPECT_LT(errs[1], errs[2]);
}

namespace {

// isg-synth gloss at 160 x 90 (64-sample GGX reference), generated once per test binary.
const std::filesystem::path& synth_gloss_dir() {
  static const std::filesystem::path dir =
      isg::test::synth_case({"gloss", 160, 90}, "refl-synth-gloss-shared");
  return dir;
}

// RMSE of refl.glossy (method isg, `search` x `gather` samples) against the reference over its
// mask; the whole scene (P and the camera) moved by `offset` world units first.
double synth_gloss_error(isg::gpu::Context& ctx, int search, int gather, double offset) {
  const auto& dir = synth_gloss_dir();
  const auto ref = isg::io::read_exr(dir / "ref" / "glossy.exr");
  const auto& mask = ref.find("mask")->data;
  auto input = dir / "aovs.exr";
  isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
  if (offset != 0.0) {
    auto aovs = isg::io::read_exr(input);
    for (const char* c : {"P.X", "P.Y", "P.Z"})
      for (float& v : aovs.find(c)->data) v = float(double(v) + offset);
    input = dir / ("aovs_offset_" + std::to_string(int(offset)) + ".exr");
    isg::io::write_exr(input, aovs, {});
    // p_cam = R (p − e): moving e by t subtracts R t from the translation column.
    auto& m = job.scene.camera->world_to_camera;
    for (int r = 0; r < 3; ++r) m[size_t(r * 4 + 3)] -= (m[size_t(r * 4)] + m[size_t(r * 4 + 1)] + m[size_t(r * 4 + 2)]) * offset;
  }
  job.params.set_text("reflections.method", "isg", "test");
  job.params.set_text("reflections.search_samples", std::to_string(search), "test");
  job.params.set_text("reflections.gather_samples", std::to_string(gather), "test");
  auto f = isg::run::load_frame(job, input.string());
  isg::run::process_frame(ctx, job, f);
  double s = 0;
  size_t k = 0;
  for (const char* c : {"R", "G", "B"}) {
    const auto& x = f.img.find(std::string("refl.glossy.") + c)->data;
    const auto& y = ref.find(std::string("refl.glossy.") + c)->data;
    for (size_t i = 0; i < mask.size(); ++i) {
      if (mask[i] < 0.5f) continue;
      s += (double(x[i]) - double(y[i])) * (double(x[i]) - double(y[i]));
      ++k;
    }
  }
  return std::sqrt(s / double(k));
}

}  // namespace

TEST_F(GpuTest, ReflectionsSynthGlossErrorFallsAsSamplesGrow) {
  double prev = 1e9;
  for (int n : {9, 25, 81}) {
    const double e = synth_gloss_error(ctx(), n, n, 0.0);
    std::printf("synth gloss %d x %d samples: refl.glossy RMSE %.5f\n", n, n, e);
    EXPECT_LT(e, prev * 1.02) << n;
    prev = e;
  }
}

// The gloss scene 1e5 units from the origin (P stored as float there, as a renderer would):
// the same error within 5%.
TEST_F(GpuTest, ReflectionsSynthGlossFarFromTheOrigin) {
  const double near = synth_gloss_error(ctx(), 25, 49, 0.0);
  const double far = synth_gloss_error(ctx(), 25, 49, 1e5);
  std::printf("synth gloss refl.glossy RMSE: at the origin %.5f, moved by 1e5 %.5f\n", near, far);
  EXPECT_LT(near, 0.021);  // measured 0.0177 at 160 x 90, 25 x 49 samples (sharp refl: 0.0516)
  EXPECT_NEAR(far, near, 0.05 * near);
}
