// Soft shadows, method isg (paper §3.1): the GPU passes against the C++ double reference, a
// parallel-planes case with a closed-form penumbra, and the shared Blender case `contact`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "effects/params.h"
#include "effects/shadows/instance.h"
#include "effects/shadows/isg.h"
#include "support/gpu_fixture.h"
#include "support/images.h"
#include "io/image.h"
#include "io/scene.h"
#include "plan/plan.h"
#include "run/job.h"
#include "support/synth_case.h"
#include "synth.h"

namespace fx = isg::effects;
namespace gpu = isg::gpu;

namespace {

constexpr double kPi = std::numbers::pi;

// The soft shadow of a light disk cut by a chord: the share of the receiver's irradiance (at p,
// normal n) from the part of the disk (centre, in-plane axes u and v, radius R) beyond the chord
// at c along u, which is what a renderer's soft shadow is (each light point weighed by the
// irradiance it gives p: the receiver's cosine, the emitter's, the inverse square), by quadrature
// in double (isg-synth's, tested there against a sum over the disk).
double disk_beyond_chord(const double p[3], const double n[3], const double centre[3], const double u[3],
                         const double v[3], double R, double c) {
  using isg::synth::Vec3;
  auto V = [](const double a[3]) { return Vec3{a[0], a[1], a[2]}; };
  return isg::synth::disk_irradiance_beyond_chord(V(p), V(n), V(centre), V(u), V(v), R, c);
}

// The soft shadow at p (normal n) of a sphere light (centre L, radius r: its disk facing p) cut
// by a plane through p with unit normal m (a blocker's edge and p span it): the chord it cuts
// from the disk, on the side of the light's centre where lit (p sees the centre), else the other.
// The irradiance-weighted share, or with `uniform` the plain fraction of the disk.
double sphere_beyond_plane(const double p[3], const double n[3], const double L[3], double r, const double m[3],
                           bool lit, bool uniform = false) {
  const double d[3] = {L[0] - p[0], L[1] - p[1], L[2] - p[2]}, D = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const double wl[3] = {d[0] / D, d[1] / D, d[2] / D}, delta = m[0] * d[0] + m[1] * d[1] + m[2] * d[2];
  // u: m projected into the disk (across the chord), v along the chord; the chord at
  // −δ / |m − (m·wl) wl| along u, δ the centre's distance from the plane.
  const double mw = delta / D, mu = std::sqrt(1.0 - mw * mw);
  double u[3] = {(m[0] - mw * wl[0]) / mu, (m[1] - mw * wl[1]) / mu, (m[2] - mw * wl[2]) / mu};
  double c = -delta / mu;
  if (lit != (c < 0.0)) {  // the visible side holds the centre (u·0 > c) where p is lit
    for (double& e : u) e = -e;
    c = -c;
  }
  const double v[3] = {wl[1] * u[2] - wl[2] * u[1], wl[2] * u[0] - wl[0] * u[2], wl[0] * u[1] - wl[1] * u[0]};
  return uniform ? isg::synth::disk_visible_fraction(c, r) : disk_beyond_chord(p, n, L, u, v, r, c);
}

// A camera at (cx, cy, cam_z) looking straight down (−Z, +Y up) over a w x h frame that spans
// cx ± half, cy ± half on the floor z = 0; the floor position of pixel (x, y).
struct DownView {
  int w = 128, h = 128;
  double cx = 0, cy = 0, cam_z = 8.0, half = 2.4;
  isg::io::Camera camera() const {
    isg::io::Camera cam;
    cam.world_to_camera = isg::io::identity4();
    cam.world_to_camera[3] = -cx;
    cam.world_to_camera[7] = -cy;
    cam.world_to_camera[11] = -cam_z;
    cam.yfov_deg = 2.0 * std::atan(half / cam_z) * 180.0 / kPi;
    cam.width = w;
    cam.height = h;
    return cam;
  }
  double px(int x) const { return cx + (x + 0.5 - 0.5 * w) / (0.5 * w) * half; }
  double py(int y) const { return cy - (y + 0.5 - 0.5 * h) / (0.5 * h) * half; }
};
isg::io::Light sphere_light(const double L[3], double r) {
  isg::io::Light light;
  light.name = "key";
  light.type = isg::io::LightType::sphere;
  light.position = {L[0], L[1], L[2]};
  light.radius = r;
  return light;
}

// A w x h frame of foreground receivers, every pixel lit (L.shadow 1, no occluder); positions
// sized for the caller to fill when with_position, else none.
fx::ShadowInputs lit_frame(int w, int h, bool with_position) {
  fx::ShadowInputs in;
  in.w = w;
  in.h = h;
  const size_t n = size_t(w) * h;
  in.shadow.assign(n, 1.0f);
  in.occluder.assign(n, 0.0f);
  in.fg.assign(n, 1.0f);
  if (with_position) in.position.assign(3 * n, 0.0f);
  return in;
}

// lit_frame of the floor z = 0 as `view` sees it (P at each pixel's floor position).
fx::ShadowInputs floor_frame(const DownView& view) {
  fx::ShadowInputs in = lit_frame(view.w, view.h, true);
  const size_t n = size_t(view.w) * view.h;
  for (int y = 0; y < view.h; ++y)
    for (int x = 0; x < view.w; ++x) {
      in.position[size_t(y) * view.w + x] = float(view.px(x));
      in.position[n + size_t(y) * view.w + x] = float(view.py(y));
    }
  return in;
}

// Parallel planes: a disk light of radius R at height H facing down over the receiver z = 0,
// an occluding half-plane x' < 0 at height h (invisible to the camera), the camera at height 6
// looking straight down. A light point (lx, ly, H) is visible from (x, y, 0) iff the segment
// crosses z = h at x + (h/H)(lx − x) ≥ 0, i.e. lx ≥ c = −x(H − h)/h: the soft shadow is the
// circular segment {lx ≥ c}'s share of the irradiance (disk_beyond_chord).
// The light may stand Ly to the side along the edge (y): the visibility test does not involve ly,
// so the chord stands, and the light reaches the receiver at cos θ_i = H / sqrt(H² + Ly²).
//
// sun_deg > 0: a sun overhead instead (issue 52), of that full angle: a direction (tx, ty, 1) is
// seen past the edge iff x + tx·h ≥ 0, so the soft shadow is the part of the sun's disk of
// directions (radius tan(sun_deg/2) in tan space) beyond tx = −x/h; L.occluder is h.
struct Planes {
  int w = 128, h = 128;
  double R = 0.5, H = 4.0, hocc = 1.0, cam_z = 6.0, half_extent = 1.2, Ly = 0.0;
  double sun_deg = 0.0;
  isg::io::Camera camera() const {
    isg::io::Camera c;
    c.world_to_camera = isg::io::identity4();
    c.world_to_camera[11] = -cam_z;  // camera at (0, 0, cam_z) looking down −Z, +Y up
    c.yfov_deg = 2.0 * std::atan(half_extent / cam_z) * 180.0 / kPi;
    c.width = w;
    c.height = h;
    return c;
  }
  isg::io::Light light() const {
    isg::io::Light l;
    l.name = "key";
    if (sun_deg > 0.0) {
      l.type = isg::io::LightType::sun;
      l.direction = {0, 0, 1};
      l.angle_deg = sun_deg;
      return l;
    }
    l.type = isg::io::LightType::disk;
    l.position = {0, Ly, H};
    l.radius = R;
    l.normal = {0, 0, -1};
    return l;
  }
  double wx(int x) const { return (x + 0.5 - 0.5 * w) / (0.5 * w) * half_extent; }
  double wy(int y) const { return -(y + 0.5 - 0.5 * h) / (0.5 * h) * half_extent; }
  double exact(int x, int y) const { return exact_at(wx(x), wy(y)); }
  double exact_at(double px, double py) const {
    if (sun_deg > 0.0) {  // the circular segment beyond the chord, of the whole disk
      const double t = std::tan(sun_deg * kPi / 360.0), d = std::clamp(-px / hocc / t, -1.0, 1.0);
      return (std::acos(d) - d * std::sqrt(1.0 - d * d)) / kPi;
    }
    const double p[3] = {px, py, 0.0}, n[3] = {0.0, 0.0, 1.0}, centre[3] = {0.0, Ly, H}, u[3] = {1.0, 0.0, 0.0},
                 v[3] = {0.0, 1.0, 0.0};
    return disk_beyond_chord(p, n, centre, u, v, R, -px * (H - hocc) / hocc);
  }
  fx::ShadowInputs inputs(bool with_position = true) const {
    fx::ShadowInputs in = lit_frame(w, h, with_position);
    const size_t n = size_t(w) * h;
    if (!with_position) in.depth.assign(n, float(cam_z));
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        const double px = wx(x), py = wy(y);
        const bool lit = px > 0.0;
        in.shadow[i] = lit ? 1.0f : 0.0f;
        const double to_occ = sun_deg > 0.0 ? hocc : std::sqrt(px * px + (py - Ly) * (py - Ly) + H * H) * hocc / H;
        in.occluder[i] = lit ? 0.0f : float(to_occ);
        if (with_position) {
          in.position[i] = float(px);
          in.position[n + i] = float(py);
          in.position[2 * n + i] = 0.0f;
        }
      }
    }
    return in;
  }
  fx::ShadowSettings settings(int search, int gather) const {
    auto p = fx::default_params();
    p.set_text("shadows.search_samples", std::to_string(search), "test");
    p.set_text("shadows.gather_samples", std::to_string(gather), "test");
    return fx::shadow_settings(light(), camera(), 4.0, p, h);
  }
  double rmse(const std::vector<float>& soft) const {
    double e = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double d = soft[size_t(y) * w + x] - exact(x, y);
        e += d * d;
      }
    return std::sqrt(e / (double(w) * h));
  }
  double hard_rmse(const fx::ShadowInputs& in) const { return rmse(in.shadow); }
};

