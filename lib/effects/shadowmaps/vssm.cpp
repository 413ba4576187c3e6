// Variance soft shadow maps (thesis ch. 7): the GPU method (passes shadows.vssm.hsm, the two
// SATs, shadows.vssm) and its double-precision mirror. The per-pixel algorithm, the narrowed
// blocker search (shadows.vssm_narrow) with it, is commented in shaders/shadowmap_vssm.glsl;
// this file follows it line for line (its filter chain with the shader's repeated branches
// merged).
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "effects/shadowmaps/hsm.h"
#include "effects/shadowmaps/method.h"
#include "effects/shadowmaps/sat.h"
#include "isg/shaders/shadowmap_vssm.spv.h"
#include "isg/shaders/shadowmap_vssm64.spv.h"
#include "shadowmap_io.h"
#include "shadowmap_vssm_io.h"

namespace isg::effects {

namespace {
using detail::Geom;
using detail::kBoxOfDisk;
using detail::Plane;
using detail::Shaded;
using detail::V3;

// What both sides derive from the map and the settings.
struct VssmSetup {
  double far_z = 0, z0 = 0;
  SatFixedPoint f1, f2;  // the SATs of z and (z − z0)²
  detail::HsmLevels hsm;
};

VssmSetup vssm_setup(const ShadowmapData& map) {
  VssmSetup v;
  v.hsm = detail::hsm_levels(map);
  v.far_z = v.hsm.far_z;
  double sum = 0;
  for (float z : map.z) sum += std::min(double(z), v.far_z);
  v.z0 = double(float(map.z.empty() ? 0.0 : sum / double(map.z.size())));
  v.f1 = sat_fixed_point(map.z, 1, v.far_z);
  v.f2 = sat_fixed_point(map.z, 2, v.far_z, v.z0);
  return v;
}

// The first blocker search's split (shadows.vssm_m_wide where narrowed searches follow).
int first_m(const ShadowmapSettings& s) { return s.vssm_narrow > 0 ? s.vssm_m_wide : s.vssm_m; }

int leaf_grid(const ShadowmapSettings& s) {
  return s.vssm_leaf_taps <= 0 ? 0 : std::max(1, int(std::lround(std::sqrt(double(s.vssm_leaf_taps)))));
}

// The double mirror: HSM, the two prefix-sum tables, and the per-pixel algorithm.
struct VssmRef {
  const Geom& G;
  const ShadowmapSettings& s;
  VssmSetup v;
  detail::HsmRef hsm;
  std::vector<double> s1, s2;  // (w+1) x (h+1) prefix sums of z and (z − z0)²
  int W, Hh, grid;
  double flat, contact;

  VssmRef(const Geom& g, const ShadowmapSettings& st)
      : G(g), s(st), v(vssm_setup(g.map)), hsm(g.map, v.hsm), W(g.map.width), Hh(g.map.height),
        grid(leaf_grid(st)) {
    flat = s.vssm_flat * s.scene_radius;
    contact = s.vssm_contact * s.scene_radius;
    // The SATs of z and (z − z0)² as the GPU builds them: each texel's fixed-point integer
    // (sat_quantize, float arithmetic as in the shader), worth q / scale + offset.
    s1.assign(size_t(W + 1) * (Hh + 1), 0.0);
    s2 = s1;
    for (int y = 0; y < Hh; ++y) {
      double r1 = 0, r2 = 0;
      for (int x = 0; x < W; ++x) {
        const float z = G.map.z[size_t(y) * W + x];
        r1 += double(sat_quantize(z, v.f1)) / v.f1.scale + double(float(v.f1.offset));
        r2 += double(sat_quantize(z, v.f2)) / v.f2.scale + double(float(v.f2.offset));
        s1[size_t(y + 1) * (W + 1) + x + 1] = s1[size_t(y) * (W + 1) + x + 1] + r1;
        s2[size_t(y + 1) * (W + 1) + x + 1] = s2[size_t(y) * (W + 1) + x + 1] + r2;
      }
    }
  }

