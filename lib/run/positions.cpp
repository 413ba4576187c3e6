#include "run/positions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>

#include "isg_io.h"

namespace isg::run {

namespace {

constexpr size_t kOut = std::numeric_limits<size_t>::max();  // no sample there

// The fit's terms at offset (dx, dy): 1, dx, dy, dx², dx dy, dy².
void monomials(int dx, int dy, double f[6]) {
  f[0] = 1.0, f[1] = dx, f[2] = dy, f[3] = double(dx) * dx, f[4] = double(dx) * dy,
  f[5] = double(dy) * dy;
}

// A k = A[.][m] (m x m+1, in place) by Gaussian elimination with partial pivoting; false where a
// pivot falls under 1e-9 of A[0][0] (the sum of the first term's squares: a degenerate set).
bool solve(double A[6][7], int m, double* k) {
  const double scale = A[0][0];
  for (int c = 0; c < m; ++c) {
    int best = c;
    for (int p = c + 1; p < m; ++p)
      if (std::abs(A[p][c]) > std::abs(A[best][c])) best = p;
    if (!(std::abs(A[best][c]) > 1e-9 * scale)) return false;
    for (int q = 0; q <= m; ++q) std::swap(A[c][q], A[best][q]);
    for (int p = c + 1; p < m; ++p) {
      const double g = A[p][c] / A[c][c];
      for (int q = c; q <= m; ++q) A[p][q] -= g * A[c][q];
    }
  }
  for (int c = m - 1; c >= 0; --c) {
    double v = A[c][m];
    for (int q = c + 1; q < m; ++q) v -= A[c][q] * k[q];
    k[c] = v / A[c][c];
  }
  return true;
}

// Least squares of values v over the window's taken samples: a plane (c + a dx + b dy, m = 3) or
// a quadric (those and dx², dx dy, dy², m = 6). ok where the normal equations are well posed.
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

// The window of radius r and its fit, a plane (m = 3) or a quadric (m = 6): the offsets, and the
// filter W[term] that the fit is where every sample is taken (inside a surface), the fit to each
// unit sample.
struct Window {
  int r = 0, n = 0, m = 3;
  std::vector<int> dx, dy;
  std::vector<double> W[6];

  Window(int radius, bool curved) : r(radius), m(curved ? 6 : 3) {
    dx.reserve(size_t(2 * r + 1) * size_t(2 * r + 1));
    dy.reserve(dx.capacity());
    for (int y = -r; y <= r; ++y)
      for (int x = -r; x <= r; ++x) dx.push_back(x), dy.push_back(y);
    n = int(dx.size());
    double full[6][7] = {};
    for (int s = 0; s < n; ++s) {
      double f[6];
      monomials(dx[size_t(s)], dy[size_t(s)], f);
      for (int p = 0; p < m; ++p)
        for (int q = 0; q < m; ++q) full[p][q] += f[p] * f[q];
    }
    for (int p = 0; p < m; ++p) W[p].assign(size_t(n), 0.0);
    for (int s = 0; s < n; ++s) {
      double A[6][7], f[6], k[6] = {};
      monomials(dx[size_t(s)], dy[size_t(s)], f);
      for (int p = 0; p < m; ++p) {
        for (int q = 0; q < m; ++q) A[p][q] = full[p][q];
        A[p][m] = f[p];
      }
      solve(A, m, k);
      for (int p = 0; p < m; ++p) W[p][size_t(s)] = k[p];
    }
  }