class ShadowsIsg : public isg::test::GpuTest {
 protected:
  // part_lanes: as fx::ShadowsIsgPass's (0: by the device).
  std::vector<float> run_gpu(const fx::ShadowInputs& in, const fx::ShadowSettings& s,
                             fx::ShadowIsgStats* stats = nullptr, uint32_t part_lanes = 0) {
    const uint32_t w = uint32_t(in.w), h = uint32_t(in.h);
    const size_t n = size_t(w) * h;
    const bool has_p = !in.position.empty();
    gpu::Buffer shadow(ctx(), n * 4, "shadow"), occ(ctx(), n * 4, "occluder"),
        geo(ctx(), (has_p ? 3 : 1) * n * 4, "geo"), fg(ctx(), n * 4, "fg"),
        tiles(ctx(), fx::shadows_isg_tiles_words(w, h) * 4, "tiles"), soft(ctx(), n * 4, "soft"),
        pack(ctx(), 4 * n * 4, "pack");
    shadow.upload(std::span<const float>(in.shadow));
    occ.upload(std::span<const float>(in.occluder));
    geo.upload(std::span<const float>(has_p ? in.position : in.depth));
    fg.upload(std::span<const float>(in.fg));
    fx::ShadowsIsgPass pass(ctx(), part_lanes);
    gpu::Sequence seq(ctx());
    pass.record(seq, s, shadow, occ, geo, has_p, fg, tiles, pack, soft, w, h, "shadows.isg");
    seq.submit();
    if (stats) *stats = fx::ShadowsIsgPass::stats(tiles, w, h);
    return soft.download_as<float>(n);
  }
};

double max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(double(a[i]) - double(b[i])));
  return m;
}

}  // namespace

