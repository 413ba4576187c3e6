// P refitted far from the world origin (lib/run/positions.h) against the closed form: a floor
// and a sphere resting on it, ray-traced in double relative to the eye, P stored as float32.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "run/positions.h"

namespace {

using V3 = std::array<double, 3>;

struct Frame {
  int w = 200, h = 120;
  std::vector<float> P, fg, bg;
  std::vector<double> exact;  // planar depth of the true hit
  std::vector<int> what;      // 0 background, 1 floor, 2 sphere
  isg::effects::PinholeView view;
};

// Camera 6 m back and 1.5 m up, looking at the sphere's foot; floor z = o, sphere of radius 0.5
// on it; the world shifted by o on every axis.
Frame render(double o, int w = 200, int h = 120) {
  Frame f;
  f.w = w;
  f.h = h;
  const double yfov = 40.0 * 3.14159265358979323846 / 180.0;
  f.view.f_px = 0.5 * f.h / std::tan(0.5 * yfov);
  f.view.eye = {o, o - 6.0, o + 1.5};
  // Rows: right, up, back (camera looks down -Z) for the direction (0, 6, -1.2) normalised.
  const V3 fw = [] {
    const double l = std::hypot(6.0, 1.2);
    return V3{0.0, 6.0 / l, -1.2 / l};
  }();
  const V3 right = {1, 0, 0};          // forward × (0, 0, 1), normalised
  const V3 up = {0.0, -fw[2], fw[1]};  // right × forward
  f.view.rot = {right[0], right[1], right[2], up[0], up[1], up[2], -fw[0], -fw[1], -fw[2]};
  const size_t n = size_t(f.w) * size_t(f.h);
  f.P.assign(3 * n, 0.0f);
  f.fg.assign(n, 0.0f);
  f.bg.assign(n, 0.0f);
  f.exact.assign(n, 0.0);
  f.what.assign(n, 0);
  const auto& r = f.view.rot;
  const V3 c = {0.0, 0.0, 0.5};  // sphere centre, relative to the world shift
  for (int y = 0; y < f.h; ++y)
    for (int x = 0; x < f.w; ++x) {
      const size_t i = size_t(y) * size_t(f.w) + size_t(x);
      const double cx = (x + 0.5 - 0.5 * f.w) / f.view.f_px,
                   cy = -(y + 0.5 - 0.5 * f.h) / f.view.f_px;
      const V3 d = {r[0] * cx + r[3] * cy - r[6], r[1] * cx + r[4] * cy - r[7],
                    r[2] * cx + r[5] * cy - r[8]};
      const V3 e = {0.0, -6.0, 1.5};  // the eye relative to the shift
      double t = 1e30;
      int hit = 0;
      if (d[2] < 0) t = -e[2] / d[2], hit = 1;
      const V3 oc = {e[0] - c[0], e[1] - c[1], e[2] - c[2]};
      const double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2],
                   dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const double disc = b * b - dd * (oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - 0.25);
      if (disc > 0) {
        const double ts = (-b - std::sqrt(disc)) / dd;
        if (ts > 0 && ts < t) t = ts, hit = 2;
      }
      if (hit == 0 || t > 40.0) {
        f.bg[i] = 1e10f;
        continue;
      }
      f.what[i] = hit;
      f.fg[i] = 1.0f;
      f.exact[i] = t;  // the direction's planar component is 1
      f.bg[i] = float(t);
      for (int k = 0; k < 3; ++k)
        f.P[size_t(k) * n + i] = float(f.view.eye[size_t(k)] + t * d[size_t(k)]);
    }
  return f;
}

struct Errors {
  double raw[3] = {0, 0, 0}, fit[3] = {0, 0, 0};  // RMS by what (0: all foreground)
  double over_bound = 0;                          // largest |fit - stored| beyond the bound
};

Errors measure(const Frame& f, const std::vector<float>& z, const std::vector<float>* bg) {
  Errors e;
  double cnt[3] = {0, 0, 0};
  const size_t n = f.exact.size();
  for (size_t i = 0; i < n; ++i) {
    if (f.fg[i] == 0.0f) {
      EXPECT_EQ(z[i], bg ? (*bg)[i] : 1e10f) << i;
      continue;
    }
    const auto s = isg::run::planar_depth(f.view, {f.P[i], f.P[n + i], f.P[2 * n + i]});
    const double raw = s.z - f.exact[i], fit = double(z[i]) - f.exact[i];
    for (int k : {0, f.what[i]}) {
      e.raw[k] += raw * raw, e.fit[k] += fit * fit, cnt[k] += 1;
    }
    e.over_bound = std::max(e.over_bound, std::abs(double(z[i]) - s.z) - s.bound);
  }
  for (int k = 0; k < 3; ++k)
    e.raw[k] = std::sqrt(e.raw[k] / cnt[k]), e.fit[k] = std::sqrt(e.fit[k] / cnt[k]);
  return e;
}

}  // namespace

