// Depth of field (issue 8): each pass against its double reference, and the properties the
// thin lens asks for (in-focus plane sharp, edge blur width, bokeh size and energy, the
// foreground over an in-focus object), on small synthetic images and on the shared Blender case.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <sstream>

#include "effects/dof/dof.h"
#include "effects/params.h"
#include "run/job.h"
#include "support/gpu_fixture.h"
#include "support/images.h"
#include "support/synth_case.h"

using isg::test::GpuTest;
namespace gpu = isg::gpu;
namespace fx = isg::effects;

namespace {

constexpr double kPi = std::numbers::pi;

struct Scene2 {
  int w = 0, h = 0;
  std::vector<float> rgba, depth;  // 4 planes, 1 plane
  size_t n() const { return size_t(w) * h; }
};

struct GpuResult {
  std::vector<float> coc, tiles, out;
  double cheap = 0;
};

gpu::Buffer upload(gpu::Context& ctx, const std::vector<float>& v, const char* name) {
  gpu::Buffer b(ctx, v.size() * sizeof(float), name);
  b.upload(std::span<const float>(v));
  return b;
}

GpuResult run_gpu(gpu::Context& ctx, const Scene2& sc, const fx::DofSettings& s) {
  const uint32_t w = uint32_t(sc.w), h = uint32_t(sc.h);
  const size_t n = sc.n();
  auto comp = upload(ctx, sc.rgba, "composite"), depth = upload(ctx, sc.depth, "depth");
  gpu::Buffer coc(ctx, n * 4, "dof.coc"), input(ctx, 4 * n * 4, "dof.input"),
      radius(ctx, n * 4, "dof.radius"),
      tiles(ctx, size_t(4) * fx::dof_tiles_x(w) * fx::dof_tiles_y(h) * 4, "dof.tiles");
  fx::DofPass pass(ctx, s);
  gpu::Sequence seq(ctx);
  pass.record_coc(seq, comp, true, depth, coc, input, w, h);
  pass.record_tiles(seq, coc, tiles, w, h);
  if (s.method == "isg") {
    pass.record_search(seq, coc, tiles, radius, w, h);
    pass.record_gather(seq, input, coc, tiles, radius, comp, w, h);
  } else {
    pass.record_layered(seq, input, coc, tiles, comp, w, h);
  }
  seq.submit();
  GpuResult r;
  r.coc = coc.download_as<float>(n);
  r.tiles = tiles.download_as<float>(size_t(4) * fx::dof_tiles_x(w) * fx::dof_tiles_y(h));
  r.out = comp.download_as<float>(4 * n);
  r.cheap = fx::DofPass::cheap_fraction(tiles, w, h);
  return r;
}

std::vector<float> reference(const Scene2& sc, const std::vector<float>& coc,
                             const std::vector<float>& tiles, const fx::DofSettings& s) {
  return s.method == "isg" ? fx::dof_isg_reference(sc.rgba, coc, tiles, sc.w, sc.h, s)
                           : fx::dof_layered_reference(sc.rgba, coc, tiles, sc.w, sc.h, s);
}

fx::DofSettings settings(const std::string& method, double c_inf, double z_f, int grid = 8) {
  fx::DofSettings s;
  s.method = method;
  s.lens.c_inf = c_inf;
  s.lens.z_f = z_f;
  s.lens.max_coc = 24;
  s.grid = grid;
  return s;
}

// Three layers: a far textured wall (depth 8), an in-focus textured card (depth 2 = z_f), a near
// disc (depth 1), one transparent background corner.
Scene2 layered_scene(int w, int h) {
  Scene2 sc{w, h, std::vector<float>(4 * size_t(w) * h), std::vector<float>(size_t(w) * h)};
  const size_t n = sc.n();
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      float z = 8.0f, r = 0.2f + 0.6f * float((x / 3 + y / 5) % 2), g = 0.3f, b = 0.1f * float(x % 7);
      if (x > w / 3 && x < w - 8 && y > 6 && y < h - 6) {
        z = 2.0f + 0.002f * float(x);
        r = 0.9f * float((x + y) % 2);
        g = 0.5f + 0.4f * std::sin(0.7f * float(x));
        b = 0.2f;
      }
      const double dx = x - w * 0.3, dy = y - h * 0.55;
      if (dx * dx + dy * dy < 49.0) { z = 1.0f; r = 0.1f; g = 0.9f; b = 0.8f; }
      if (x > w - 12 && y < 8 && z == 8.0f) z = 1e10f;
      if (x == w / 5 && y == h / 4) { r = g = b = 30.0f; }  // a bright far highlight
      const float a = z >= 1e9f ? 0.0f : 1.0f;
      sc.depth[i] = z;
      sc.rgba[i] = r * a;
      sc.rgba[n + i] = g * a;
      sc.rgba[2 * n + i] = b * a;
      sc.rgba[3 * n + i] = a;
    }
  }
  return sc;
}