// Each setting that shadows.isg compiles in (a specialization constant) is a pipeline of its own:
// every one runs here, on 97x83 (partial tiles) as well as 96x80.
TEST_F(ShadowsIsg, GpuMatchesReference) {
  struct Case {
    int w, h;
    bool with_p, sphere, rotate, search_reach, tile_skip;
  };
  std::vector<Case> cases;
  for (bool with_p : {true, false})
    for (bool sphere : {false, true}) cases.push_back({96, 80, with_p, sphere, true, true, true});
  for (int off = 0; off < 4; ++off)
    cases.push_back({97, 83, true, false, off != 1, off != 2, off != 3});
  for (const Case& c : cases) {
    Planes pl;
    pl.w = c.w;
    pl.h = c.h;
    const bool with_p = c.with_p, sphere = c.sphere;
    auto in = pl.inputs(with_p);
    // A background patch and a sphere-like light to exercise both cross-sections.
    for (int y = 10; y < 20; ++y)
      for (int x = 40; x < 56; ++x) in.fg[size_t(y) * in.w + x] = 0.0f;
    auto s = pl.settings(25, 49);
    s.oriented = !sphere;
    s.rotate = c.rotate;
    s.search_reach = c.search_reach;
    s.tile_skip = c.tile_skip;
    fx::ShadowIsgStats st_ref, st_gpu;
    auto ref = fx::shadows_isg_reference(in, s, &st_ref);
    auto got = run_gpu(in, s, &st_gpu);
    const double diff = max_abs_diff(ref, got);
    std::printf("GPU vs reference (%dx%d, P %d, sphere %d, rotate %d, reach %d, tile skip %d): "
                "max abs diff %.2e\n", c.w, c.h, int(with_p), int(sphere), int(c.rotate),
                int(c.search_reach), int(c.tile_skip), diff);
    EXPECT_LT(diff, 1e-3) << c.w << "x" << c.h << " position " << with_p << " sphere "
                          << sphere << " rotate " << c.rotate << " reach " << c.search_reach
                          << " tile skip " << c.tile_skip;
    EXPECT_EQ(st_ref.full_pixels, st_gpu.full_pixels);
    EXPECT_EQ(st_ref.clamped_pixels, st_gpu.clamped_pixels);
    EXPECT_NEAR(double(st_ref.searches), double(st_gpu.searches), 0.01 * double(st_ref.searches));
    EXPECT_NEAR(double(st_ref.gathers), double(st_gpu.gathers), 0.01 * double(st_ref.gathers));
    EXPECT_NEAR(double(st_ref.borrowed), double(st_gpu.borrowed), 0.01 * double(st_ref.borrowed));
    EXPECT_NEAR(st_ref.skipped_fraction, st_gpu.skipped_fraction, 1e-9);
    // shadows.isg.list dispatched every tile that did not take the cheap path.
    EXPECT_GE(st_gpu.dispatched_fraction, 1.0 - st_gpu.skipped_fraction - 1e-9);
    EXPECT_LE(st_gpu.dispatched_fraction, 1.0);
    EXPECT_FLOAT_EQ(float(st_ref.d_max), float(st_gpu.d_max));
    // The quads' and the own list's sums a lane each (CPU devices) or a lane a part (GPUs): the
    // same taps added in another order, so within float rounding (a part left out moves a pixel
    // by far more).
    for (uint32_t lanes : {1u, 4u, 8u}) {
      if (lanes > ctx().info().subgroup_size) continue;
      fx::ShadowIsgStats st_lanes;
      const auto by_lanes = run_gpu(in, s, &st_lanes, lanes);
      EXPECT_LT(max_abs_diff(got, by_lanes), 1e-6) << lanes << " lanes a sum";
      EXPECT_EQ(st_lanes.searches, st_gpu.searches) << lanes << " lanes a sum";
      EXPECT_EQ(st_lanes.gathers, st_gpu.gathers) << lanes << " lanes a sum";
      EXPECT_EQ(st_lanes.clamped_pixels, st_gpu.clamped_pixels) << lanes << " lanes a sum";
      EXPECT_EQ(st_lanes.borrowed, st_gpu.borrowed) << lanes << " lanes a sum";
    }
  }
}

// Wide penumbrae (R_g >= SHADOWS_ISG_REUSE_RADIUS, issue 18): the search runs once per 2x2 quad
// and most pixels take their gather bilinearly from the quads' representatives. The GPU matches
// the double reference on that path, and both match the closed form.
TEST_F(ShadowsIsg, WidePenumbraeReuseTheQuadsGathers) {
  Planes pl;
  pl.w = pl.h = 256;
  pl.R = 1.0;  // R_g about 36 px
  for (bool with_p : {true, false}) {
    auto in = pl.inputs(with_p);
    auto s = pl.settings(25, 49);
    fx::ShadowIsgStats st_ref, st_gpu;
    auto ref = fx::shadows_isg_reference(in, s, &st_ref);
    auto got = run_gpu(in, s, &st_gpu);
    const double diff = max_abs_diff(ref, got), e = pl.rmse(got), hard = pl.hard_rmse(in);
    std::printf("wide penumbrae (P %d): %llu pixels, %llu searches, %llu gathers; GPU vs reference %.2e; "
                "RMSE %.5f (hard %.5f)\n", int(with_p), (unsigned long long)st_gpu.full_pixels,
                (unsigned long long)st_gpu.searches, (unsigned long long)st_gpu.gathers, diff, e, hard);
    EXPECT_LT(diff, 1e-3) << "position " << with_p;
    EXPECT_LT(st_gpu.searches, st_gpu.full_pixels / 3);
    EXPECT_LT(st_gpu.gathers, st_gpu.full_pixels / 3);
    EXPECT_NEAR(double(st_ref.gathers), double(st_gpu.gathers), 0.01 * double(st_ref.gathers));
    // Measured 0.01359 (hard 0.1350; 0.01363 before the quads that miss borrowed their
    // neighbours' occluders; against the uniform chord, before the gather weighed its taps by
    // irradiance, 0.01340, and 0.01351 with every pixel gathering for itself).
    EXPECT_LT(e, 0.016);
  }
}