  using F2 = std::array<double, 2>;
  std::array<double, 2> hsm_range(F2 flo, F2 fhi) const { return hsm.range(flo, fhi); }
  // Σ over texels of (covered fraction) · value: the box filter of [lo, hi) on the texel grid.
  double box_sum(const std::vector<double>& t, F2 lo, F2 hi) const {
    auto R = [&](int x, int y) { return t[size_t(y) * (W + 1) + x]; };
    auto runs = [](double a, double b, std::array<int, 3>& from, std::array<int, 3>& to,
                   std::array<double, 3>& wt) {
      const int i0 = int(std::floor(a)), i1 = int(std::ceil(b)) - 1;
      if (i0 >= i1) { from = {i0, 0, 0}; to = {i0 + 1, 0, 0}; wt = {b - a, 0, 0}; return; }
      from = {i0, i0 + 1, i1};
      to = {i0 + 1, i1, i1 + 1};
      wt = {double(i0 + 1) - a, 1.0, b - double(i1)};
    };
    std::array<int, 3> fx, tx, fy, ty;
    std::array<double, 3> wx, wy;
    runs(lo[0], hi[0], fx, tx, wx);
    runs(lo[1], hi[1], fy, ty, wy);
    double sum = 0;
    for (int j = 0; j < 3; ++j) {
      if (ty[size_t(j)] <= fy[size_t(j)]) continue;
      for (int i = 0; i < 3; ++i) {
        if (tx[size_t(i)] <= fx[size_t(i)]) continue;
        const int x0 = fx[size_t(i)], x1 = tx[size_t(i)], y0 = fy[size_t(j)], y1 = ty[size_t(j)];
        sum += wx[size_t(i)] * wy[size_t(j)] * (R(x1, y1) - R(x0, y1) - R(x1, y0) + R(x0, y0));
      }
    }
    return sum;
  }
  struct Moments { double T, ez, ez2; };
  Moments moments(F2 lo, F2 hi) const {
    const double T = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    return {T, box_sum(s1, lo, hi) / T, box_sum(s2, lo, hi) / T};
  }
  double variance(double ez, double ez2) const {
    return std::max(ez2 - (ez - v.z0) * (ez - v.z0), 0.0);
  }
  static void cell(F2 a, F2 b, int n, int ix, int iy, F2& lo, F2& hi) {
    const double sx = (b[0] - a[0]) / n, sy = (b[1] - a[1]) / n;
    lo = {a[0] + sx * ix, a[1] + sy * iy};
    hi = {a[0] + sx * (ix + 1), a[1] + sy * (iy + 1)};
  }
  static bool empty(F2 lo, F2 hi) { return hi[0] - lo[0] < 1e-3 || hi[1] - lo[1] < 1e-3; }
  // kr > 0 (the filter's): blockers only within reach (Geom::reaches).
  double pcf(F2 lo, F2 hi, int g, const V3& q, const Plane& gr, double tw, double kr, double& nb,
             double& zb) const {
    nb = zb = 0;
    for (int j = 0; j < g; ++j)
      for (int i = 0; i < g; ++i) {
        const double cx = std::min(std::floor(lo[0] + (i + 0.5) / g * (hi[0] - lo[0])), double(W - 1)) + 0.5;
        const double cy = std::min(std::floor(lo[1] + (j + 0.5) / g * (hi[1] - lo[1])), double(Hh - 1)) + 0.5;
        const double z = G.fetch(cx, cy);
        if (z < G.threshold(q, gr, cx, cy, tw) && G.reaches(q, cx, cy, z, kr)) { nb += 1; zb += z; }
      }
    return 1.0 - nb / double(g * g);
  }
  void square(const V3& q, double r, F2& lo, F2& hi) const {
    r = std::max(r, 0.5);
    lo = {std::max(q[0] - r, 0.0), std::max(q[1] - r, 0.0)};
    hi = {std::min(q[0] + r, double(W)), std::min(q[1] + r, double(Hh))};
  }
  double threshold_at(const V3& q, const Plane& g, F2 lo, F2 hi, double tw) const {
    return G.threshold(q, g, 0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), tw);
  }

  // The receiver's threshold stays within gap = t − E(z) over [lo, hi) (shadowmap_vssm.comp).
  bool threshold_flat(const V3& q, const Plane& g, F2 lo, F2 hi, double tw, double gap) const {
    const auto tr = G.threshold_range(q, g, lo, hi, tw);
    return tr[1] - tr[0] < gap;
  }

  // Eq. 7.1: the lit fraction of depths of mean mu and variance var against threshold t; the
  // filter takes it per sub-kernel, the search on the pooled moments (shadowmap_vssm.glsl's
  // chebyshev says why).
  static double chebyshev(double mu, double var, double t) {
    const double d = t - mu;
    return d > 0 ? var / (var + d * d) : 1.0;
  }

  int hsm_verdict(const V3& q, const Plane& g, F2 lo, F2 hi, double tw) const {
    const auto zr = hsm_range(lo, hi);
    const auto tr = G.threshold_range(q, g, lo, hi, tw);
    return zr[0] >= tr[1] ? 1 : (zr[1] < tr[0] ? -1 : 0);
  }