// One bright pixel (energy E in R, G, B) at (hx, hy) on a black wall at depth 10, c = 8 px with
// c_inf 10 and z_f 2 (the depths alternate by 0.05 so that no tile takes the cheap path).
Scene2 highlight_scene(int w, int h, int hx, int hy, float E) {
  Scene2 sc{w, h, std::vector<float>(4 * size_t(w) * h, 0.0f), std::vector<float>(size_t(w) * h)};
  const size_t n = sc.n();
  for (size_t i = 0; i < n; ++i) {
    sc.depth[i] = 10.0f + 0.05f * float(i % 2);
    sc.rgba[3 * n + i] = 1.0f;
  }
  for (int c = 0; c < 3; ++c) sc.rgba[c * n + size_t(hy) * w + hx] = E;
  return sc;
}

double max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, double(std::abs(a[i] - b[i])));
  return m;
}

}  // namespace

TEST(Dof, LensFromCamera) {
  // The dof case: 85 mm f/1.4 focused at 3 m, 36 mm sensor, 480 px wide:
  // c_inf = 85² / (2 · 1.4 · (3000 − 85)) · 480 / 36 = 11.80 px.
  isg::io::Camera cam;
  cam.focal_length_mm = 85;
  cam.fstop = 1.4;
  cam.focus_distance = 3.0;
  cam.sensor_width_mm = 36;
  cam.width = 480;
  auto p = fx::default_params();
  auto L = fx::dof_lens(cam, "m", p);
  EXPECT_NEAR(L.c_inf, 85.0 * 85.0 / (2 * 1.4 * 2915.0) * 480.0 / 36.0, 1e-9);
  EXPECT_NEAR(L.c_inf, 11.80, 0.01);
  EXPECT_EQ(L.z_f, 3.0);
  p.set_text("dof.coc_infinity", "5", "test");
  p.set_text("dof.coc_scale", "2", "test");
  EXPECT_NEAR(fx::dof_lens(cam, "m", p).c_inf, 10.0, 1e-12);
  p.set_text("dof.focus_distance", "300", "test");
  p.set_text("dof.coc_infinity", "0", "test");
  p.set_text("dof.coc_scale", "1", "test");
  EXPECT_NEAR(fx::dof_lens(cam, "cm", p).c_inf, 11.80, 0.01);  // 300 cm = 3 m
}

TEST_F(GpuTest, DofMatchesReferencePerMethod) {
  const Scene2 sc = layered_scene(72, 40);
  // c_inf 12: far CoCs of 9-12 px, over DOF_REUSE_COC, so dof.layered's quads' results are reused.
  for (const std::string method : {"isg", "layered", "layered-wide"}) {
    for (int blades : {0, 5}) {
      auto s = settings(method == "isg" ? "isg" : "layered", method == "layered-wide" ? 12.0 : 6.0, 2.0, 6);
      s.blades = blades;
      s.rotation_deg = 17;
      auto g = run_gpu(ctx(), sc, s);
      auto coc = fx::dof_coc_reference(sc.depth, sc.rgba.data() + 3 * sc.n(), s);
      EXPECT_LT(max_abs_diff(g.coc, coc), 1e-5) << method;
      // Same inputs from here on: the GPU's CoC feeds the references of the later passes.
      auto tiles = fx::dof_tiles_reference(g.coc, sc.w, sc.h, s);
      EXPECT_EQ(g.tiles, tiles) << method;
      EXPECT_LT(g.cheap, 1.0);
      EXPECT_DOUBLE_EQ(g.cheap, fx::dof_cheap_fraction(tiles));
      auto want = reference(sc, g.coc, tiles, s);
      EXPECT_LT(max_abs_diff(g.out, want), 1e-3) << method << " blades " << blades;
    }
  }
}