// A wide penumbra searched with few samples (issue 19): a quad whose search misses the shadow
// takes the mean occluder distance of the quads around it that found one
// (SHADOWS_ISG_BORROW_MIN), instead of keeping the hard shadow, a lit speck in the penumbra. The
// GPU matches the double reference on that path, and both keep near the closed form.
TEST_F(ShadowsIsg, QuadsThatMissBorrowTheirNeighboursOccluders) {
  Planes pl;
  pl.w = pl.h = 256;
  pl.R = 1.0;  // R_g about 36 px
  auto in = pl.inputs(true);
  for (int search : {4, 25}) {
    auto s = pl.settings(search, 49);
    fx::ShadowIsgStats st_ref, st_gpu;
    auto ref = fx::shadows_isg_reference(in, s, &st_ref);
    auto got = run_gpu(in, s, &st_gpu);
    const double diff = max_abs_diff(ref, got), e = pl.rmse(got), hard = pl.hard_rmse(in);
    std::printf("%d search samples: %llu of %llu pixels borrowed (reference %llu); GPU vs reference "
                "%.2e; RMSE %.5f (hard %.5f)\n", search, (unsigned long long)st_gpu.borrowed,
                (unsigned long long)st_gpu.full_pixels, (unsigned long long)st_ref.borrowed, diff, e, hard);
    EXPECT_LT(diff, 1e-3) << search;
    EXPECT_NEAR(double(st_ref.borrowed), double(st_gpu.borrowed), 0.01 * double(st_ref.borrowed));
    // Measured: 4 samples 224 pixels borrowed, RMSE 0.02688 (0.02944 with none borrowed:
    // SHADOWS_ISG_BORROW_MIN 100); 25 samples 384, 0.01359 (0.01363).
    if (search == 4) {
      EXPECT_GT(st_gpu.borrowed, st_gpu.full_pixels / 200);
      EXPECT_LT(e, 0.0285);
    }
  }
}

TEST_F(ShadowsIsg, ParallelPlanesClosedForm) {
  Planes pl;
  auto in = pl.inputs();
  fx::ShadowIsgStats st;
  auto soft = run_gpu(in, pl.settings(25, 49), &st);
  const double e = pl.rmse(soft), hard = pl.hard_rmse(in);
  std::printf("parallel planes: RMSE %.5f (hard %.5f), %.1f%% tiles skipped, %.1f%% dispatched\n",
              e, hard, 100 * st.skipped_fraction, 100 * st.dispatched_fraction);
  EXPECT_LT(e, 0.008);  // measured 0.00552 (25 search, 49 gather samples; hard: 0.0966)
  EXPECT_EQ(st.clamped_pixels, 0u);
  EXPECT_GT(st.skipped_fraction, 0.3);  // tiles far from the edge keep L.shadow
  // ... and shadows.isg is not dispatched on most of them (shadows.isg.list); none skipped wrongly.
  EXPECT_GE(st.dispatched_fraction, 1.0 - st.skipped_fraction - 1e-9);
  EXPECT_LT(st.dispatched_fraction, 1.0 - 0.5 * st.skipped_fraction);
}

// Light at 18 degrees above the receivers, beside the edge (issue 19): the penumbra across the
// edge keeps its width while the footprint on the receiver is stretched along the light (1 / cos
// θ_i = 3.2). The gather's samples go to an ellipse (the stretch capped at
// SHADOWS_ISG_MAX_STRETCH), not a disk of the long radius, most of which the cross-section
// weight would discard: the error stays that of the light overhead.
TEST_F(ShadowsIsg, LowLightBesideTheEdgeKeepsTheClosedForm) {
  Planes top, low;
  low.Ly = 12.0;
  auto in = low.inputs();
  const auto s = low.settings(25, 49);
  auto soft = run_gpu(in, s);
  EXPECT_LT(max_abs_diff(fx::shadows_isg_reference(in, s), soft), 1e-3);
  const double e = low.rmse(soft), e_top = top.rmse(run_gpu(top.inputs(), top.settings(25, 49)));
  std::printf("parallel planes, light 18 deg above them: RMSE %.5f (overhead %.5f, hard %.5f)\n", e, e_top,
              low.hard_rmse(in));
  EXPECT_LT(e, 1.5 * e_top);  // measured 0.00680 against 0.00552 (a disk of the long radius: 0.0245)
}

// A sun (issue 52): isg takes it as a sphere light kSunDistance scene radii away that subtends
// its angle (settings.cpp's light_centre_for), so eq. 8's penumbra is tan(angle/2)·d. A 14° sun
// (tan 0.123: the penumbra 0.25 wide, 13 pixels) over the parallel planes: the GPU against the
// reference, and the closed form of the sun's disk of directions.
TEST_F(ShadowsIsg, SunParallelPlanesClosedForm) {
  Planes pl;
  pl.sun_deg = 14.0;
  const auto in = pl.inputs();
  const auto s = pl.settings(25, 49);
  EXPECT_NEAR(s.light_size / std::hypot(s.light[0], s.light[1], s.light[2] - pl.cam_z),
              std::tan(7.0 * kPi / 180.0), 1e-9);
  fx::ShadowIsgStats st;
  const auto soft = run_gpu(in, s, &st);
  const double d = max_abs_diff(fx::shadows_isg_reference(in, s), soft);
  const double e = pl.rmse(soft), hard = pl.hard_rmse(in);
  std::printf("parallel planes under a 14 degree sun: RMSE %.5f (hard %.5f), GPU against reference "
              "%.2g, %.1f%% tiles skipped\n", e, hard, d, 100 * st.skipped_fraction);
  EXPECT_LT(d, 1e-3);
  EXPECT_LT(e, 0.1 * hard);
  EXPECT_GT(st.skipped_fraction, 0.3);
}

