// cssm_reference (shadowmap.h): the double-precision mirror of the CSSM passes (thesis ch. 5),
// which the GPU tests compare them with; the conventions are cssm_setup.h's, the passes cssm.cpp.
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "effects/shadowmaps/hsm.h"
#include "effects/shadowmaps/method.h"
#include "effects/shadowmaps/sat.h"
#include "shadowmap_cssm_io.h"

#include "effects/shadowmaps/cssm_setup.h"

namespace isg::effects {

using detail::Geom;
using detail::kBoxOfDisk;
using detail::kPi;
using detail::Plane;
using detail::Shaded;
using detail::V2;
using detail::V3;

using namespace detail::cssm;

namespace {

// The double mirror of the GPU's prefiltered basis: per layer, a SAT with a zero row and column
// ((W+1) x (H+1)) or the mip chain.
class Prefiltered {
 public:
  Prefiltered(const ShadowmapData& map, const Setup& u)
      : u_(u), W_(u.bw), H_(u.bh), f_(double(1 << u.shift)), Wf_(map.width / f_),
        Hf_(map.height / f_), L_(mip_levels(u.bw, u.bh, u.sat)) {
    const int layers = 4 * u.M + 1, F = 1 << u.shift;
    std::vector<std::vector<double>> base(static_cast<size_t>(layers),
                                          std::vector<double>(size_t(W_) * size_t(H_)));
    for (int by = 0; by < H_; ++by)
      for (int bx = 0; bx < W_; ++bx) {
        // The block's average of each basis function over the map texels it covers.
        std::vector<double> acc(size_t(layers), 0.0);
        int n = 0;
        for (int y = by * F; y < std::min((by + 1) * F, map.height); ++y)
          for (int x = bx * F; x < std::min((bx + 1) * F, map.width); ++x, ++n) {
            const double z = norm_depth(u, map.z[size_t(y) * map.width + x]), zeta = u.s_z * z;
            for (int k = 0; k < u.M; ++k) {
              const double c = kPi * (2 * k + 1);
              const double cs = std::cos(c * zeta), sn = std::sin(c * zeta);
              const size_t i = size_t(k), M = size_t(u.M);
              acc[i] += cs;
              acc[M + i] += sn;
              acc[2 * M + i] += z * cs;
              acc[3 * M + i] += z * sn;
            }
            acc[4 * size_t(u.M)] += z;
          }
        for (int l = 0; l < layers; ++l) base[size_t(l)][size_t(by) * W_ + bx] = acc[size_t(l)] / n;
      }
    for (auto& b : base) {
      if (u.sat) {
        std::vector<double> t(size_t(W_ + 1) * size_t(H_ + 1), 0.0);
        for (int y = 0; y < H_; ++y) {
          double row = 0;
          for (int x = 0; x < W_; ++x) {
            row += b[size_t(y) * W_ + x];
            t[size_t(y + 1) * (W_ + 1) + x + 1] = t[size_t(y) * (W_ + 1) + x + 1] + row;
          }
        }
        tables_.push_back({std::move(t)});
        continue;
      }
      std::vector<std::vector<double>> chain{std::move(b)};
      for (size_t l = 1; l < L_.w.size(); ++l) {
        const int w0 = L_.w[l - 1], h0 = L_.h[l - 1], w1 = L_.w[l], h1 = L_.h[l];
        const auto& s = chain.back();
        std::vector<double> d(size_t(w1) * h1);
        for (int y = 0; y < h1; ++y)
          for (int x = 0; x < w1; ++x) {
            const int xa = 2 * x, xb = std::min(2 * x + 1, w0 - 1), ya = 2 * y,
                      yb = std::min(2 * y + 1, h0 - 1);
            d[size_t(y) * w1 + x] = 0.25 * (s[size_t(ya) * w0 + xa] + s[size_t(ya) * w0 + xb] +
                                            s[size_t(yb) * w0 + xa] + s[size_t(yb) * w0 + xb]);
          }
        chain.push_back(std::move(d));
      }
      tables_.push_back(std::move(chain));
    }
  }