// Issue 53: depth as compositors get it. The dof.coc pass on normalized and inverse depth gives
// the CoC of eq. 15 on the planar depth they came from (the closed form, in double), and on a
// CoC channel its values times the gain; each also against the pass's own double reference.
TEST_F(GpuTest, DofCocFromDepthFormsAndACocChannel) {
  const Scene2 planar = layered_scene(40, 24);
  auto s = settings("layered", 6.0, 2.0, 4);
  const double near = 0.5, far = 20.0;
  std::vector<float> want(planar.n());
  for (size_t i = 0; i < planar.n(); ++i) {
    const double z = planar.depth[i];
    const double c = z >= 1e9 ? 6.0 : 6.0 * (z - 2.0) / z;
    want[i] = float(std::clamp(c, -24.0, 24.0));
  }
  for (int form : {1, 2}) {
    Scene2 sc = planar;
    for (size_t i = 0; i < sc.n(); ++i) {
      const double z = planar.depth[i];
      sc.depth[i] = form == 1 ? (z >= 1e9 ? 1.0f : float((z - near) / (far - near))) : (z >= 1e9 ? 0.0f : float(1.0 / z));
    }
    auto f = s;
    f.depth_form = form;
    f.depth_near = near;
    f.depth_far = far;
    auto g = run_gpu(ctx(), sc, f);
    EXPECT_LT(max_abs_diff(g.coc, want), 2e-4) << "form " << form;
    EXPECT_LT(max_abs_diff(g.coc, fx::dof_coc_reference(sc.depth, sc.rgba.data() + 3 * sc.n(), f)), 1e-5);
  }
  Scene2 sc = planar;
  for (size_t i = 0; i < sc.n(); ++i) sc.depth[i] = float(int(i % 97) - 48) * 0.5f;  // CoC -24 .. 24
  auto f = s;
  f.coc_source = 1;
  f.lens.c_inf = 1.5;  // dof.coc_scale
  auto g = run_gpu(ctx(), sc, f);
  for (size_t i = 0; i < sc.n(); ++i)
    ASSERT_FLOAT_EQ(g.coc[i], std::clamp(1.5f * sc.depth[i], -24.0f, 24.0f)) << i;
}

// Issue 53: an anamorphic aperture (dof.anamorphic 2): the highlight of the test above becomes an
// oval twice as tall as wide, its half-axes cr/√2 across and cr·√2 down (the thin lens's disc
// squeezed at the same area), with its energy kept; each method against its double reference.
TEST_F(GpuTest, DofAnamorphicHighlightIsAnOvalWithEnergyKept) {
  const int w = 48, h = 64;
  const int hx = 24, hy = 32;
  const float E = 100.0f;
  const Scene2 sc = highlight_scene(w, h, hx, hy, E);
  const double cr = 8.0, ax = cr / std::sqrt(2.0), ay = cr * std::sqrt(2.0);
  for (const std::string method : {"isg", "layered"}) {
    auto s = settings(method, 10.0, 2.0, 24);
    s.anamorphic = 2.0;
    auto g = run_gpu(ctx(), sc, s);
    double energy = 0, reach_x = 0, reach_y = 0, far_out = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double v = g.out[size_t(y) * w + x];
        energy += v;
        const double e = std::hypot((x - hx) / (ax + 1.5), (y - hy) / (ay + 1.5));
        if (e > 1.0) far_out = std::max(far_out, v);
        if (v > 0.1 * E / (kPi * cr * cr)) {
          if (y == hy) reach_x = std::max(reach_x, std::abs(double(x - hx)));
          if (x == hx) reach_y = std::max(reach_y, std::abs(double(y - hy)));
        }
      }
    EXPECT_NEAR(energy, E, 0.06 * E) << method;
    EXPECT_LT(far_out, 1e-6) << method;
    EXPECT_NEAR(reach_x, ax, 1.0) << method;
    EXPECT_NEAR(reach_y, ay, 1.0) << method;
    auto tiles = fx::dof_tiles_reference(g.coc, w, h, s);
    EXPECT_EQ(g.tiles, tiles) << method;
    EXPECT_LT(max_abs_diff(g.out, reference(sc, g.coc, tiles, s)), 1e-3) << method;
  }
}