TEST_F(ShadowsIsg, ErrorFallsAsSamplesGrow) {
  Planes pl;
  auto in = pl.inputs();
  double prev = 1e9;
  for (int n : {9, 25, 81}) {
    const double e = pl.rmse(run_gpu(in, pl.settings(n, n)));
    std::printf("parallel planes %d x %d samples: RMSE %.5f\n", n, n, e);
    EXPECT_LT(e, prev * 1.02) << n;
    prev = e;
  }
}

TEST_F(ShadowsIsg, LitSideGetsOuterPenumbraAndBackgroundIsUntouched) {
  Planes pl;
  auto in = pl.inputs();
  // Background: a band on the lit side holding arbitrary values; never gathered from.
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < pl.w; ++x) {
      const size_t i = size_t(y) * pl.w + x;
      in.fg[i] = 0.0f;
      in.shadow[i] = 0.25f;
    }
  auto soft = run_gpu(in, pl.settings(25, 49));
  int outer = 0;
  for (int y = 8; y < pl.h; ++y)
    for (int x = 0; x < pl.w; ++x) {
      const size_t i = size_t(y) * pl.w + x;
      if (in.shadow[i] == 1.0f && soft[i] < 0.99f) ++outer;
    }
  EXPECT_GT(outer, 4 * (pl.h - 8));  // several lit pixels per row lie in the outer penumbra
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < pl.w; ++x) EXPECT_EQ(soft[size_t(y) * pl.w + x], 0.25f);
  // The rows next to the background match the rows further down: no background in the gather.
  EXPECT_NEAR(soft[size_t(8) * pl.w + pl.w / 2], soft[size_t(pl.h / 2) * pl.w + pl.w / 2], 0.1);
}

TEST(ShadowsIsgPlan, SaysWhyItCannotRun) {
  isg::io::Roles roles;
  for (const char* r : {"beauty", "depth", "key.shadow", "key.direct", "key.occluder"})
    roles.found[r] = isg::io::RoleBinding{r, {{r}}, "test"};
  roles.lights = {"key"};
  auto p = fx::default_params();
  p.set_text("shadows.method", "isg", "test");
  isg::io::Scene scene;
  Planes pl;
  scene.camera = pl.camera();
  // Without what isg needs the hard shadow is kept (method hard) and the status says why.
  auto plan = isg::plan::make_plan(roles, scene, p, 64, 64);  // no scene entry for key
  ASSERT_FALSE(plan.effects.empty());
  EXPECT_TRUE(plan.effects[0].runs);
  EXPECT_EQ(plan.effects[0].method, "hard");
  EXPECT_NE(plan.effects[0].why.find("no scene entry"), std::string::npos) << plan.effects[0].why;
  auto l = pl.light();
  l.type = isg::io::LightType::point;
  scene.lights = {l};
  plan = isg::plan::make_plan(roles, scene, p, 64, 64);
  EXPECT_FALSE(plan.effects[0].runs);
  EXPECT_NE(plan.effects[0].why.find("point light"), std::string::npos) << plan.effects[0].why;
  scene.lights = {pl.light()};
  plan = isg::plan::make_plan(roles, scene, p, 64, 64);
  EXPECT_TRUE(plan.effects[0].runs) << plan.effects[0].why;
  EXPECT_EQ(plan.effects[0].method, "isg");
  const auto* inst = plan.instance_as<fx::ShadowsInstance>("shadows[key]");
  EXPECT_TRUE(inst && inst->isg.has_value());
  roles.found.erase("key.occluder");
  plan = isg::plan::make_plan(roles, scene, p, 64, 64);
  EXPECT_EQ(plan.effects[0].method, "hard");
  EXPECT_NE(plan.effects[0].why.find("key.occluder"), std::string::npos) << plan.effects[0].why;
}

TEST_F(ShadowsIsg, ContactCaseHalvesTheHardShadowError) {
  auto dir = isg::test::shared_case("contact");
  if (dir.empty()) GTEST_SKIP() << "no ../shared/cases/contact";
  auto ref = isg::io::read_exr(dir / "ref" / "softshadow_key.exr");
  isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
  job.params.set_text("shadows.method", "isg", "test");
  auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
  auto st = isg::run::process_frame(ctx(), job, f);
  const auto e = isg::test::shadow_error(f.img, ref);
  const double es = e.soft, eh = e.hard;
  const size_t n = e.pixels;
  const auto* r = st.report("shadows[key]");
  ASSERT_TRUE(r);
  std::printf("contact: key.softshadow RMSE %.5f, hard %.5f (mask, %zu px), %.1f%% tiles skipped\n",
              es, eh, n, 100 * r->get("skipped") / r->get("tiles"));
  EXPECT_NEAR(eh, 0.0435, 0.0005);  // the case README's "error of doing nothing"
  EXPECT_LT(es, 0.5 * eh);          // measured 0.0153
}

namespace {

// isg-synth `scene` at 192 x 108 (64 light samples per reference pixel): RMSE over the
// reference's mask of key.softshadow (isg, default settings) and of key.shadow (doing nothing)
// against ref/<ref_file>.
struct SynthShadowError {
  double isg = 0, hard = 0;
};
SynthShadowError synth_shadow_error(isg::gpu::Context& ctx, const std::string& scene,
                                    const std::string& ref_file, int aov_spp = 1) {
  const auto dir = isg::test::synth_case({scene, 192, 108, 64, aov_spp},
                                         "shadows-synth-" + scene + std::to_string(aov_spp));
  const auto ref = isg::io::read_exr(dir / "ref" / ref_file);
  isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
  job.params.set_text("shadows.method", "isg", "test");
  auto f = isg::run::load_frame(job, (dir / "aovs.exr").string());
  isg::run::process_frame(ctx, job, f);
  const auto e = isg::test::shadow_error(f.img, ref);
  return {e.soft, e.hard};
}

}  // namespace

