// CSSM, convolution soft shadow maps (thesis ch. 5): the shadow test expanded in a Fourier
// series (eq. 5.2, 5.10) whose basis images are prefiltered once (SATs or mipmaps, §5.3.1), so
// that the blocker search (CSM-Z, eq. 5.8, 5.11) and the penumbra filter are constant-time
// lookups. The double reference and the GPU passes (shaders/shadowmap_cssm*.comp).
//
// Conventions shared by both:
// - z ∈ [0, 1]: the map depth normalised over [min_depth, largest non-background depth];
//   background texels are 1. d: the receiver-plane threshold at the pixel's own texel centre
//   (bias included), normalised the same way and clamped to [0, 1].
// - The expansion of the visibility f(x) = [x < 0], x = d − z, is, with c_k = π(2k − 1)
//   (eq. 5.10 with Annen07's π), f_M(x) = 1/2 − Σ_k 2/c_k sin(c_k x); its period is 2.
// - Ringing suppression (§5.2.3, Fig. 5.2c-d): s ↦ clamp(α (s − 1/2) + 1/2, 0, 1), α the
//   smallest scale that lifts every ringing trough of f_M on the lit side to 1 (and, by
//   symmetry, every crest on the shadowed side to 0): α = 1 / (2 f_M(−1/M) − 1), the first
//   trough (1.121 for M = 4, 1.111 for 8, 1.108 for 16). The step is shifted by x0 so that an
//   unoccluded receiver (x = 0) is fully lit after the scale: f_M(−x0) = 1/2 + 1/(2α)
//   (x0 = 0.064, 0.033, 0.016 of the expansion's unit), and the depths are squeezed into
//   ζ = s_z z, s_z = 1 − 2 x0, so that the shifted argument s_z (d − z) − x0 stays inside
//   [−1 + x0, 1 − x0], away from the step the series repeats at ±1. Blockers nearer the
//   receiver than 2 x0 / s_z of the depth range only partly shadow it: the contact leak that
//   the sharpening of eq. 5.9 darkens. Those nearer than x0 / s_z (where the shifted step
//   crosses 1/2) shadow it by less than half, so the expansion cannot place the narrow penumbrae
//   they cast: shadows.input_edges keeps the input's ray-traced edge up to the radius a blocker
//   x0 / s_z in front of the receiver casts (Shaded::r_min; issue 19: own contact-far1e5
//   0.51 -> 0.45 of doing nothing, the shared cases within 0.01).
// - Kernels are square boxes in map texels of the area of the disk PCSS samples (half-width
//   √π/2 · r), at least one texel wide, clipped to the map. SAT: the box snapped to whole basis
//   texels (its edges to the nearest texel boundary, at least one texel wide), so a lookup reads
//   four table entries an image, one 16-byte load for four images (issue 51: the fractional
//   box's 4 x 4 entries cost lavapipe 1.8 s against 0.5 s a 1080p frame; shared contact 0.2365
//   -> 0.2428 of doing nothing, rowdepth 0.2611 -> 0.2641). The tables are 32-bit integers
//   summed in wrapping arithmetic (Lauritzen07's integer SATs, which VSSM §7.5.4 adopts): each
//   value quantised to sat_scale units, a power of two that keeps the largest box any kernel
//   reads (shadows.smap_max_radius) within 2^30 units, so its sum from four entries is exact.
//   Mipmaps sample the level whose texel spans the box (bilinear, linear between levels, clamp
//   to edge).
// - The min-max HSM (hsm.h; thesis §7.5.1, as vssm's) proves a pixel lit where every texel of
//   the search's box lies behind the receiver's threshold over it, and in umbra where every
//   texel of PCSS's whole region lies in front of it, with no lookup. Only the pixels whose
//   first search finds blockers run the rest, in a second dispatch (shadowmap_common.h's
//   sm_pixel_of).
// - Receiver depth per sub-kernel (issue 19; the thesis takes one d per pixel, which a receiver
//   whose light depth changes across the kernel cannot have: at grazing light the receiver's own
//   texels on the light's side of the pixel lie in front of d and shadow it). A lookup over
//   half-width h is split into nx x ny sub-kernels, n = ⌈s_z Δ / (zrange x0)⌉ clamped to
//   [1, shadows.cssm_split] per axis, Δ the range of the receiver-plane threshold over the
//   kernel's extent along that axis through the pixel (Geom::threshold_range): within a
//   sub-kernel the threshold then moves by about the step shift x0 that keeps an unoccluded
//   receiver lit, and a receiver sloped along one axis is split only along it. Only a plane
//   the screen neighbours confirm (sm_receiver_plane's trusted bound) is extrapolated so;
//   elsewhere n = 1. Each sub-kernel is tested against the receiver's threshold at its centre.
//   Where the cap binds, a sub-kernel spans more than x0 and the receiver's texels in its
//   nearer half still shadow it in part: on the Cycles case `grazing` that leaves 3 % of the lit
//   floor too dark against 33 % with n = 1. Testing each sub-kernel against its nearest depth
//   instead (plus half the lead) keeps such a receiver lit but lets the blockers within the
//   sub-kernel's span leak: measured worse on grazing (RMSE 0.125 against 0.070) and lowlight
//   (0.270 against 0.108), so the centre it is. The sums are weighted by each sub-kernel's
//   area inside the map. n = 1 is the thesis's lookup, with d at the pixel's own texel centre.
// - The blocker search narrowed (issue 19; shadows.cssm_narrow passes, 0 the thesis's single
//   search). PCSS's region is the cone of the nearest depth in the whole map, so the first
//   search takes in texels that no cone from the receiver reaches, and the mean blocker depth
//   with them. Each pass searches again over the box of the cone at the mean found so far,
//   widened CSSM_NARROW_MARGIN times (blockers nearer the light than the mean cast wider cones),
//   while that box shrinks: where it holds no blocker the receiver is lit, else its mean is the
//   new one. Ratio to doing nothing's RMSE, 0 -> 2 passes: Cycles cases grazing 0.68 -> 0.43,
//   lowlight 0.75 -> 0.50, overlap 0.35 -> 0.26, shared contact 0.27 -> 0.24 (margin 1.13: 0.45,
//   0.54, 0.26, 0.25; 2: 0.45, 0.49, 0.27, 0.24). Its cost, on a penumbra's outer rim: a box
//   holding a sliver of the blocker gives a mean nearer the light than the blocker, and the
//   penumbra widens into the lit side (tests/gpu/test_cssm.cpp: parallel planes 0.030 -> 0.065
//   against the closed form).
// - Basis resolution: a map larger than shadows.cssm_max_basis a side is averaged in f x f
//   blocks (f = 2^shift, the smallest that fits; edge blocks average the texels they cover)
//   before prefiltering. The basis is linear in the texels, so each block holds exactly the box
//   average of the full-resolution basis; kernels and lookups then work in block units (q/f,
//   h/f). This is what lets 4M + 1 layers of a 4096² map fit a device; where the device's
//   storage-buffer range cannot hold the basis (M = 16 at 1024² on lavapipe's 128 MiB), f grows
//   further on its own.
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "effects/shadowmaps/hsm.h"
#include "effects/shadowmaps/method.h"
#include "effects/shadowmaps/sat.h"
#include "isg/shaders/shadowmap_cssm.spv.h"
#include "isg/shaders/shadowmap_cssm_basis.spv.h"
#include "isg/shaders/shadowmap_cssm_mip.spv.h"
#include "shadowmap_cssm_io.h"