TEST(RefitPositions, HalvesPlanarDepthErrorFarFromTheOrigin) {
  const Frame f = render(1e6);
  // A pixel at a scene radius (6 m, 0.036 m) against P's step there (0.0625 m): 1.7 pixels, a
  // window of two steps' worth on either side.
  const int r = isg::run::refit_radius(0.0625, 6.0 / f.view.f_px);
  EXPECT_EQ(r, 4);
  const auto z = isg::run::refit_depth(f.P.data(), f.fg.data(), f.w, f.h, r, f.view, f.bg.data());
  const Errors e = measure(f, z, &f.bg);
  std::printf(
      "1e6 from the origin, %dx%d window: planar depth RMS error as stored %.4f m, refitted "
      "%.4f m (floor %.4f -> %.4f, sphere %.4f -> %.4f); furthest beyond the bound %.2g m\n",
      2 * r + 1, 2 * r + 1, e.raw[0], e.fit[0], e.raw[1], e.fit[1], e.raw[2], e.fit[2],
      e.over_bound);
  // Measured: 0.0160 -> 0.0078 (floor 0.0159 -> 0.0077, sphere 0.0185 -> 0.0105). P's rounding
  // is a staircase, correlated over the pixels of a step, which a 9x9 window only halves.
  EXPECT_GT(e.raw[0], 0.01);            // P's rounding: about a quarter of its step
  EXPECT_LT(e.fit[1], 0.6 * e.raw[1]);  // the floor, seen from 1.5 m above it
  EXPECT_LT(e.fit[2], 0.6 * e.raw[2]);  // the sphere: curved, and cut by the floor at its foot
  EXPECT_LT(e.fit[0], 0.6 * e.raw[0]);
  EXPECT_LE(e.over_bound, 1e-6);  // never further from P than its rounding allows
}

// Three times the resolution: P's step spans 5.2 pixels at a scene radius, the widest window.
TEST(RefitPositions, WiderWindowAtHigherResolution) {
  const Frame f = render(1e6, 600, 360);
  const int r = isg::run::refit_radius(0.0625, 6.0 / f.view.f_px);
  EXPECT_EQ(r, isg::run::kRefitMaxRadius);
  const auto z = isg::run::refit_depth(f.P.data(), f.fg.data(), f.w, f.h, r, f.view, f.bg.data());
  const Errors e = measure(f, z, &f.bg);
  std::printf(
      "600x360, %dx%d window: planar depth RMS error as stored %.4f m, refitted %.4f m "
      "(floor %.4f -> %.4f, sphere %.4f -> %.4f)\n",
      2 * r + 1, 2 * r + 1, e.raw[0], e.fit[0], e.raw[1], e.fit[1], e.raw[2], e.fit[2]);
  EXPECT_LT(e.fit[1], 0.6 * e.raw[1]);
  EXPECT_LT(e.fit[2], 0.6 * e.raw[2]);
  EXPECT_LE(e.over_bound, 1e-6);
}

// Z as a renderer computes it far from the origin: from the float32 hit and eye, in float
// (Cycles 1e6 m away writes Z as coarse as P). Refitted from Z with the hit's and the eye's
// steps as its bound.
TEST(RefitPositions, ZFromAFloat32WorldToo) {
  const Frame f = render(1e6);
  const size_t n = f.exact.size();
  const auto& R = f.view.rot;
  const float eye[3] = {float(f.view.eye[0]), float(f.view.eye[1]), float(f.view.eye[2])};
  std::vector<float> Z(n, 1e10f);
  double raw = 0, cnt = 0;
  for (size_t i = 0; i < n; ++i) {
    if (f.fg[i] == 0.0f) continue;
    float zf = 0.0f;
    for (int k = 0; k < 3; ++k) zf -= float(R[size_t(6 + k)]) * (f.P[size_t(k) * n + i] - eye[k]);
    Z[i] = zf;
    const auto d = isg::run::planar_depth_of_z(f.view, i, f.w, f.h, zf);
    EXPECT_LE(std::abs(zf - f.exact[i]), d.bound + 1e-6) << i;  // the bound holds
    raw += (zf - f.exact[i]) * (zf - f.exact[i]), cnt += 1;
  }
  raw = std::sqrt(raw / cnt);
  const auto z = isg::run::refit_depth_z(Z.data(), f.fg.data(), f.w, f.h, 3, f.view, Z.data());
  double fit = 0;
  for (size_t i = 0; i < n; ++i)
    if (f.fg[i] != 0.0f) fit += (z[i] - f.exact[i]) * (z[i] - f.exact[i]);
  fit = std::sqrt(fit / cnt);
  std::printf("Z from a float32 world 1e6 away: RMS error as stored %.4f m, refitted %.4f m\n", raw,
              fit);
  EXPECT_GT(raw, 0.01);
  EXPECT_LT(fit, 0.6 * raw);
}

TEST(RefitPositions, BackgroundAndTheOriginAreKept) {
  // At the origin P's steps are under a micrometre: the refit stays within them.
  const Frame f = render(0.0);
  const auto z = isg::run::refit_depth(f.P.data(), f.fg.data(), f.w, f.h, 3, f.view, nullptr);
  const Errors e = measure(f, z, nullptr);  // background: 1e10 without the input's depth
  std::printf("at the origin: planar depth RMS error as stored %.3g m, refitted %.3g m\n", e.raw[0],
              e.fit[0]);
  EXPECT_LT(e.fit[0], 1e-5);
  EXPECT_LE(e.over_bound, 1e-6);
  EXPECT_EQ(isg::run::refit_radius(0.0625, 0.1), isg::run::kRefitMinRadius);
  EXPECT_EQ(isg::run::refit_radius(0.0625, 0.025), 5);
  EXPECT_EQ(isg::run::refit_radius(1.0, 0.01), isg::run::kRefitMaxRadius);
}