// Ray-traced parallel planes against the closed-form penumbra (the configuration eq. 5 and 8
// are exact for): what is left is sampling and the anti-aliasing of the renderer's hard edge.
TEST_F(ShadowsIsg, SynthParallelPlanesAgainstClosedForm) {
  const auto e = synth_shadow_error(ctx(), "parallel-planes", "softshadow_closed_form.exr");
  std::printf("isg-synth parallel-planes: key.softshadow RMSE %.5f (hard %.5f)\n", e.isg, e.hard);
  EXPECT_LT(e.isg, 0.025);  // measured 0.0145 (hard 0.0948), 25 x 49 samples
  EXPECT_LT(e.isg, 0.2 * e.hard);
}

// The same scene translated 1e5 units from the origin gives the same error (positions are
// made relative to the camera before any float arithmetic).
TEST_F(ShadowsIsg, SynthContactAndFarWorldAgreeWithin5Percent) {
  const auto near = synth_shadow_error(ctx(), "contact", "softshadow_key.exr");
  const auto far = synth_shadow_error(ctx(), "far-world", "softshadow_key.exr");
  std::printf("isg-synth contact RMSE %.5f (hard %.5f), far-world %.5f (hard %.5f)\n", near.isg,
              near.hard, far.isg, far.hard);
  EXPECT_LT(near.isg, 0.5 * near.hard);
  EXPECT_NEAR(far.isg, near.isg, 0.05 * near.isg);
}

// Anti-aliased AOVs (4 samples per pixel, as renderers write them): at silhouettes P is a blend
// of two surfaces and L.shadow a fraction. The estimator must not fall apart there.
TEST_F(ShadowsIsg, SynthAntiAliasedAovs) {
  const auto single = synth_shadow_error(ctx(), "contact", "softshadow_key.exr", 1);
  const auto aa = synth_shadow_error(ctx(), "contact", "softshadow_key.exr", 4);
  std::printf("isg-synth contact RMSE: 1 AOV sample %.5f (hard %.5f), 4 samples %.5f (hard %.5f)\n",
              single.isg, single.hard, aa.isg, aa.hard);
  EXPECT_LT(aa.isg, 0.5 * aa.hard);
  EXPECT_LT(aa.isg, 1.25 * single.isg);
}

// Grazing view: the parallel planes seen by a camera 80° from the receiver's normal, looking
// along the penumbra's gradient, so the penumbra is squeezed on screen. The radii must follow
// the receiver's inclination to stay near the closed form.
TEST_F(ShadowsIsg, GrazingViewKeepsTheClosedForm) {
  Planes pl;
  pl.w = 160;
  pl.h = 120;
  const double th = 80.0 * kPi / 180.0, D = 5.0, sn = std::sin(th), cs = std::cos(th);
  const double E[3] = {-D * sn, 0.0, D * cs};
  // Camera axes (rows of R): right (0,-1,0), up (cos, 0, sin), back -(forward) = (-sin, 0, cos).
  const double R[3][3] = {{0, -1, 0}, {cs, 0, sn}, {-sn, 0, cs}};
  isg::io::Camera cam;
  cam.yfov_deg = 30.0;
  cam.width = pl.w;
  cam.height = pl.h;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) cam.world_to_camera[size_t(i * 4 + j)] = R[i][j];
    cam.world_to_camera[size_t(i * 4 + 3)] = -(R[i][0] * E[0] + R[i][1] * E[1] + R[i][2] * E[2]);
  }
  const double f_px = 0.5 * pl.h / std::tan(cam.yfov_deg * kPi / 360.0);
  fx::ShadowInputs in = lit_frame(pl.w, pl.h, true);
  const size_t n = size_t(pl.w) * pl.h;
  in.fg.assign(n, 0.0f);  // background where the view misses the receiver
  std::vector<double> wxs(n, 0.0), wys(n, 0.0);
  for (int y = 0; y < pl.h; ++y)
    for (int x = 0; x < pl.w; ++x) {
      const size_t i = size_t(y) * pl.w + x;
      const double dc[3] = {(x + 0.5 - 0.5 * pl.w) / f_px, -(y + 0.5 - 0.5 * pl.h) / f_px, -1.0};
      double dw[3];
      for (int k = 0; k < 3; ++k) dw[k] = R[0][k] * dc[0] + R[1][k] * dc[1] + R[2][k] * dc[2];
      if (dw[2] >= 0) continue;
      const double t = -E[2] / dw[2], px = E[0] + t * dw[0], py = E[1] + t * dw[1];
      if (std::abs(px) > 3.0 || std::abs(py) > 3.0) continue;
      in.fg[i] = 1.0f;
      in.position[i] = float(px);
      in.position[n + i] = float(py);
      wxs[i] = px;
      wys[i] = py;
      const bool lit = px > 0.0;
      in.shadow[i] = lit ? 1.0f : 0.0f;
      in.occluder[i] = lit ? 0.0f : float(std::sqrt(px * px + py * py + pl.H * pl.H) * pl.hocc / pl.H);
    }
  auto p = fx::default_params();
  auto s = fx::shadow_settings(pl.light(), cam, 4.0, p, pl.h);
  auto soft = run_gpu(in, s);
  auto ref = fx::shadows_isg_reference(in, s);
  EXPECT_LT(max_abs_diff(ref, soft), 1e-3);
  double es = 0, eh = 0;
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    if (in.fg[i] == 0.0f) continue;
    const double want = pl.exact_at(wxs[i], wys[i]);
    es += std::pow(soft[i] - want, 2);
    eh += std::pow(in.shadow[i] - want, 2);
    ++m;
  }
  es = std::sqrt(es / double(m));
  eh = std::sqrt(eh / double(m));
  std::printf("grazing view (80 deg): RMSE %.5f, hard %.5f over %zu px\n", es, eh, m);
  EXPECT_LT(es, 0.015);     // measured 0.0096 (hard 0.0431; seen from above: 0.0055)
  EXPECT_LT(es, 0.5 * eh);
}