TEST_F(GpuTest, DofInFocusPlaneStaysSharp) {
  // A textured card at the focus distance in front of a far wall: away from the wall's reach
  // (its CoC, which cannot cross in front of the card anyway) the card is the pinhole image.
  Scene2 sc = layered_scene(64, 40);
  const size_t n = sc.n();
  for (size_t i = 0; i < n; ++i)
    if (sc.depth[i] < 1.5f) sc.depth[i] = 8.0f;  // no near disc here
  for (const std::string method : {"isg", "layered"}) {
    for (bool skip : {true, false}) {
      auto s = settings(method, 6.0, 2.0, 6);
      s.tile_skip = skip;
      for (size_t i = 0; i < n; ++i)
        if (sc.depth[i] < 3.0f) sc.depth[i] = 2.0f;  // exactly in focus
      auto g = run_gpu(ctx(), sc, s);
      double worst = 0;
      size_t count = 0;
      for (size_t i = 0; i < n; ++i) {
        if (sc.depth[i] != 2.0f) continue;
        ++count;
        for (size_t c = 0; c < 4; ++c)
          worst = std::max(worst, double(std::abs(g.out[c * n + i] - sc.rgba[c * n + i])));
      }
      EXPECT_GT(count, 300u);
      EXPECT_LT(worst, 1e-5) << method << " tile_skip " << skip;
    }
  }
}

TEST_F(GpuTest, DofBackgroundEdgeBlurMatchesThinLensCoc) {
  // A black/white edge on a wall at depth 10 with z_f = 2, c_inf = 10: c = 10 · 8 / 10 = 8 px.
  // A disk-shaped blur of radius c turns the step into a ramp from x0 − c to x0 + c.
  const int w = 64, h = 24;
  Scene2 sc{w, h, std::vector<float>(4 * size_t(w) * h), std::vector<float>(size_t(w) * h)};
  const size_t n = sc.n();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      size_t i = size_t(y) * w + x;
      sc.depth[i] = 10.0f + 0.02f * float(y % 3);  // a little depth noise
      float v = x >= w / 2 ? 1.0f : 0.0f;
      sc.rgba[i] = sc.rgba[n + i] = sc.rgba[2 * n + i] = v;
      sc.rgba[3 * n + i] = 1.0f;
    }
  for (const std::string method : {"isg", "layered"}) {
    for (bool skip : {true, false}) {
      auto s = settings(method, 10.0, 2.0, 16);
      s.tile_skip = skip;
      auto g = run_gpu(ctx(), sc, s);
      const double c = 10.0 * (10.0 - 2.0) / 10.0;
      // Row-averaged profile over the middle rows.
      std::vector<double> prof(w, 0.0);
      for (int y = 8; y < 16; ++y)
        for (int x = 0; x < w; ++x) prof[x] += g.out[size_t(y) * w + x] / 8.0;
      // The line spread function (the profile's derivative) of a disk of radius c is its chord,
      // whose variance is c² / 4: the blur radius is twice its standard deviation.
      double sw = 0, sx = 0, sxx = 0;
      for (int x = 0; x + 1 < w; ++x) {
        double l = prof[x + 1] - prof[x], pos = x + 1.0;  // at the boundary between the centres
        sw += l;
        sx += l * pos;
        sxx += l * pos * pos;
      }
      const double mean = sx / sw, radius = 2.0 * std::sqrt(sxx / sw - mean * mean);
      EXPECT_NEAR(2.0 * radius, 2.0 * c, 1.0) << method << " tile_skip " << skip;
      EXPECT_NEAR(mean, w / 2.0, 0.5) << method;
    }
  }
}