namespace isg::effects {

using detail::Geom;
using detail::kBoxOfDisk;
using detail::kPi;
using detail::Plane;
using detail::Shaded;
using detail::V2;
using detail::V3;

namespace {

constexpr double kMinHalfWidth = 0.5;             // texels: the box covers at least one texel
constexpr double kMinBlockers = 1e-3;             // 1 − s_f below it: no blockers (eq. 5.8)

// The truncated expansion f_M(x) of the visibility (eq. 5.10, f = 1 − f̄).
double f_m(int M, double x) {
  double s = 0.5;
  for (int k = 1; k <= M; ++k) {
    const double c = kPi * (2 * k - 1);
    s -= 2.0 / c * std::sin(c * x);
  }
  return s;
}

// Everything both sides derive from the settings and the map (the CssmParams scalars).
struct Setup {
  int M = 4;
  bool sat = true;
  int shift = 0, bw = 0, bh = 0;  // basis blocks of 2^shift texels a side; basis size
  int split = 1;                  // most sub-kernels a side (shadows.cssm_split)
  int narrow = 0;                 // narrowed blocker searches (shadows.cssm_narrow)
  double alpha = 1.0, x0 = 0.0, s_z = 1.0, zmin = 0.0, zrange = 1.0;
};

Setup make_setup(const ShadowmapData& map, const ShadowmapSettings& s) {
  Setup u;
  u.M = s.cssm_order;
  if (u.M < 1 || u.M > 64) throw std::invalid_argument("shadows.cssm_order out of range");
  if (s.cssm_filter != "sat" && s.cssm_filter != "mipmap")
    throw std::invalid_argument("shadows.cssm_filter must be sat or mipmap");
  u.sat = s.cssm_filter == "sat";
  if (s.cssm_max_basis < 1) throw std::invalid_argument("shadows.cssm_max_basis out of range");
  if (s.cssm_split < 1 || s.cssm_split > 8) throw std::invalid_argument("shadows.cssm_split out of range");
  u.split = s.cssm_split;
  if (s.cssm_narrow < 0 || s.cssm_narrow > 4) throw std::invalid_argument("shadows.cssm_narrow out of range");
  u.narrow = s.cssm_narrow;
  while (std::max(map.width, map.height) > (s.cssm_max_basis << u.shift)) ++u.shift;
  u.bw = (map.width + (1 << u.shift) - 1) >> u.shift;
  u.bh = (map.height + (1 << u.shift) - 1) >> u.shift;
  // f_M's extrema lie at x = j / (2M); its lit-side troughs at even j (§5.2.3).
  double trough = 1.0;
  for (int j = 2; j <= 2 * u.M - 2; j += 2) trough = std::min(trough, f_m(u.M, -j / (2.0 * u.M)));
  u.alpha = 1.0 / (2.0 * trough - 1.0);
  const double target = 0.5 + 0.5 / u.alpha;
  double lo = 0.0, hi = 1.0 / (2.0 * u.M);  // f_M(−t) rises monotonically to its first crest
  for (int it = 0; it < 60; ++it) {
    const double m = 0.5 * (lo + hi);
    (f_m(u.M, -m) < target ? lo : hi) = m;
  }
  u.x0 = hi;
  u.s_z = 1.0 - 2.0 * u.x0;
  double zmax = -1.0;
  for (float v : map.z)
    if (v > 0.0f && v < ISG_BACKGROUND_DEPTH) zmax = std::max(zmax, double(v));
  if (zmax < 0.0) return u;  // no blockers at all: every receiver is lit
  u.zmin = map.min_depth;
  u.zrange = std::max(zmax - u.zmin, 1e-6 * std::max(u.zmin, 1e-30));
  return u;
}

// SAT fixed point (shadowmap_cssm_io.h): every basis value lies in [−1, 1], so a rectangle of
// A block texels sums to at most A units of value; a power of two (exact in float) that keeps
// A · scale within 2^30 for the largest rectangle a kernel reads (the box of the widest search
// or filter, shadows.smap_max_radius, plus a texel, within the basis) keeps its 32-bit integer
// sum exact in wrapping arithmetic.
double sat_scale(const Setup& u, const ShadowmapSettings& s) {
  const double side = std::ceil(2.0 * std::max(kBoxOfDisk * s.max_radius, kMinHalfWidth) /
                                double(1 << u.shift)) + 2.0;
  const double area = std::min(side, double(u.bw)) * std::min(side, double(u.bh));
  return std::ldexp(1.0, 30 - int(std::ceil(std::log2(std::max(area, 1.0)))));
}

double norm_depth(const Setup& u, double z) {
  if (!(z > 0.0 && z < ISG_BACKGROUND_DEPTH)) return 1.0;
  return std::clamp((z - u.zmin) / u.zrange, 0.0, 1.0);
}

struct Levels {
  std::vector<int> w, h;
};
Levels mip_levels(int w, int h, bool sat) {
  Levels L{{w}, {h}};
  if (sat) return L;
  while (L.w.back() > 1 || L.h.back() > 1) {
    L.w.push_back(std::max(1, (L.w.back() + 1) / 2));
    L.h.push_back(std::max(1, (L.h.back() + 1) / 2));
  }
  return L;
}

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
              acc[size_t(k)] += cs;
              acc[size_t(u.M + k)] += sn;
              acc[size_t(2 * u.M + k)] += z * cs;
              acc[size_t(3 * u.M + k)] += z * sn;
            }
            acc[size_t(4 * u.M)] += z;
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

namespace detail {
namespace {
// The shading pass's slots: `tab` as a texel view (its whole, beyond a storage buffer's range).
std::vector<gpu::Slot> cssm_slots() {
  std::vector<gpu::Slot> s(12, gpu::Slot::buffer);
  s[8] = gpu::Slot::texels;
  return s;
}

// CSSM on the GPU: basis images (one dispatch for all 4M + 1), prefiltering (the 32-bit SAT
// scans, or one dispatch per mip level), then the shading kernel.
class Cssm final : public ShadowmapMethod {
 public:
  Cssm(gpu::Context& ctx, const ShadowmapSettings& s, const ShadowmapData& map, uint32_t w,
       uint32_t h, bool has_position)
      : basis_(ctx, "shadows.cssm.basis", isg_spv_shadowmap_cssm_basis,
               std::vector<gpu::Slot>(5, gpu::Slot::buffer), sizeof(shaders::CssmPush),
               CSSM_LOCAL, CSSM_LOCAL, {0u, s.cssm_filter == "mipmap" ? 1u : 0u}),
        shade_(ctx, "shadows.cssm", isg_spv_shadowmap_cssm,
               cssm_slots(), sizeof(shaders::ShadowmapPush),
               SHADOWMAP_LOCAL, SHADOWMAP_LOCAL, {0u, s.cssm_filter == "mipmap" ? 1u : 0u}),
        // The pixels the search finds blockers for (shadowmap_common.h's sm_pixel_of).
        own_k_(ctx, "shadows.cssm.own", isg_spv_shadowmap_cssm,
               cssm_slots(), sizeof(shaders::ShadowmapPush),
               SHADOWMAP_LOCAL, SHADOWMAP_LOCAL, {1u, s.cssm_filter == "mipmap" ? 1u : 0u}),
        own_(ctx, w, h),
        hsm_levels_(detail::hsm_levels(map)),
        hsm_(ctx, hsm_levels_),
        w_(w),
        h_(h),
        map_w_(uint32_t(map.width)),
        map_h_(uint32_t(map.height)) {
    Setup u = make_setup(map, s);
    const uint32_t groups = 2u * uint32_t((u.M + 1) / 2);
    // The basis's texels: `groups` uvec4 each in one storage buffer; where the device's range
    // cannot hold them, the basis is block-averaged further (as shadows.cssm_max_basis does).
    auto texels_of = [](const Setup& v) {
      const Levels L = mip_levels(v.bw, v.bh, v.sat);
      uint64_t n = 0;
      for (size_t l = 0; l < L.w.size(); ++l) n += uint64_t(L.w[l]) * uint64_t(L.h[l]);
      return n;
    };
    // A half of `tab` within a storage buffer's range, the whole within a texel view's
    // (shadowmap_cssm_io.h).
    auto fits = [&](const Setup& v) {
      const uint64_t half = texels_of(v) * (groups / 2u);
      return half * 16u <= ctx.info().max_storage_buffer_range &&
             2u * half <= ctx.info().max_texel_buffer_elements;
    };
    while (!fits(u) && u.bw * u.bh > 1) {
      ++u.shift;
      u.bw = (map.width + (1 << u.shift) - 1) >> u.shift;
      u.bh = (map.height + (1 << u.shift) - 1) >> u.shift;
    }
    const Levels L = mip_levels(u.bw, u.bh, u.sat);
    if (L.w.size() > CSSM_MAX_LEVELS) throw std::invalid_argument("cssm: shadow map too large");
    shaders::CssmParams c{};
    c.order = uint32_t(u.M);
    if (u.M > CSSM_MAX_ORDER) throw std::invalid_argument("cssm: order above 16");
    c.prefilter = u.sat ? CSSM_FILTER_SAT : CSSM_FILTER_MIPMAP;
    c.groups = groups;
    c.basis_shift = uint32_t(u.shift);
    c.max_split = uint32_t(u.split);
    c.narrow = uint32_t(u.narrow);
    c.levels = uint32_t(L.w.size());
    c.zmin = float(u.zmin);
    c.zrange = float(u.zrange);
    c.s_z = float(u.s_z);
    c.x0 = float(u.x0);
    c.alpha = float(u.alpha);
    c.sharpen_a = float(s.cssm_a);
    c.sharpen_b = float(s.cssm_b);
    c.sat_scale = float(sat_scale(u, s));
    c.hsm = hsm_levels_gpu(hsm_levels_);
    uint64_t texels = 0;
    for (size_t l = 0; l < L.w.size(); ++l) {
      c.level_w[l] = uint32_t(L.w[l]);
      c.level_h[l] = uint32_t(L.h[l]);
      c.level_off[l] = uint32_t(texels);
      texels += uint64_t(L.w[l]) * uint64_t(L.h[l]);
    }
    // The CSM-Z half from a 256-byte boundary (any device's storage-buffer offset alignment).
    c.half_texels = uint32_t((texels * (groups / 2u) + 15u) / 16u * 16u);
    half_bytes_ = uint64_t(c.half_texels) * 16u;
    cparams_ = c;
    const shaders::ShadowmapParams p = shadowmap_params(s, map, w, h, has_position, 0u);
    params_ = gpu::Buffer(ctx, sizeof(p), "shadowmap.params");
    params_.upload(&p, sizeof(p));
    cssm_params_ = gpu::Buffer(ctx, sizeof(c), "shadowmap.cssm.params");
    cssm_params_.upload(&c, sizeof(c));
    tab_ = gpu::Buffer(ctx, 2u * half_bytes_, u.sat ? "shadowmap.cssm.sat" : "shadowmap.cssm.mip");
    tz_ = gpu::Buffer(ctx, texels * 4u, u.sat ? "shadowmap.cssm.sat_z" : "shadowmap.cssm.mip_z");
    if (u.sat)
      scan_.emplace(ctx);
    else
      mip_.emplace(ctx, "shadows.cssm.mip", isg_spv_shadowmap_cssm_mip,
                   std::vector<gpu::Slot>(4, gpu::Slot::buffer), sizeof(shaders::CssmPush),
                   CSSM_LOCAL, CSSM_LOCAL);
    stats_ = zeroed_stats(ctx);
  }