  // The blocker search over [a, b) (Algorithm 2, L11-L15): whether it finds blockers, and their
  // mean depth zavg.
  bool blocker_search(const V3& q, const Plane& g, double tw, double unbias, F2 a, F2 b, int m,
                      double& zavg) const {
    double sA = 0, sZ = 0, sZ2 = 0, sT = 0, bPcf = 0, zPcf = 0;
    for (int iy = 0; iy < m; ++iy)
      for (int ix = 0; ix < m; ++ix) {
        F2 lo, hi;
        cell(a, b, m, ix, iy, lo, hi);
        if (empty(lo, hi)) continue;
        const int hv = hsm_verdict(q, g, lo, hi, tw);
        if (hv > 0) continue;
        const Moments mo = moments(lo, hi);
        const double t = threshold_at(q, g, lo, hi, tw);
        const bool flat_t = mo.ez < t && threshold_flat(q, g, lo, hi, tw, t - mo.ez);
        if (hv < 0) {
          bPcf += mo.T; zPcf += mo.ez * mo.T;
        } else if (flat_t || (mo.ez < t && grid == 0)) {
          sA += mo.T; sZ += mo.ez * mo.T; sZ2 += mo.ez2 * mo.T; sT += (t + unbias) * mo.T;
        } else if ((mo.ez < t || variance(mo.ez, mo.ez2) >= flat) && grid > 0) {
          double nb, zb;
          pcf(lo, hi, grid, q, g, tw, 0.0, nb, zb);
          const double n = double(grid * grid);
          bPcf += mo.T * nb / n;
          zPcf += mo.T * zb / n;
        }
      }
    double bVsm = 0, zVsm = 0;
    if (sA > 0) {
      const double mu = sZ / sA, t = sT / sA, var = variance(mu, sZ2 / sA);
      if (mu < t) {
        const double lit = chebyshev(mu, var, t);
        if (lit < 1.0 - 1e-6) {
          bVsm = (1.0 - lit) * sA;
          zVsm = (mu - lit * t) / (1.0 - lit) * bVsm;
        }
      }
    }
    if (bVsm + bPcf <= 0) return false;
    zavg = std::clamp((zVsm + zPcf) / (bVsm + bPcf), G.map.min_depth, q[2]);
    return true;
  }