TEST_F(GpuTest, DofHighlightBecomesApertureDiscWithEnergyKept) {
  // One bright pixel on a black wall at depth 10 (c = 8 px): a disc of radius c holding the
  // pixel's energy; with a 6-blade aperture, a hexagon (longer to its corners than its edges).
  const int w = 48, h = 48;
  const int hx = 24, hy = 24;
  const float E = 100.0f;
  const Scene2 sc = highlight_scene(w, h, hx, hy, E);
  const double cr = 10.0 * 8.0 / 10.0;
  for (const std::string method : {"isg", "layered"}) {
    for (int blades : {0, 6}) {
      auto s = settings(method, 10.0, 2.0, 24);
      s.blades = blades;
      auto g = run_gpu(ctx(), sc, s);
      double energy = 0, inside = 0, far_out = 0;
      double reach_corner = 0, reach_edge = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          double v = g.out[size_t(y) * w + x];
          energy += v;
          double r = std::hypot(x - hx, y - hy);
          if (r <= cr + 1.0) inside += v;
          if (r > cr + 1.5) far_out = std::max(far_out, v);
          if (v > 0.1 * E / (kPi * cr * cr)) {
            if (y == hy) reach_corner = std::max(reach_corner, std::abs(double(x - hx)));  // corner at 0°
            if (x == hx) reach_edge = std::max(reach_edge, std::abs(double(y - hy)));     // edge at 90°
          }
        }
      EXPECT_NEAR(energy, E, 0.06 * E) << method << " blades " << blades;
      EXPECT_GT(inside, 0.97 * energy) << method;
      EXPECT_LT(far_out, 1e-6) << method;
      // The disc's radius is the CoC (within a pixel).
      EXPECT_NEAR(reach_corner, cr, 1.0) << method << " blades " << blades;
      if (blades == 0) EXPECT_NEAR(reach_edge, cr, 1.0) << method;
      else EXPECT_NEAR(reach_edge, cr * std::cos(kPi / 6), 1.0) << method;
    }
  }
}

namespace {
// Thin-lens truth for two planes: an in-focus textured card behind a near disc of constant
// colour with CoC c_n < 0. A ray through lens point u reaching pixel p crosses the near plane at
// p + |c_n|·u (image units); it sees the disc there, else the card at p.
std::vector<float> two_plane_truth(const Scene2& sc, const std::vector<float>& near_mask,
                                   const std::vector<float>& near_rgba, double cn) {
  const size_t n = sc.n();
  std::vector<float> out(4 * n);
  const int G = 48;
  for (int y = 0; y < sc.h; ++y)
    for (int x = 0; x < sc.w; ++x) {
      const size_t i = size_t(y) * sc.w + x;
      double acc[4] = {0, 0, 0, 0};
      int cnt = 0;
      for (int a = 0; a < G; ++a)
        for (int b = 0; b < G; ++b) {
          double ux = 2 * (a + 0.5) / G - 1, uy = 2 * (b + 0.5) / G - 1;
          if (ux * ux + uy * uy > 1) continue;
          ++cnt;
          int qx = int(std::floor(x + 0.5 + std::abs(cn) * ux)), qy = int(std::floor(y + 0.5 + std::abs(cn) * uy));
          bool hit = qx >= 0 && qy >= 0 && qx < sc.w && qy < sc.h && near_mask[size_t(qy) * sc.w + qx] > 0;
          for (size_t c = 0; c < 4; ++c) acc[c] += hit ? near_rgba[c] : sc.rgba[c * n + i];
        }
      for (size_t c = 0; c < 4; ++c) out[c * n + i] = float(acc[c] / cnt);
    }
  return out;
}
}  // namespace

TEST_F(GpuTest, DofLayeredBeatsIsgOnForegroundOverInFocus) {
  // A near disc (depth 1, z_f = 2, c_inf = 12: c = −12 px) over an in-focus textured card.
  const int w = 96, h = 64;
  Scene2 sc{w, h, std::vector<float>(4 * size_t(w) * h), std::vector<float>(size_t(w) * h)};
  const size_t n = sc.n();
  std::vector<float> mask(n, 0.0f), card(4 * n);
  const float near_rgba[4] = {0.9f, 0.2f, 0.1f, 1.0f};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      size_t i = size_t(y) * w + x;
      card[i] = 0.5f + 0.5f * float((x / 2 + y / 2) % 2);
      card[n + i] = 0.3f + 0.6f * float(((x + 1) / 3) % 2);
      card[2 * n + i] = 0.8f;
      card[3 * n + i] = 1.0f;
      double dx = x - 40, dy = y - 32;
      mask[i] = dx * dx + dy * dy < 16.0 * 16.0 ? 1.0f : 0.0f;
    }
  Scene2 card_only{w, h, card, std::vector<float>(n, 2.0f)};
  sc.rgba = card;
  for (size_t i = 0; i < n; ++i) {
    sc.depth[i] = mask[i] > 0 ? 1.0f : 2.0f;
    if (mask[i] > 0)
      for (size_t c = 0; c < 4; ++c) sc.rgba[c * n + i] = near_rgba[c];
  }
  const double cn = 12.0 * (1.0 - 2.0) / 1.0;
  auto truth = two_plane_truth(card_only, mask, {near_rgba[0], near_rgba[1], near_rgba[2], near_rgba[3]}, cn);
  // Foreground region: card pixels that the blurred disc partly covers (outside the disc).
  double err[2] = {0, 0};
  size_t count = 0;
  for (int m = 0; m < 2; ++m) {
    auto s = settings(m == 0 ? "isg" : "layered", 12.0, 2.0, 12);
    auto g = run_gpu(ctx(), sc, s);
    double se = 0;
    count = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        size_t i = size_t(y) * w + x;
        double r = std::hypot(x - 40.0, y - 32.0);
        if (r < 16.0 || r > 16.0 + std::abs(cn)) continue;
        ++count;
        for (size_t c = 0; c < 3; ++c) se += std::pow(double(g.out[c * n + i]) - truth[c * n + i], 2);
      }
    err[m] = std::sqrt(se / double(3 * count));
  }
  std::printf("foreground-over-in-focus RMSE (%zu px): isg %.4f, layered %.4f\n", count, err[0], err[1]);
  EXPECT_LT(err[1], 0.8 * err[0]);
}