  void record(gpu::Sequence& seq, const gpu::Buffer& geo, const gpu::Buffer& fg,
              const gpu::Buffer& hard, const gpu::Buffer& map, const gpu::Buffer& soft,
              const std::string& label) override {
    const auto& c = cparams_;
    hsm_.record(seq, map, label);
    shaders::CssmPush bp{map_w_, map_h_, 0u, 0u};
    const std::vector<gpu::Binding> bb{gpu::Binding::of(cssm_params_), gpu::Binding::of(map),
                                       tab_half(0), tab_half(1), gpu::Binding::of(tz_)};
    if (scan_) {
      // A lane per basis row and part (shadowmap_cssm_basis.comp), the rows summed; then the
      // columns.
      const uint32_t lines = c.level_h[0] * (c.groups / 2u + 1u);
      seq.dispatch(basis_, bb, bp, CSSM_BASIS_ROW, (lines + CSSM_BASIS_ROW - 1) / CSSM_BASIS_ROW,
                   label + ".basis");
      scan_->record(seq, tab_half(0), c.level_w[0], c.level_h[0], 2u * c.groups, label + ".sat", false);
      scan_->record(seq, tab_half(1), c.level_w[0], c.level_h[0], 2u * c.groups, label + ".sat", false);
      scan_->record(seq, gpu::Binding::of(tz_), c.level_w[0], c.level_h[0], 1u, label + ".sat_z", false);
    } else {
      seq.dispatch(basis_, bb, bp, c.level_w[0], c.level_h[0], label + ".basis");
      for (uint32_t l = 1; l < c.levels; ++l) {
        shaders::CssmPush mp{c.level_w[l], c.level_h[l], l, 0u};
        seq.dispatch(*mip_,
                     {gpu::Binding::of(cssm_params_), tab_half(0), tab_half(1), gpu::Binding::of(tz_)},
                     mp, c.level_w[l] * (c.groups + 1u), c.level_h[l], label + ".mip");
      }
    }
    shaders::ShadowmapPush pc{w_, h_};
    const std::vector<gpu::Binding> b{
        gpu::Binding::of(params_), gpu::Binding::of(cssm_params_), gpu::Binding::of(geo),
        gpu::Binding::of(fg), gpu::Binding::of(hard), gpu::Binding::of(map),
        gpu::Binding::of(soft), gpu::Binding::of(stats_),
        gpu::Binding::texels(tab_, VK_FORMAT_R32G32B32A32_UINT),
        gpu::Binding::of(tz_), gpu::Binding::of(hsm_.buffer()), gpu::Binding::of(own_.buffer())};
    own_.reset(seq, label + ".list");
    seq.dispatch(shade_, b, pc, w_, h_, label);
    own_.dispatch(seq, own_k_, b, pc, label + ".own");
  }
  ShadowmapStats stats() const override { return read_stats(stats_); }
  // Half k of `tab` (0: CSM, 1: CSM-Z) as a storage buffer of its own.
  gpu::Binding tab_half(int k) const { return gpu::Binding::part(tab_, k * half_bytes_, half_bytes_); }
  uint64_t gpu_bytes() const override {
    return params_.size() + cssm_params_.size() + stats_.size() + tab_.size() + tz_.size() +
           hsm_.buffer().size() + own_.buffer().size();
  }

 private:
  gpu::Kernel basis_, shade_, own_k_;
  OwnList own_;
  HsmLevels hsm_levels_;
  HsmPass hsm_;
  std::optional<gpu::Kernel> mip_;  // the mipmap filter's
  std::optional<SatScan32> scan_;   // the SAT filter's
  gpu::Buffer params_, cssm_params_, stats_, tab_, tz_;
  shaders::CssmParams cparams_{};
  uint64_t half_bytes_ = 0;
  uint32_t w_, h_, map_w_, map_h_;
};
}  // namespace

std::unique_ptr<ShadowmapMethod> make_cssm(gpu::Context& ctx, const ShadowmapSettings& s,
                                           const ShadowmapData& map, uint32_t w, uint32_t h,
                                           bool has_position) {
  return std::make_unique<Cssm>(ctx, s, map, w, h, has_position);
}
}  // namespace detail

}  // namespace isg::effects