  // One pixel inside the map, not back-facing.
  Shaded shade(int px, int py, const V3& q_in, const Plane& g, ShadowmapStats& st) const {
    // A receiver beyond the map's farthest surface (far_z, where the background stands in the
    // SATs and the HSM) is shaded as lying on it: else the background would block it. (A
    // surface at far_z itself then no longer blocks it; the background a quarter farther,
    // tried, kept that but cost grazing 0.062 -> 0.080 and lowlight 0.242 -> 0.301 RMSE.)
    const V3 q = {q_in[0], q_in[1], std::min(q_in[2], v.far_z)};
    const double tw = G.texel_world(q[2]);
    const double k = G.k();
    (void)px;
    (void)py;
    const double rs = G.cone_radius(k, G.map.min_depth, q[2], 1.0, s.max_radius);
    F2 a, b;
    square(q, rs, a, b);
    const double lim = g[3] * tw * (rs + 1.0) * 1.5;
    const double unbias = s.bias * tw + s.spread_bias * g[2];
    const double base = q[2] - s.bias * tw - s.spread_bias * g[2];
    const auto zr = hsm_range(a, b);
    if (zr[0] >= base + lim) { ++st.skipped; return {1.0, 0.0}; }
    if (zr[1] < base - lim) { ++st.skipped; return {0.0, 0.0}; }
    // The search narrowed to the blockers' cone (the top of the file), while it shrinks.
    double zavg = 0;
    bool found = blocker_search(q, g, tw, unbias, a, b, first_m(s), zavg);
    double hs = std::max(rs, 0.5);
    for (int pass = 0; found && pass < s.vssm_narrow; ++pass) {
      const double hn = G.cone_box(k, zavg, q[2], VSSM_NARROW_MARGIN, s.max_radius);
      if (hn >= hs) break;
      square(q, hn, a, b);
      found = blocker_search(q, g, tw, unbias, a, b, s.vssm_m, zavg);
      hs = hn;
    }
    if (!found) { ++st.skipped; return {1.0, 0.0}; }
    double rf = k * G.gap(zavg, q[2]);
    if (rf > s.max_radius) { rf = s.max_radius; ++st.clamped; }
    square(q, kBoxOfDisk * rf, a, b);
    if (q[2] - zavg < contact) {
      ++st.contact;
      double nb, zb;
      square(q, std::max(rf, 1.0), a, b);
      return {pcf(a, b, 3, q, g, tw, s.reach * k, nb, zb), rf};
    }
    double lA = 0, uA = 0, fA = 0, fLit = 0;
    int level = 0, nx = 0, ny = 0;
    for (;;) {
      F2 lo, hi;
      cell(a, b, 1 << level, nx, ny, lo, hi);
      bool down = false;
      const int hv = empty(lo, hi) ? 2 : hsm_verdict(q, g, lo, hi, tw);
      const double T = (hi[0] - lo[0]) * (hi[1] - lo[1]);
      if (hv == 1) {
        lA += T;
      } else if (hv == -1) {
        uA += T;
      } else if (hv == 0) {
        const Moments mo = moments(lo, hi);
        const double t = threshold_at(q, g, lo, hi, tw);
        const double var = variance(mo.ez, mo.ez2);
        const bool flat_t = mo.ez < t && threshold_flat(q, g, lo, hi, tw, t - mo.ez);
        // The shader's chain, its two lit and its two Chebyshev branches each as one: a leaf
        // without PCF (plain) is lit behind the receiver and Chebyshev's in front of it.
        const bool leaf = level >= s.vssm_h, plain = leaf && grid <= 0;
        if (mo.ez >= t && (var < flat || plain)) {
          lA += mo.T;
        } else if (flat_t || (plain && mo.ez < t)) {
          fLit += mo.T * chebyshev(mo.ez, var, t + unbias);
          fA += mo.T;
        } else if (!leaf) {
          down = true;
        } else {
          double nb, zb;
          fLit += mo.T * pcf(lo, hi, grid, q, g, tw, s.reach * k, nb, zb);
          fA += mo.T;
        }
      }
      if (down) { ++level; nx *= 2; ny *= 2; continue; }
      bool done = false;
      for (;;) {
        if (level == 0) { done = true; break; }
        if ((nx & 1) == 0) { ++nx; break; }
        if ((ny & 1) == 0) { --nx; ++ny; break; }
        --level; nx >>= 1; ny >>= 1;
      }
      if (done) break;
    }
    return {(lA + fLit) / (lA + uA + fA), rf};
  }
};

shaders::VssmParams vssm_params(const ShadowmapSettings& s, const VssmSetup& v) {
  if (s.vssm_narrow < 0 || s.vssm_narrow > 4) throw std::invalid_argument("shadows.vssm_narrow out of range");
  shaders::VssmParams p{};
  p.m = uint32_t(s.vssm_m);
  p.m_first = uint32_t(first_m(s));
  p.tree_h = uint32_t(s.vssm_h);
  p.leaf_grid = uint32_t(leaf_grid(s));
  p.flat_var = float(s.vssm_flat * s.scene_radius);
  p.contact = float(s.vssm_contact * s.scene_radius);
  p.z0 = float(v.z0);
  p.off1 = float(v.f1.offset);
  p.scale1 = float(v.f1.scale);
  p.off2 = float(v.f2.offset);
  p.scale2 = float(v.f2.scale);
  p.narrow = uint32_t(s.vssm_narrow);
  p.hsm = detail::hsm_levels_gpu(v.hsm);
  return p;
}

std::span<const uint32_t> vssm_spirv(gpu::Context& ctx) {
  return ctx.info().float64 ? std::span<const uint32_t>(isg_spv_shadowmap_vssm64)
                            : std::span<const uint32_t>(isg_spv_shadowmap_vssm);
}
std::vector<gpu::Slot> vssm_slots() {
  return {gpu::Slot::buffer, gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels,
          gpu::Slot::texels, gpu::Slot::buffer, gpu::Slot::texels, gpu::Slot::texels,
          gpu::Slot::buffer, gpu::Slot::buffer, gpu::Slot::buffer, gpu::Slot::texels};
}

class Vssm final : public detail::ShadowmapMethod {
 public:
  Vssm(gpu::Context& ctx, const ShadowmapSettings& s, const ShadowmapData& map, uint32_t w,
       uint32_t h, bool has_position)
      : v_(vssm_setup(map)),
        hsm_(ctx, v_.hsm),
        // The moments in double where the device can (shadowmap_vssm.glsl's VSSM_REAL); two
        // dispatches, the HSM's verdict and the listed pixels' filters (SM_OWN).
        shade_k_(ctx, "shadows.vssm", vssm_spirv(ctx), vssm_slots(), sizeof(shaders::ShadowmapPush),
                 SHADOWMAP_LOCAL, SHADOWMAP_LOCAL, {0u}),
        own_k_(ctx, "shadows.vssm.own", vssm_spirv(ctx), vssm_slots(),
               sizeof(shaders::ShadowmapPush), SHADOWMAP_LOCAL, SHADOWMAP_LOCAL, {1u}),
        own_(ctx, w, h),
        sat_pass_(ctx), w_(w), h_(h), mw_(uint32_t(map.width)),
        mh_(uint32_t(map.height)) {
    const auto p = shadowmap_params(s, map, w, h, has_position, 0u);
    params_ = gpu::Buffer(ctx, sizeof(p), "vssm.params");
    params_.upload(&p, sizeof(p));
    const auto vp = vssm_params(s, v_);
    vparams_ = gpu::Buffer(ctx, sizeof(vp), "vssm.vparams");
    vparams_.upload(&vp, sizeof(vp));
    const size_t texels = map.z.size();
    // The SATs of z and (z − z0)², a buffer each: interleaved, a 4096² map's pair (256 MiB)
    // would exceed a storage buffer's range on lavapipe (128 MiB) in sat.quantize and sat.scan.
    sat1_ = gpu::Buffer(ctx, texels * 8, "vssm.sat_z");
    sat2_ = gpu::Buffer(ctx, texels * 8, "vssm.sat_z2");
    stats_ = detail::zeroed_stats(ctx);
  }
  void record(gpu::Sequence& seq, const gpu::Buffer& geo, const gpu::Buffer& fg,
              const gpu::Buffer& hard, const gpu::Buffer& map, const gpu::Buffer& soft,
              const std::string& label) override {
    // Min-max HSM, level by level (thesis §7.5.1); level 0 is the map itself.
    hsm_.record(seq, map, label);
    sat_pass_.record(seq, map, sat1_, mw_, mh_, v_.f1, label + ".sat_z");
    sat_pass_.record(seq, map, sat2_, mw_, mh_, v_.f2, label + ".sat_z2");
    shaders::ShadowmapPush pc{w_, h_};
    const std::vector<gpu::Binding> b{
        gpu::Binding::of(params_), gpu::Binding::floats(geo), gpu::Binding::floats(fg),
        gpu::Binding::floats(hard), gpu::Binding::floats(map), gpu::Binding::of(vparams_),
        gpu::Binding::texels(hsm_.buffer(), VK_FORMAT_R32G32_SFLOAT),
        gpu::Binding::texels(sat1_, VK_FORMAT_R32G32_UINT), gpu::Binding::of(soft),
        gpu::Binding::of(stats_), gpu::Binding::of(own_.buffer()),
        gpu::Binding::texels(sat2_, VK_FORMAT_R32G32_UINT)};
    own_.reset(seq, label + ".list");
    seq.dispatch(shade_k_, b, pc, w_, h_, label);
    own_.dispatch(seq, own_k_, b, pc, label + ".own");
  }
  ShadowmapStats stats() const override { return detail::read_stats(stats_); }
  uint64_t gpu_bytes() const override {
    return params_.size() + vparams_.size() + hsm_.buffer().size() + sat1_.size() + sat2_.size() + own_.buffer().size() +
           stats_.size();
  }

 private:
  VssmSetup v_;
  detail::HsmPass hsm_;
  gpu::Kernel shade_k_, own_k_;
  detail::OwnList own_;
  SatPass sat_pass_;
  gpu::Buffer params_, vparams_, sat1_, sat2_, stats_;
  uint32_t w_, h_, mw_, mh_;
};
}  // namespace

std::vector<float> vssm_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                  const ShadowmapSettings& s, ShadowmapStats* stats) {
  Geom G(in, map, s);
  VssmRef R(G, s);
  ShadowmapStats st;
  auto out = detail::shade_receivers(
      G, st, [&](int px, int py, const V3& q, const Plane& g, const V3&, const V3&) { return R.shade(px, py, q, g, st); });
  if (stats) *stats = st;
  return out;
}

namespace detail {
std::unique_ptr<ShadowmapMethod> make_vssm(gpu::Context& ctx, const ShadowmapSettings& s,
                                           const ShadowmapData& map, uint32_t w, uint32_t h,
                                           bool has_position) {
  return std::make_unique<Vssm>(ctx, s, map, w, h, has_position);
}
}  // namespace detail

}  // namespace isg::effects