namespace {
struct RegionErr {
  double lin[3] = {0, 0, 0}, clamped[3] = {0, 0, 0};
  size_t count[3] = {0, 0, 0};
};
// Regions of the dof case from the pinhole CoC: 0 foreground (near pixels, c <= −1, and every
// pixel their CoC reaches), 1 in focus (|c| < 1, outside the foreground), 2 background (the rest).
std::vector<int> case_regions(const std::vector<float>& coc, int w, int h) {
  std::vector<int> reg(coc.size(), 2);
  for (size_t i = 0; i < coc.size(); ++i)
    if (std::abs(coc[i]) < 1.0f) reg[i] = 1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float c = coc[size_t(y) * w + x];
      if (c > -1.0f) continue;
      int r = int(std::ceil(-c)) + 1;
      for (int v = std::max(0, y - r); v <= std::min(h - 1, y + r); ++v)
        for (int u = std::max(0, x - r); u <= std::min(w - 1, x + r); ++u)
          if ((u - x) * (u - x) + (v - y) * (v - y) <= (-c + 1) * (-c + 1)) reg[size_t(v) * w + u] = 0;
    }
  return reg;
}
RegionErr region_rmse(const isg::io::Image& a, const isg::io::Image& ref, const std::vector<int>& reg) {
  RegionErr e;
  for (const char* ch : {"R", "G", "B"}) {
    const auto& A = a.find(ch)->data;
    const auto& B = ref.find(ch)->data;
    for (size_t i = 0; i < A.size(); ++i) {
      double d = double(A[i]) - B[i];
      double dc = std::min(double(A[i]), 1.0) - std::min(double(B[i]), 1.0);
      e.lin[reg[i]] += d * d;
      e.clamped[reg[i]] += dc * dc;
      ++e.count[reg[i]];
    }
  }
  for (int r = 0; r < 3; ++r) {
    e.lin[r] = std::sqrt(e.lin[r] / double(std::max<size_t>(e.count[r], 1)));
    e.clamped[r] = std::sqrt(e.clamped[r] / double(std::max<size_t>(e.count[r], 1)));
  }
  return e;
}
}  // namespace