// An upright blocker under a low sphere light (issue 19): a wall, the half-plane y = 0, x < 0,
// unbounded in height and invisible to the camera, with its vertical edge on the z axis, and a
// sphere light 12 degrees above the receiver beside it. The edge's shadow runs away from the light
// and its penumbra widens with the distance from the edge's foot. A light point Q is hidden from
// p iff the segment p→Q crosses y = 0 at x < 0: the boundary is the plane through p and the z
// axis, a chord of the light's disk (facing p) at δ / sqrt(1 − (δ / |L − p|)²) from its centre,
// δ the centre's distance from that plane (sphere_beyond_plane). Along the long shadow the
// occluder distances grow with
// the distance from the foot, while the occluders themselves (points of the edge) stay about as
// far from each pixel: the search measures them from the pixel.
TEST_F(ShadowsIsg, UprightEdgeUnderALowLightKeepsTheClosedForm) {
  DownView view;
  view.cx = -1.2;
  view.cy = -2.4;
  const int w = view.w, h = view.h;
  const double L[3] = {3.0, 6.0, 1.5}, r = 0.6;
  const auto cam = view.camera();
  const auto light = sphere_light(L, r);
  fx::ShadowInputs in = floor_frame(view);
  const size_t n = size_t(w) * h;
  std::vector<double> exact(n, 1.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double px = view.px(x), py = view.py(y);
      const double dx = L[0] - px, dy = L[1] - py, D = std::sqrt(dx * dx + dy * dy + L[2] * L[2]);
      if (py >= 0.0) continue;  // in front of the wall: lit
      const double s = -py / dy;  // the ray to the light's centre meets y = 0 here
      const bool lit = px + s * dx >= 0.0;
      in.shadow[i] = lit ? 1.0f : 0.0f;
      in.occluder[i] = lit ? 0.0f : float(s * D);
      const double hp = std::sqrt(px * px + py * py), m[3] = {py / hp, -px / hp, 0.0};
      const double pp[3] = {px, py, 0.0}, nz[3] = {0.0, 0.0, 1.0};
      exact[i] = sphere_beyond_plane(pp, nz, L, r, m, lit);
    }
  auto p = fx::default_params();
  const auto st = fx::shadow_settings(light, cam, 4.0, p, h);
  const auto soft = run_gpu(in, st);
  EXPECT_LT(max_abs_diff(fx::shadows_isg_reference(in, st), soft), 1e-3);
  double es = 0, eh = 0;
  for (size_t i = 0; i < n; ++i) {
    es += std::pow(soft[i] - exact[i], 2);
    eh += std::pow(in.shadow[i] - exact[i], 2);
  }
  es = std::sqrt(es / double(n));
  eh = std::sqrt(eh / double(n));
  std::printf("upright edge, light 12 deg above the receiver: RMSE %.5f (hard %.5f)\n", es, eh);
  // Measured 0.0127 (hard 0.0871); 0.0125 before the gather weighed its taps by irradiance, and
  // with each occluder measured from its tap, as before issue 19's fourth stop, 0.0190. The
  // cutting plane holds the receiver's normal here, and the weighted share equals the uniform
  // one (to 1e-14).
  EXPECT_LT(es, 0.015);
  EXPECT_LT(es, 0.2 * eh);
}

// A low wall under a low sphere light (issue 19): the plane x = 0 up to height hw, unbounded
// along y and invisible to the camera, and a sphere light about 26 degrees above the floor
// behind it (scene_radius 10, as the Cycles cases'). A light point Q is hidden from p (x < 0) iff
// the segment p→Q crosses x = 0 under hw: the boundary is the plane through p and the wall's top
// edge, which cuts the light's disk across its vertical, so the visible part is its top, which
// lights the floor more than its bottom: the irradiance-weighted share (what a renderer's soft
// shadow is; sphere_beyond_plane) is up to 0.057 above the uniform fraction of the disk here.
// shadows.isg weighs its gather so, and must be nearer the weighted share than the uniform one.
TEST_F(ShadowsIsg, LowWallKeepsTheIrradianceWeightedShare) {
  DownView view;
  view.cx = -1.0;
  view.half = 1.4;
  const int w = view.w, h = view.h;
  const double L[3] = {3.0, 0.3, 2.0}, r = 0.6, hw = 0.5;
  const auto cam = view.camera();
  const auto light = sphere_light(L, r);
  fx::ShadowInputs in = floor_frame(view);
  const size_t n = size_t(w) * h;
  std::vector<double> weighted(n, 1.0), uniform(n, 1.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double px = view.px(x), py = view.py(y);
      if (px >= 0.0) continue;  // in front of the wall: lit
      const double dx = L[0] - px, dy = L[1] - py, D = std::sqrt(dx * dx + dy * dy + L[2] * L[2]);
      const double s = -px / dx;  // the ray to the light's centre meets x = 0 here, at height s·L_z
      const bool lit = s * L[2] >= hw;
      in.shadow[i] = lit ? 1.0f : 0.0f;
      in.occluder[i] = lit ? 0.0f : float(s * D);
      // The plane through p and the top edge (the line x = 0, z = hw along y).
      const double ml = std::sqrt(hw * hw + px * px), m[3] = {hw / ml, 0.0, px / ml};
      const double pp[3] = {px, py, 0.0}, nz[3] = {0.0, 0.0, 1.0};
      weighted[i] = sphere_beyond_plane(pp, nz, L, r, m, lit);
      uniform[i] = sphere_beyond_plane(pp, nz, L, r, m, lit, true);
    }
  auto p = fx::default_params();
  const auto st = fx::shadow_settings(light, cam, 10.0, p, h);
  const auto soft = run_gpu(in, st);
  EXPECT_LT(max_abs_diff(fx::shadows_isg_reference(in, st), soft), 1e-3);
  double ew = 0, eu = 0, eh = 0, gap = 0;
  for (size_t i = 0; i < n; ++i) {
    ew += std::pow(soft[i] - weighted[i], 2);
    eu += std::pow(soft[i] - uniform[i], 2);
    eh += std::pow(in.shadow[i] - weighted[i], 2);
    gap = std::max(gap, std::abs(weighted[i] - uniform[i]));
  }
  ew = std::sqrt(ew / double(n));
  eu = std::sqrt(eu / double(n));
  eh = std::sqrt(eh / double(n));
  std::printf("low wall, light 26 deg above the floor: RMSE %.5f against the weighted share, %.5f against "
              "the uniform fraction (hard %.5f; the two truths differ by up to %.3f)\n", ew, eu, eh, gap);
  // Measured 0.0349 against the weighted share, 0.0416 against the uniform fraction (hard
  // 0.147); with every tap weighed alike, as before, 0.0410 and 0.0388: the test fails there.
  // What is left is mostly the lit side's outer penumbra, which the footprint's stretch cap
  // (SHADOWS_ISG_MAX_STRETCH) leaves out at this elevation.
  EXPECT_GT(gap, 0.05);
  EXPECT_LT(ew, 0.3 * eh);
  EXPECT_LT(ew, 0.9 * eu);
}

