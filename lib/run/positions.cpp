#include "run/positions.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "isg_io.h"

namespace isg::run {

PlanarDepth planar_depth(const effects::PinholeView& view, const std::array<double, 3>& P) {
  const auto& r = view.rot;
  PlanarDepth d;
  d.z = -(r[6] * (P[0] - view.eye[0]) + r[7] * (P[1] - view.eye[1]) + r[8] * (P[2] - view.eye[2]));
  d.bound = 0.5 * (std::abs(r[6]) * effects::float32_step(P[0]) +
                   std::abs(r[7]) * effects::float32_step(P[1]) +
                   std::abs(r[8]) * effects::float32_step(P[2]));
  return d;
}

int refit_radius(double step, double pixel) {
  if (!(pixel > 0)) return kRefitMaxRadius;
  return std::clamp(int(std::ceil(step / pixel)), kRefitMinRadius, kRefitMaxRadius);
}

std::vector<float> refit_depth(const float* P, const float* fg, int w, int h, int r,
                               const effects::PinholeView& view, const float* background) {
  const size_t n = size_t(w) * size_t(h);
  // Depth of P as stored, its bound, and 1/z (0: no surface to fit over).
  std::vector<double> z(n, 0.0), bound(n, 0.0), u(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    if (fg[i] == 0.0f) continue;
    const PlanarDepth d = planar_depth(view, {P[i], P[n + i], P[2 * n + i]});
    z[i] = d.z;
    bound[i] = d.bound;
    if (d.z > 0 && std::isfinite(d.z)) u[i] = 1.0 / d.z;
  }
  std::vector<float> out(n);
  // Least squares of 1/z_j - 1/z_i over the window's neighbours j that `take`: a plane
  // (c + a dx + b dy) or, with `curved`, a quadric (those and dx², dx dy, dy²); c at the pixel,
  // ok where the normal equations are well posed (Gaussian elimination with partial pivoting).
  struct Fit {
    double k[6] = {0, 0, 0, 0, 0, 0};  // c, a, b, then the quadric's
    int terms = 3;
    bool ok = false;
    double at(int dx, int dy) const {
      double v = k[0] + k[1] * dx + k[2] * dy;
      if (terms == 6) v += k[3] * dx * dx + k[4] * dx * dy + k[5] * dy * dy;
      return v;
    }
  };
  auto fit = [&](int x, int y, bool curved, auto take) {
    const size_t i = size_t(y) * size_t(w) + size_t(x);
    const int m = curved ? 6 : 3;
    double A[6][7] = {};
    int count = 0;
    for (int dy = -r; dy <= r; ++dy) {
      const int yy = y + dy;
      if (yy < 0 || yy >= h) continue;
      for (int dx = -r; dx <= r; ++dx) {
        const int xx = x + dx;
        if (xx < 0 || xx >= w) continue;
        const size_t j = size_t(yy) * size_t(w) + size_t(xx);
        if (u[j] == 0.0 || !take(j, dx, dy)) continue;
        const double f[6] = {
            1.0, double(dx), double(dy), double(dx * dx), double(dx * dy), double(dy * dy)};
        const double v = u[j] - u[i];
        for (int p = 0; p < m; ++p) {
          for (int q = 0; q < m; ++q) A[p][q] += f[p] * f[q];
          A[p][m] += f[p] * v;
        }
        ++count;
      }
    }
    Fit F;
    F.terms = m;
    if (count < 2 * m) return F;
    const double scale = A[0][0];  // the count: pivots of a degenerate set fall to ~0 of it
    for (int c = 0; c < m; ++c) {
      int best = c;
      for (int p = c + 1; p < m; ++p)
        if (std::abs(A[p][c]) > std::abs(A[best][c])) best = p;
      if (!(std::abs(A[best][c]) > 1e-9 * scale)) return F;
      for (int q = 0; q <= m; ++q) std::swap(A[c][q], A[best][q]);
      for (int p = c + 1; p < m; ++p) {
        const double g = A[p][c] / A[c][c];
        for (int q = c; q <= m; ++q) A[p][q] -= g * A[c][q];
      }
    }
    for (int c = m - 1; c >= 0; --c) {
      double v = A[c][m];
      for (int q = c + 1; q < m; ++q) v -= A[c][q] * F.k[q];
      F.k[c] = v / A[c][c];
    }
    F.ok = true;
    return F;
  };
  auto rows = [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        if (fg[i] == 0.0f) {
          out[i] = background ? background[i] : float(10.0 * ISG_BACKGROUND_DEPTH);
          continue;
        }
        if (u[i] == 0.0) {  // behind the camera: nothing to refit
          out[i] = float(z[i]);
          continue;
        }
        // Two least-squares fits over the window: a plane over the neighbours whose stored
        // depth is within kRefitGate bounds plus kRefitSlope pixel footprints a pixel of offset
        // (a surface inclined up to atan(kRefitSlope) from the view: a floor seen from near it),
        // then a quadric over those within kRefitGate bounds of the plane (the pixel's own
        // surface, where another entered the first; curved, as a sphere's).
        const double gate = kRefitGate * bound[i], slope = kRefitSlope * z[i] / view.f_px;
        Fit first = fit(x, y, false, [&](size_t j, int dx, int dy) {
          return std::abs(z[j] - z[i]) <= gate + slope * std::max(std::abs(dx), std::abs(dy));
        });
        Fit second = first;
        if (first.ok)
          second = fit(x, y, true, [&](size_t j, int dx, int dy) {
            const double up = u[i] + first.at(dx, dy);
            return up > 0 && std::abs(z[j] - 1.0 / up) <= gate;
          });
        if (!second.ok) second = first;
        double zi = z[i];
        if (second.ok && u[i] + second.k[0] > 0)
          zi = std::clamp(1.0 / (u[i] + second.k[0]), z[i] - bound[i], z[i] + bound[i]);
        out[i] = float(zi);
      }
  };
  const int threads = std::clamp(int(std::thread::hardware_concurrency()), 1, std::max(1, h / 16));
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(rows, h * t / threads, h * (t + 1) / threads);
  for (auto& t : pool) t.join();
  return out;
}

}  // namespace isg::run