TEST_F(GpuTest, DofSharedCaseLayeredBeatsIsgInForeground) {
  auto dir = isg::test::shared_case("dof");
  if (dir.empty()) GTEST_SKIP() << "no ../shared/cases/dof";
  auto ref = isg::io::read_exr(dir / "ref" / "beauty.exr");
  std::vector<int> samples = {64};
  if (const char* env = std::getenv("ISG_DOF_REPORT_SAMPLES")) {  // e.g. "16,64,256"
    samples.clear();
    std::stringstream ss(env);
    for (std::string t; std::getline(ss, t, ',');) samples.push_back(std::stoi(t));
  }
  std::vector<int> reg;
  auto print = [](const char* what, const RegionErr& e) {
    std::printf("%-16s fg %.5f / %.5f   in-focus %.5f / %.5f   bg %.5f / %.5f   (linear / clamped at 1; %zu %zu %zu px)\n",
                what, e.lin[0], e.clamped[0], e.lin[1], e.clamped[1], e.lin[2], e.clamped[2],
                e.count[0] / 3, e.count[1] / 3, e.count[2] / 3);
  };
  for (int spp : samples) {
    RegionErr errs[2];
    for (int m = 0; m < 2; ++m) {
      isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
      job.params.set_text("dof.method", m == 0 ? "isg" : "layered", "test");
      job.params.set_text("dof.samples", std::to_string(spp), "test");
      auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
      auto pinhole = f.img;
      auto st = isg::run::process_frame(ctx(), job, f);
      ASSERT_NE(f.img.find("dof.coc"), nullptr);
      if (reg.empty()) {
        reg = case_regions(f.img.find("dof.coc")->data, f.img.width, f.img.height);
        print("pinhole", region_rmse(pinhole, ref, reg));
      }
      errs[m] = region_rmse(f.img, ref, reg);
      char label[64];
      std::snprintf(label, sizeof label, "%s %d spp", m == 0 ? "isg" : "layered", spp);
      print(label, errs[m]);
      std::printf("%-16s GPU %.1f ms, cheap tiles %.1f%%\n", label, st.gpu_ms(), 100 * st.report("dof")->get("cheap"));
    }
    // Clamped at 1 (the case README's second metric): the linear RMSE is ruled by the 8 emitters
    // (values near 40) behind the foreground's halo.
    EXPECT_LT(errs[1].clamped[0], errs[0].clamped[0]) << spp << " spp";
  }
}

// isg-synth dof (85 mm f/1.4; the thin-lens reference of the AOV beauty's shading, so shadows
// and reflections stay as rendered): per region against ref/dof.exr.
TEST_F(GpuTest, DofSynthRegions) {
  const auto dir = isg::test::synth_case({"dof"}, "dof-synth");
  const auto ref = isg::io::read_exr(dir / "ref" / "dof.exr");
  std::vector<int> reg;
  RegionErr errs[3];  // pinhole, isg, layered
  for (int m = 1; m < 3; ++m) {
    isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
    job.params.set_text("dof.method", m == 1 ? "isg" : "layered", "test");
    job.params.set_text("shadows.method", "hard", "test");
    job.params.set_text("reflections.method", "none", "test");
    // 256 samples: at 64, layered's near/far split is noisier than isg's single gather and
    // the two are level in the foreground (0.0124 vs 0.0105); at 256 layered's better
    // occlusion shows (0.0093 vs 0.0105).
    job.params.set_text("dof.samples", "256", "test");
    auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
    auto pinhole = f.img;
    isg::run::process_frame(ctx(), job, f);
    if (reg.empty()) {
      reg = case_regions(f.img.find("dof.coc")->data, f.img.width, f.img.height);
      errs[0] = region_rmse(pinhole, ref, reg);
    }
    errs[m] = region_rmse(f.img, ref, reg);
  }
  const char* names[3] = {"pinhole", "isg", "layered"};
  for (int m = 0; m < 3; ++m)
    std::printf("synth dof %-8s fg %.4f / %.4f  in-focus %.4f / %.4f  bg %.4f / %.4f (linear / clamped; %zu %zu %zu px)\n",
                names[m], errs[m].lin[0], errs[m].clamped[0], errs[m].lin[1], errs[m].clamped[1],
                errs[m].lin[2], errs[m].clamped[2], errs[m].count[0] / 3, errs[m].count[1] / 3,
                errs[m].count[2] / 3);
  // Bounds measured at 192 x 108, ref 64 spp, 256 samples (clamped at 1): foreground isg 0.0105,
  // layered 0.0093 (pinhole 0.0425); background 0.0538 / 0.0520 (pinhole 0.0955). In focus all
  // three sit at 0.0176: the reference's noise and the 1-sample AOVs' aliasing, which no blur
  // removes; the methods must leave it sharp, not make it worse.
  EXPECT_LT(errs[1].clamped[0], 0.013);
  EXPECT_LT(errs[2].clamped[0], 0.011);
  EXPECT_LT(errs[1].clamped[2], 0.065);
  EXPECT_LT(errs[2].clamped[2], 0.065);
  for (int m = 1; m < 3; ++m) EXPECT_LT(errs[m].clamped[1], 1.02 * errs[0].clamped[1]) << m;
  EXPECT_LT(errs[2].clamped[0], errs[1].clamped[0]);  // layered beats isg in the foreground
}