  // The area, in block units², of the box of half-widths hx, hy about (qx, qy) inside the map.
  double area(double qx, double qy, double hx, double hy) const {
    qx /= f_;
    qy /= f_;
    hx /= f_;
    hy /= f_;
    const double lx = std::min(qx + hx, Wf_) - std::max(qx - hx, 0.0);
    const double ly = std::min(qy + hy, Hf_) - std::max(qy - hy, 0.0);
    return lx > 0 && ly > 0 ? lx * ly : 0.0;
  }

  // The box average of one layer over half-widths hx, hy about (qx, qy) (eq. 5.3: w * B_i);
  // map texels in, block units inside.
  double box(int layer, double qx, double qy, double hx, double hy) const {
    const auto& T = tables_[size_t(layer)];
    qx /= f_;
    qy /= f_;
    hx /= f_;
    hy /= f_;
    if (u_.sat) {
      const auto& t = T[0];
      auto S = [&](int x, int y) { return t[size_t(y) * (W_ + 1) + x]; };
      const double x0 = std::max(qx - hx, 0.0), x1 = std::min(qx + hx, Wf_);
      const double y0 = std::max(qy - hy, 0.0), y1 = std::min(qy + hy, Hf_);
      // The box snapped to whole texels (the nearest boundaries, widened to hold the texel of
      // its centre): four corners of the table, an exact integer sum (see the top of the file).
      const int cx = std::clamp(int(std::floor(qx)), 0, W_ - 1);
      const int cy = std::clamp(int(std::floor(qy)), 0, H_ - 1);
      const int X0 = std::clamp(std::min(int(std::floor(x0 + 0.5)), cx), 0, W_ - 1);
      const int X1 = std::clamp(std::max(int(std::floor(x1 + 0.5)), cx + 1), X0 + 1, W_);
      const int Y0 = std::clamp(std::min(int(std::floor(y0 + 0.5)), cy), 0, H_ - 1);
      const int Y1 = std::clamp(std::max(int(std::floor(y1 + 0.5)), cy + 1), Y0 + 1, H_);
      return (S(X1, Y1) - S(X0, Y1) - S(X1, Y0) + S(X0, Y0)) / (double(X1 - X0) * double(Y1 - Y0));
    }
    const int levels = int(L_.w.size());
    // The level whose texel spans the kernel (of a rectangle, the square of its area).
    const double h = hx == hy ? hx : std::sqrt(hx * hy);
    const double lev = std::clamp(std::log2(2.0 * h), 0.0, double(levels - 1));
    const int l0 = int(std::floor(lev)), l1 = std::min(l0 + 1, levels - 1);
    const double t = lev - l0;
    auto bilinear = [&](int l) {
      const int lw = L_.w[size_t(l)], lh = L_.h[size_t(l)];
      const double ux = qx * lw / W_ - 0.5, uy = qy * lh / H_ - 0.5;
      const double ix = std::floor(ux), iy = std::floor(uy), fx = ux - ix, fy = uy - iy;
      const int xa = std::clamp(int(ix), 0, lw - 1), xb = std::clamp(int(ix) + 1, 0, lw - 1);
      const int ya = std::clamp(int(iy), 0, lh - 1), yb = std::clamp(int(iy) + 1, 0, lh - 1);
      const auto& m = T[size_t(l)];
      return (1 - fx) * (1 - fy) * m[size_t(ya) * lw + xa] +
             fx * (1 - fy) * m[size_t(ya) * lw + xb] + (1 - fx) * fy * m[size_t(yb) * lw + xa] +
             fx * fy * m[size_t(yb) * lw + xb];
    };
    return (1 - t) * bilinear(l0) + t * bilinear(l1);
  }