// A huge depth range: the synth contact frame with its background replaced by a lit wall 1e6
// units away (planar depth), so receivers at a few units and at 1e6 share the image. The wall
// must come out lit and finite, and nothing it adds may reach the near receivers (the range
// function of eq. 6 rejects samples that far).
TEST_F(ShadowsIsg, HugeDepthRangeLeavesNearReceiversAlone) {
  const auto dir = isg::test::synth_case({"contact", 192, 108, 0}, "shadows-depth-range");
  auto job_for = [&] {
    isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
    job.params.set_text("shadows.method", "isg", "test");
    job.params.set_text("reflections.method", "none", "test");
    return job;
  };
  auto job = job_for();
  auto near = isg::run::load_frame(job, (dir / "aovs.exr").string());
  isg::run::process_frame(ctx(), job, near);

  auto img = isg::io::read_exr(dir / "aovs.exr");
  const auto& cam = *job.scene.camera;
  const auto inv = isg::io::inverse(cam.world_to_camera);
  const double f_px = 0.5 * img.height / std::tan(cam.yfov_deg * kPi / 360.0), far = 1e6;
  const size_t n = img.pixels();
  std::vector<char> was_bg(n, 0);
  size_t walls = 0;
  for (size_t i = 0; i < n; ++i) {
    if (img.find("A")->data[i] > 0.0f && img.find("Z")->data[i] < 1e9f) continue;
    was_bg[i] = 1;
    ++walls;
    const double x = double(i % size_t(img.width)) + 0.5, y = double(i / size_t(img.width)) + 0.5;
    const double c[3] = {(x - 0.5 * img.width) / f_px * far, -(y - 0.5 * img.height) / f_px * far, -far};
    const char* P[3] = {"P.X", "P.Y", "P.Z"};
    for (int k = 0; k < 3; ++k)
      img.find(P[k])->data[i] = float(inv[size_t(k * 4)] * c[0] + inv[size_t(k * 4 + 1)] * c[1] +
                                      inv[size_t(k * 4 + 2)] * c[2] + inv[size_t(k * 4 + 3)]);
    img.find("Z")->data[i] = float(far);
    img.find("A")->data[i] = 1.0f;
    img.find("key.shadow")->data[i] = 1.0f;
    img.find("key.occluder")->data[i] = 0.0f;
  }
  ASSERT_GT(walls, n / 50) << "the scene needs background to replace";
  isg::io::write_exr(dir / "wall.exr", img, {});
  auto job2 = job_for();
  auto wall = isg::run::load_frame(job2, (dir / "wall.exr").string());
  isg::run::process_frame(ctx(), job2, wall);
  const auto& a = near.img.find("key.softshadow")->data;
  const auto& b = wall.img.find("key.softshadow")->data;
  double worst = 0;
  for (size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(std::isfinite(b[i])) << i;
    if (was_bg[i]) EXPECT_EQ(b[i], 1.0f) << i;
    else worst = std::max(worst, std::abs(double(a[i]) - b[i]));
  }
  std::printf("huge depth range: %zu wall pixels at 1e6; near receivers change by at most %.2e\n",
              walls, worst);
  EXPECT_LT(worst, 1e-3);
}

// Half-float inputs: the synth contact AOVs with every channel stored as half (P and Z too, as
// some pipelines write them). Half's 11-bit mantissa moves P by up to ~2e-3 at these distances;
// the soft shadow's error against the ray-traced reference must stay close to the float input's.
TEST_F(ShadowsIsg, HalfFloatInputs) {
  const auto dir = isg::test::synth_case({"contact"}, "shadows-half");
  auto img = isg::io::read_exr(dir / "aovs.exr");
  for (auto& c : img.channels) c.storage = isg::io::Storage::half;
  isg::io::write_exr(dir / "half.exr", img, {});
  const auto ref = isg::io::read_exr(dir / "ref" / "softshadow_key.exr");
  const auto& mask = ref.find("mask")->data;
  const auto& want = ref.find("key.softshadow")->data;
  double err[2];
  for (int k = 0; k < 2; ++k) {
    isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", fx::default_params()};
    job.params.set_text("shadows.method", "isg", "test");
    auto f = isg::run::load_frame(job, (dir / (k ? "half.exr" : "aovs.exr")).string());
    isg::run::process_frame(ctx(), job, f);
    const auto& soft = f.img.find("key.softshadow")->data;
    double e = 0;
    size_t m = 0;
    for (size_t i = 0; i < mask.size(); ++i) {
      if (mask[i] < 0.5f) continue;
      e += std::pow(double(soft[i]) - want[i], 2);
      ++m;
    }
    err[k] = std::sqrt(e / double(m));
  }
  std::printf("contact key.softshadow RMSE: float inputs %.5f, half inputs %.5f\n", err[0], err[1]);
  EXPECT_LT(err[1], 1.1 * err[0]);
}