  // The fit of v over the samples `taken` (count of them); with every sample taken, only its
  // first `needed` terms (the rest stay 0).
  Fit fit(const double* v, const bool* taken, int count, int needed = 6) const {
    Fit F;
    F.terms = m;
    if (count == n) {
      for (int p = 0; p < std::min(m, needed); ++p) {
        const double* w = W[p].data();
        for (int s = 0; s < n; ++s) F.k[p] += w[s] * v[s];
      }
      F.ok = true;
      return F;
    }
    if (count < 2 * m) return F;
    double A[6][7] = {};
    for (int s = 0; s < n; ++s) {
      if (!taken[s]) continue;
      double f[6];
      monomials(dx[size_t(s)], dy[size_t(s)], f);
      for (int p = 0; p < m; ++p) {
        for (int q = p; q < m; ++q) A[p][q] += f[p] * f[q];  // the upper triangle
        A[p][m] += f[p] * v[s];
      }
    }
    for (int p = 1; p < m; ++p)
      for (int q = 0; q < p; ++q) A[p][q] = A[q][p];
    F.ok = solve(A, m, F.k);
    return F;
  }
};

}  // namespace

PlanarDepth planar_depth(const effects::PinholeView& view, const std::array<double, 3>& P) {
  const auto& r = view.rot;
  PlanarDepth d;
  d.z = -(r[6] * (P[0] - view.eye[0]) + r[7] * (P[1] - view.eye[1]) + r[8] * (P[2] - view.eye[2]));
  d.bound = 0.5 * (std::abs(r[6]) * effects::float32_step(P[0]) +
                   std::abs(r[7]) * effects::float32_step(P[1]) +
                   std::abs(r[8]) * effects::float32_step(P[2]));
  return d;
}

PlanarDepth planar_depth_of_z(const effects::PinholeView& view, size_t i, int w, int h, double z) {
  const auto& r = view.rot;
  const auto hit = view.world(i, z, w, h);
  PlanarDepth d;
  d.z = z;
  for (size_t k = 0; k < 3; ++k)
    d.bound += 0.5 * std::abs(r[6 + k]) *
               (effects::float32_step(hit[k]) + effects::float32_step(view.eye[k]));
  return d;
}

int refit_radius(double step, double pixel) {
  if (!(pixel > 0) || !(step > 0)) return kRefitMaxRadius;
  return int(
      std::clamp(std::ceil(2.0 * step / pixel), double(kRefitMinRadius), double(kRefitMaxRadius)));
}

namespace {

// The refit of the depths as stored (`stored(i)`, a PlanarDepth, on foreground pixels).
template <class Stored>
std::vector<float> refit(Stored stored, const float* fg, int w, int h, int r,
                         const effects::PinholeView& view, const float* background) {
  const size_t n = size_t(w) * size_t(h);
  // Depth as stored, its bound, and 1/z (0: no surface to fit over).
  std::vector<double> z(n, 0.0), bound(n, 0.0), u(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    if (fg[i] == 0.0f) continue;
    const PlanarDepth d = stored(i);
    z[i] = d.z;
    bound[i] = d.bound;
    if (d.z > 0 && std::isfinite(d.z)) u[i] = 1.0 / d.z;
  }
  // The plane over the smallest window (it only gates the quadric's samples), the quadric over
  // the whole: 1920x1080 1e6 m away (17x17), 2.4 -> 1.9 s with the quadric's value alone where
  // every sample is taken, -> 1.2 s with the plane's window 7x7.
  const Window near(std::min(r, kRefitMinRadius), false), win(r, true);
  std::vector<float> out(n);
  auto rows = [&](int y0, int y1) {
    std::vector<double> v(size_t(win.n));
    std::unique_ptr<bool[]> taken(new bool[size_t(win.n)]);
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
        // Two least-squares fits of 1/z_j - 1/z_i: a plane over the samples whose stored depth
        // is within kRefitGate bounds plus kRefitSlope pixel footprints a pixel of offset (a
        // surface inclined up to atan(kRefitSlope) from the view: a floor seen from near it),
        // then a quadric over those within kRefitGate bounds of the plane (the pixel's own
        // surface, where another entered the first; curved, as a sphere's).
        const double gate = kRefitGate * bound[i], slope = kRefitSlope * z[i] / view.f_px;
        // Sample s of window W at pixel (x, y): its index, or kOut outside the image or surface.
        auto sample = [&](const Window& W, int s) {
          const int xx = x + W.dx[size_t(s)], yy = y + W.dy[size_t(s)];
          if (xx < 0 || xx >= w || yy < 0 || yy >= h) return kOut;
          const size_t j = size_t(yy) * size_t(w) + size_t(xx);
          return u[j] != 0.0 ? j : kOut;
        };
        int count = 0;
        for (int s = 0; s < near.n; ++s) {
          const size_t j = sample(near, s);
          const int cheb = std::max(std::abs(near.dx[size_t(s)]), std::abs(near.dy[size_t(s)]));
          taken[s] = j != kOut && std::abs(z[j] - z[i]) <= gate + slope * cheb;
          v[size_t(s)] = taken[s] ? u[j] - u[i] : 0.0;
          count += taken[s];
        }
        const Fit first = near.fit(v.data(), taken.get(), count);
        Fit second = first;
        if (first.ok) {
          // Within the gate of the plane, in 1/z: |z_j - 1/up| <= gate as |u_j - up| <=
          // gate·u_j·up.
          count = 0;
          for (int s = 0; s < win.n; ++s) {
            const size_t j = sample(win, s);
            const double up = u[i] + first.at(win.dx[size_t(s)], win.dy[size_t(s)]);
            taken[s] = j != kOut && up > 0 && std::abs(u[j] - up) <= gate * u[j] * up;
            v[size_t(s)] = taken[s] ? u[j] - u[i] : 0.0;
            count += taken[s];
          }
          second = win.fit(v.data(), taken.get(), count, 1);  // its value at the pixel
          if (!second.ok) second = first;
        }
        double zi = z[i];
        if (second.ok && u[i] + second.k[0] > 0)
          zi = std::clamp(1.0 / (u[i] + second.k[0]), z[i] - bound[i], z[i] + bound[i]);
        out[i] = float(zi);
      }
  };
  const int threads = std::clamp(int(std::thread::hardware_concurrency()), 1, std::max(1, h / 16));
  std::vector<std::thread> pool;
  pool.reserve(size_t(threads));
  for (int t = 0; t < threads; ++t) pool.emplace_back(rows, h * t / threads, h * (t + 1) / threads);
  for (auto& t : pool) t.join();
  return out;
}

}  // namespace

std::vector<float> refit_depth(const float* P, const float* fg, int w, int h, int r,
                               const effects::PinholeView& view, const float* background) {
  const size_t n = size_t(w) * size_t(h);
  return refit(
      [&](size_t i) {
        return planar_depth(view, {P[i], P[n + i], P[2 * n + i]});
      },
      fg, w, h, r, view, background);
}

std::vector<float> refit_depth_z(const float* Z, const float* fg, int w, int h, int r,
                                 const effects::PinholeView& view, const float* background) {
  return refit([&](size_t i) { return planar_depth_of_z(view, i, w, h, Z[i]); }, fg, w, h, r, view,
               background);
}

}  // namespace isg::run