 private:
  const Setup& u_;
  int W_, H_;        // basis size (blocks)
  double f_, Wf_, Hf_;  // block side in map texels; the map's size in blocks
  Levels L_;
  std::vector<std::vector<std::vector<double>>> tables_;  // [layer][level][texel]
};

double suppress(const Setup& u, double s) {  // §5.2.3
  return std::clamp(u.alpha * (s - 0.5) + 0.5, 0.0, 1.0);
}

}  // namespace

std::vector<float> cssm_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                  const ShadowmapSettings& s, ShadowmapStats* stats) {
  Geom G(in, map, s);
  const Setup u = make_setup(map, s);
  const Prefiltered pf(map, u);
  const detail::HsmLevels hsm_levels = detail::hsm_levels(map);
  const detail::HsmRef hsm(map, hsm_levels);
  const int M = u.M;
  ShadowmapStats st;
  const double k = G.k();
  auto out = detail::shade_receivers(G, st, [&](int, int, const V3& q, const Plane& g, const V3&, const V3&) -> Shaded {
    const double texel_world = G.texel_world(q[2]);
    const double cx = std::floor(q[0]) + 0.5, cy = std::floor(q[1]) + 0.5;
    const double d =
        std::clamp((G.threshold(q, g, cx, cy, texel_world) - u.zmin) / u.zrange, 0.0, 1.0);
    // Prefiltered CSM (eq. 5.3, 5.10): the raw filtered visibility s_f of a box against the
    // normalised receiver depth dn; with csm_z, CSM-Z's numerator w * (f̄ z) instead (eq. 5.11:
    // (w * z)/2 + Σ 2/c_k [sin(c_k δ)(w * z cos) − cos(c_k δ)(w * z sin)]).
    auto lookup = [&](double bx, double by, double hx, double hy, double dn, bool csm_z) {
      const double delta = u.s_z * dn - u.x0;
      double v = csm_z ? 0.5 * pf.box(4 * M, bx, by, hx, hy) : 0.5;
      const int base = csm_z ? 2 * M : 0;
      for (int j = 0; j < M; ++j) {
        const double c = kPi * (2 * j + 1);
        const double t = 2.0 / c *
                         (std::sin(c * delta) * pf.box(base + j, bx, by, hx, hy) -
                          std::cos(c * delta) * pf.box(base + M + j, bx, by, hx, hy));
        v += csm_z ? t : -t;
      }
      return v;
    };
    // Sub-kernels along one axis (see the top of the file): the threshold's range over the
    // kernel's extent [lo, hi] through the pixel, in units of x0, rounded up.
    auto split = [&](V2 lo, V2 hi) {
      if (g[3] < SHADOWMAP_TRUSTED_SLOPE) return 1;  // a plane the neighbours do not confirm
      const auto tr = G.threshold_range(q, g, lo, hi, texel_world);
      const double r = u.s_z * (tr[1] - tr[0]) / u.zrange / u.x0;
      return r > double(u.split) ? u.split : (r > 1.0 ? int(std::ceil(r)) : 1);
    };
    // The lookup over half-width h about the pixel, split into nx x ny sub-kernels, each
    // against the receiver's depth at its centre.
    auto filtered = [&](double h, bool csm_z) {
      const int nx = split({q[0] - h, q[1]}, {q[0] + h, q[1]});
      const int ny = split({q[0], q[1] - h}, {q[0], q[1] + h});
      if (nx * ny == 1) return lookup(q[0], q[1], h, h, d, csm_z);
      const double sx = h / nx, sy = h / ny;
      double sum = 0, area = 0;
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const double bx = q[0] - h + (2 * i + 1) * sx, by = q[1] - h + (2 * j + 1) * sy;
          const double a = pf.area(bx, by, sx, sy);
          if (a <= 0) continue;
          const double dn = std::clamp(
              (G.threshold(q, g, bx, by, texel_world) - u.zmin) / u.zrange, 0.0, 1.0);
          sum += a * lookup(bx, by, sx, sy, dn, csm_z);
          area += a;
        }
      return area > 0 ? sum / area : lookup(q[0], q[1], h, h, d, csm_z);
    };
    auto visibility = [&](double h) { return filtered(h, false); };
    // The min-max HSM: lit over the search's box, umbra over PCSS's region (see the top of
    // the file).
    {
      const V3 qv = {q[0], q[1], std::min(q[2], hsm_levels.far_z)};
      const double hb = G.cone_box(k, map.min_depth, q[2], 1.0, s.max_radius);
      V2 lo = {std::max(q[0] - hb, 0.0), std::max(q[1] - hb, 0.0)};
      V2 hi = {std::min(q[0] + hb, double(map.width)), std::min(q[1] + hb, double(map.height))};
      if (hsm.range(lo, hi)[0] >= G.threshold_range(qv, g, lo, hi, texel_world)[1]) {
        ++st.skipped;
        return {1.0, 0.0};
      }
      const double rs = std::max(G.cone_radius(k, map.min_depth, qv[2], 1.0, s.max_radius), 0.5);
      lo = {std::max(q[0] - rs, 0.0), std::max(q[1] - rs, 0.0)};
      hi = {std::min(q[0] + rs, double(map.width)), std::min(q[1] + rs, double(map.height))};
      if (hsm.range(lo, hi)[1] < G.threshold_range(qv, g, lo, hi, texel_world)[0]) {
        ++st.skipped;
        return {0.0, 0.0};
      }
    }
    // Blocker search (Fig. 5.1a): the PCSS region as a box of the same area.
    double hs = G.cone_box(k, map.min_depth, q[2], 1.0, s.max_radius);
    const double sf = visibility(hs);
    if (suppress(u, sf) >= 1.0 || 1.0 - sf < kMinBlockers) {
      ++st.skipped;  // no blockers: fully lit
      return {1.0, 0.0};
    }
    // CSM-Z (eq. 5.11), then z_avg (eq. 5.8).
    double z_avg = std::clamp(filtered(hs, true) / (1.0 - sf), 0.0, d);
    double zb = u.zmin + z_avg * u.zrange;
    // The search narrowed to the blockers' cone (see the top of the file), while it shrinks.
    for (int pass = 0; pass < u.narrow; ++pass) {
      const double hn = G.cone_box(k, zb, q[2], CSSM_NARROW_MARGIN, s.max_radius);
      if (hn >= hs) break;
      const double sn = visibility(hn);
      if (suppress(u, sn) >= 1.0 || 1.0 - sn < kMinBlockers) {
        ++st.skipped;  // none of the blockers found reaches the receiver: fully lit
        return {1.0, 0.0};
      }
      z_avg = std::clamp(filtered(hn, true) / (1.0 - sn), 0.0, d);
      zb = u.zmin + z_avg * u.zrange;
      hs = hn;
    }
    // Penumbra width (§5.3.1): rf = k (1/z_avg − 1/d), in texels.
    double rf = k * G.gap(zb, q[2]);
    if (rf > s.max_radius) {
      rf = s.max_radius;
      ++st.clamped;
    }
    const double v = suppress(u, visibility(std::max(kBoxOfDisk * rf, kMinHalfWidth)));
    const double p = 1.0 + s.cssm_a * std::exp(-s.cssm_b * (d - z_avg));  // eq. 5.9
    // Blockers within x0 / s_z of the receiver shadow it by under half (the top of the file):
    // input_edges keeps the input's edge up to the radius one there casts (issue 19).
    const double zh = u.zmin + std::max(d - u.x0 / u.s_z, 0.0) * u.zrange;
    const double r_half = std::min(k * G.gap(zh, q[2]), s.max_radius);
    return {std::pow(v, p), rf, r_half};
  });
  if (stats) *stats = st;
  return out;
}

}  // namespace isg::effects
