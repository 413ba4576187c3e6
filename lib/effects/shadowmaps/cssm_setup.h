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
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "effects/shadowmaps/method.h"
#include "shadowmap_cssm_io.h"

// What cssm.cpp (the GPU passes) and cssm_reference.cpp (their double mirror) share: the
// expansion's set-up, the SAT's scale, the depth normalisation and the mip chain.
namespace isg::effects::detail::cssm {

constexpr double kMinHalfWidth = 0.5;             // texels: the box covers at least one texel
constexpr double kMinBlockers = 1e-3;             // 1 − s_f below it: no blockers (eq. 5.8)

// The truncated expansion f_M(x) of the visibility (eq. 5.10, f = 1 − f̄).
inline double f_m(int M, double x) {
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

inline Setup make_setup(const ShadowmapData& map, const ShadowmapSettings& s) {
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
inline double sat_scale(const Setup& u, const ShadowmapSettings& s) {
  const double side = std::ceil(2.0 * std::max(kBoxOfDisk * s.max_radius, kMinHalfWidth) /
                                double(1 << u.shift)) + 2.0;
  const double area = std::min(side, double(u.bw)) * std::min(side, double(u.bh));
  return std::ldexp(1.0, 30 - int(std::ceil(std::log2(std::max(area, 1.0)))));
}

inline double norm_depth(const Setup& u, double z) {
  if (!(z > 0.0 && z < ISG_BACKGROUND_DEPTH)) return 1.0;
  return std::clamp((z - u.zmin) / u.zrange, 0.0, 1.0);
}

struct Levels {
  std::vector<int> w, h;
};
inline Levels mip_levels(int w, int h, bool sat) {
  Levels L{{w}, {h}};
  if (sat) return L;
  while (L.w.back() > 1 || L.h.back() > 1) {
    L.w.push_back(std::max(1, (L.w.back() + 1) / 2));
    L.h.push_back(std::max(1, (L.h.back() + 1) / 2));
  }
  return L;
}

}  // namespace isg::effects::detail::cssm
