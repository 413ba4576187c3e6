#include "effects/dof/dof.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "effects/sampling.h"
#include "dof_coc_io.h"
#include "dof_gather_io.h"
#include "dof_layered_io.h"
#include "dof_search_io.h"
#include "dof_tiles_io.h"
#include "isg/shaders/dof_coc.spv.h"
#include "isg/shaders/dof_gather.spv.h"
#include "isg/shaders/dof_layered.spv.h"
#include "isg/shaders/dof_search.spv.h"
#include "isg/shaders/dof_tiles.spv.h"

namespace isg::effects {


namespace {

constexpr double kPi = std::numbers::pi;
using V2 = std::array<double, 2>;
using V4 = std::array<double, 4>;

// dof.anamorphic s: the aperture 1/√s across and √s down (dof_common.h's dof_stretch), as the
// floats the shaders get.
float stretch_x(const DofSettings& s) { return float(1.0 / std::sqrt(s.anamorphic)); }
float stretch_y(const DofSettings& s) { return float(std::sqrt(s.anamorphic)); }
float reach_scale(const DofSettings& s) { return std::max(stretch_x(s), stretch_y(s)); }

// The tiles' reach test accepts (|c| + 1) · reach_scale: the margin holds it (at scale 1,
// ceil(max_coc) + 1 as before).
uint32_t margin_of(const DofSettings& s) { return uint32_t(std::ceil((s.lens.max_coc + 1.0) * reach_scale(s))); }

double smoothstep(double e0, double e1, double x) {
  double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// The mirrors of dof_common.h, in double.


struct Aperture {
  int blades = 0;
  double rotation = 0;
  double sx = 1, sy = 1;  // the stretch (dof.anamorphic)
  V2 stretch(V2 u) const { return {u[0] * sx, u[1] * sy}; }
  double norm(V2 v) const {
    v = {v[0] / sx, v[1] / sy};
    double len = std::hypot(v[0], v[1]);
    if (blades < 3 || len == 0.0) return len;
    double seg = 2.0 * kPi / blades, phi = std::atan2(v[1], v[0]) - rotation;
    double t = phi - seg * std::floor(phi / seg) - 0.5 * seg;
    return len * std::cos(t) / std::cos(kPi / blades);
  }
  double cover(V2 v, double r) const { return std::clamp(r - norm(v) + 0.5, 0.0, 1.0); }
  double area_factor() const { return blades < 3 ? kPi : 0.5 * blades * std::sin(2.0 * kPi / blades); }
};

struct Field {
  const std::vector<float>& src;  // RGBA planes
  const std::vector<float>& coc;
  int w, h;
  size_t n() const { return size_t(w) * h; }
  template <class F>
  void taps(V2 q, F&& f) const {
    double x = q[0] - 0.5, y = q[1] - 0.5, x0 = std::floor(x), y0 = std::floor(y);
    double fx = x - x0, fy = y - y0;
    int xa = std::clamp(int(x0), 0, w - 1), xb = std::clamp(int(x0) + 1, 0, w - 1);
    int ya = std::clamp(int(y0), 0, h - 1), yb = std::clamp(int(y0) + 1, 0, h - 1);
    f(size_t(ya) * w + xa, size_t(ya) * w + xb, size_t(yb) * w + xa, size_t(yb) * w + xb, fx, fy);
  }
  double fetch_coc(V2 q) const {
    double r = 0;
    taps(q, [&](size_t a, size_t b, size_t c, size_t d, double fx, double fy) {
      r = (coc[a] * (1 - fx) + coc[b] * fx) * (1 - fy) + (coc[c] * (1 - fx) + coc[d] * fx) * fy;
    });
    return r;
  }
  V4 fetch_src(V2 q) const {
    V4 r{};
    taps(q, [&](size_t a, size_t b, size_t c, size_t d, double fx, double fy) {
      for (size_t k = 0; k < 4; ++k) {
        const float* s = src.data() + k * n();
        r[k] = (s[a] * (1 - fx) + s[b] * fx) * (1 - fy) + (s[c] * (1 - fx) + s[d] * fx) * fy;
      }
    });
    return r;
  }
  V4 at(size_t i) const { return {src[i], src[n() + i], src[2 * n() + i], src[3 * n() + i]}; }
};

V2 rotate(double a, V2 u) {
  return {std::cos(a) * u[0] - std::sin(a) * u[1], std::sin(a) * u[0] + std::cos(a) * u[1]};
}

V4 mix4(const V4& a, const V4& b, double t) {
  V4 r;
  for (size_t k = 0; k < 4; ++k) r[k] = a[k] * (1 - t) + b[k] * t;
  return r;
}

// The cheap path: an aperture average of radius |c0|, faded to the sharp pixel under 0.5 px.
V4 cheap(const Field& F, const Aperture& ap, int grid, int x, int y, double c0) {
  const V2 p0{x + 0.5, y + 0.5};
  const double a = pixel_angle(uint32_t(x), uint32_t(y)), r = std::abs(c0);
  const V4 c_0 = F.at(size_t(y) * F.w + x);
  V4 s = c_0;
  double ws = 1.0;
  for (int k = 0; k < grid * grid; ++k) {
    V2 u = ap.stretch(rotate(a, concentric(k, grid))), d{r * u[0], r * u[1]};
    double w = ap.cover(d, r);
    V4 v = F.fetch_src({p0[0] + d[0], p0[1] + d[1]});
    for (size_t c = 0; c < 4; ++c) s[c] += w * v[c];
    ws += w;
  }
  for (double& v : s) v /= ws;
  return mix4(c_0, s, smoothstep(0.25, 0.75, r));
}

const float* tile_of(const std::vector<float>& tiles, int w, int x, int y) {
  return tiles.data() + 4 * (size_t(y / DOF_TILE) * dof_tiles_x(uint32_t(w)) + size_t(x / DOF_TILE));
}

void store(std::vector<float>& out, size_t n, size_t i, const V4& v) {
  for (size_t k = 0; k < 4; ++k) out[k * n + i] = float(v[k]);
}

}  // namespace

// ---- references ----

std::vector<float> dof_coc_reference(const std::vector<float>& depth, const float* alpha,
                                     const DofSettings& s) {
  std::vector<float> coc(depth.size());
  for (size_t i = 0; i < depth.size(); ++i) {
    const double v = depth[i];
    double z = v;  // planar depth from the file's form (dof_coc.comp)
    if (s.depth_form == 1) z = v >= 1.0 ? ISG_BACKGROUND_DEPTH : s.depth_near + v * (s.depth_far - s.depth_near);
    if (s.depth_form == 2) z = v > 0.0 ? 1.0 / v : ISG_BACKGROUND_DEPTH;
    const bool bg = z <= 0 || z >= ISG_BACKGROUND_DEPTH || (alpha && alpha[i] == 0.0f);
    double c = bg ? s.lens.c_inf : s.lens.c_inf * (z - s.lens.z_f) / z;  // eq. 15, signed
    if (s.coc_source == 1) c = s.lens.c_inf * v;  // a CoC channel, times its gain
    coc[i] = float(std::clamp(c, -s.lens.max_coc, s.lens.max_coc));
  }
  return coc;
}

std::vector<float> dof_tiles_reference(const std::vector<float>& coc, int w, int h,
                                       const DofSettings& s) {
  const int tx = int(dof_tiles_x(uint32_t(w))), ty = int(dof_tiles_y(uint32_t(h)));
  const int m = int(margin_of(s));
  std::vector<float> tiles(size_t(4) * tx * ty);
  for (int t_y = 0; t_y < ty; ++t_y) {
    for (int t_x = 0; t_x < tx; ++t_x) {
      const int x0 = t_x * DOF_TILE, y0 = t_y * DOF_TILE;
      const int x1 = std::min(x0 + DOF_TILE, w) - 1, y1 = std::min(y0 + DOF_TILE, h) - 1;
      float cmin = 1e30f, cmax = -1e30f, rmax = 0.0f;
      for (int y = std::max(y0 - m, 0); y <= std::min(y1 + m, h - 1); ++y) {
        for (int x = std::max(x0 - m, 0); x <= std::min(x1 + m, w - 1); ++x) {
          const float c = coc[size_t(y) * w + x];
          const int dx = std::max(std::max(x0 - x, x - x1), 0), dy = std::max(std::max(y0 - y, y - y1), 0);
          const float reach = (std::abs(c) + 1.0f) * reach_scale(s);  // float, as on the GPU: the test is discrete
          if (float(dx * dx + dy * dy) > reach * reach) continue;
          cmin = std::min(cmin, c);
          cmax = std::max(cmax, c);
          rmax = std::max(rmax, std::abs(c));
        }
      }
      float* o = tiles.data() + 4 * (size_t(t_y) * tx + t_x);
      o[0] = cmin;
      o[1] = cmax;
      o[2] = rmax;
      o[3] = s.tile_skip && cmax - cmin < float(DOF_CHEAP_RANGE) ? 1.0f : 0.0f;
    }
  }
  return tiles;
}

double dof_cheap_fraction(const std::vector<float>& tiles) {
  if (tiles.empty()) return 0.0;
  size_t cheap = 0;
  for (size_t t = 3; t < tiles.size(); t += 4) cheap += tiles[t] != 0.0f;
  return double(cheap) / (double(tiles.size()) / 4.0);
}

std::vector<float> dof_isg_reference(const std::vector<float>& rgba, const std::vector<float>& coc,
                                     const std::vector<float>& tiles, int w, int h,
                                     const DofSettings& s) {
  const size_t n = size_t(w) * h;
  const Field F{rgba, coc, w, h};
  const Aperture ap{s.blades, s.rotation_deg * kPi / 180.0, stretch_x(s), stretch_y(s)};
  const int N = s.grid * s.grid;
  // dof.search: eq. 16, softened.
  std::vector<double> radius(n);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double c0 = coc[i];
      const float* t = tile_of(tiles, w, x, y);
      if (t[3] != 0.0f) { radius[i] = std::abs(c0); continue; }
      const double R_s = std::max(double(t[2]), 0.5), a = pixel_angle(uint32_t(x), uint32_t(y));
      double sw = 1.0, sv = std::abs(c0);
      for (int k = 0; k < N; ++k) {
        V2 u = ap.stretch(rotate(a, concentric(k, s.grid))), d{R_s * u[0], R_s * u[1]};
        const double ci = F.fetch_coc({x + 0.5 + d[0], y + 0.5 + d[1]});
        const V2 v = ci >= 0 ? V2{-d[0], -d[1]} : d;  // aperture image inverted in front of focus
        const double wgt = ap.cover(d, R_s) * ap.cover(v, std::abs(ci));
        // eq. 16: behind p0 and blurrier -> hidden by p0, counts with p0's own CoC.
        const double hidden = smoothstep(0, 1, ci - c0) * smoothstep(0, 1, std::abs(ci) - std::abs(c0));
        sv += wgt * (std::abs(ci) * (1 - hidden) + std::abs(c0) * hidden);
        sw += wgt;
      }
      radius[i] = float(sv / sw);  // stored as float between the passes, as on the GPU
    }
  }
  // dof.gather: eq. 4 with the range function of eq. 17, softened.
  std::vector<float> out(4 * n);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double c0 = coc[i], a = pixel_angle(uint32_t(x), uint32_t(y));
      const float* t = tile_of(tiles, w, x, y);
      if (t[3] != 0.0f) { store(out, n, i, cheap(F, ap, s.grid, x, y, c0)); continue; }
      const double R_g = radius[i];
      const V4 c_0 = F.at(i);
      V4 acc = c_0;
      double ws = 1.0;
      for (int k = 0; k < N; ++k) {
        V2 u = ap.stretch(rotate(a, concentric(k, s.grid))), d{R_g * u[0], R_g * u[1]};
        const V2 q{x + 0.5 + d[0], y + 0.5 + d[1]};
        const double ci = F.fetch_coc(q);
        const V2 v = ci >= 0 ? V2{-d[0], -d[1]} : d;
        const double own = ap.cover(v, std::abs(ci));
        // eq. 17: in front of p0 and sharper -> counts only inside its own CoC.
        const double front_sharper = smoothstep(0, 1, c0 - ci) * smoothstep(0, 1, std::abs(c0) - std::abs(ci));
        const double wgt = ap.cover(d, R_g) * (1.0 + (own - 1.0) * front_sharper);
        const V4 ci4 = F.fetch_src(q);
        for (size_t c = 0; c < 4; ++c) acc[c] += wgt * ci4[c];
        ws += wgt;
      }
      for (double& v : acc) v /= ws;
      store(out, n, i, mix4(c_0, acc, smoothstep(0.25, 0.75, R_g)));
    }
  }
  return out;
}

std::vector<float> dof_layered_reference(const std::vector<float>& rgba,
                                         const std::vector<float>& coc,
                                         const std::vector<float>& tiles, int w, int h,
                                         const DofSettings& s) {
  const size_t n = size_t(w) * h;
  const Field F{rgba, coc, w, h};
  const Aperture ap{s.blades, s.rotation_deg * kPi / 180.0, stretch_x(s), stretch_y(s)};
  const double K = ap.area_factor();
  // The lattice for a tile of radius R (as the shader's dof_layered_grid; R is the tile's float).
  auto grid_of = [&](double R) {
    return std::clamp(int(std::ceil(float(DOF_LATTICE_DENSITY) * float(R))), std::min(int(DOF_MIN_GRID), s.grid), s.grid);
  };
  // The layered gather at (x, y) with CoC c0 and the tile's radius R.
  auto layered = [&](int x, int y, double c0, double R) {
    const int g = grid_of(R), N = g * g;
    const size_t i = size_t(y) * w + x;
    const double a = pixel_angle(uint32_t(x), uint32_t(y));
    const double a_s = kPi * R * R / N;  // image area one sample stands for
    const double m0 = smoothstep(0.5, 1.5, -c0);  // near-field membership
    const double w0 = 1.0 / std::max(K * c0 * c0, 1.0);
    const V4 c_0 = F.at(i);
    V4 Sn{}, Sf{};
    for (size_t c = 0; c < 4; ++c) { Sn[c] = m0 * w0 * c_0[c]; Sf[c] = (1 - m0) * w0 * c_0[c]; }
    double Wn = m0 * w0, Wf = (1 - m0) * w0;
    for (int k = 0; k < N; ++k) {
      V2 u = ap.stretch(rotate(a, concentric(k, g))), d{R * u[0], R * u[1]};
      const V2 q{x + 0.5 + d[0], y + 0.5 + d[1]};
      const double ci = F.fetch_coc(q);
      const V2 v = ci >= 0 ? V2{-d[0], -d[1]} : d;
      const double mi = smoothstep(0.5, 1.5, -ci);
      // Scatter as gather: the sample's energy spreads over its aperture's area.
      const double dens = a_s / std::max(K * ci * ci, a_s);
      // Far-field occlusion (eq. 17 mirrored): behind p0 it spreads no further than p0's CoC.
      const double behind = smoothstep(0, 1, ci - c0) * (1 - m0);
      double r_far = std::abs(ci) * (1 - behind) + std::min(std::abs(ci), std::max(c0, 0.0)) * behind;
      // Seen from inside a blurred near object's edge, the lens looks past it at the far
      // field within p0's own CoC (partial occlusion): far samples that near reach p0.
      r_far = std::max(r_far, m0 * std::max(-c0, 0.0));
      // In-focus samples (CoC under half a pixel) are the centre pixel's, not the ring's.
      const double wf = (1 - mi) * ap.cover(v, r_far) * dens * smoothstep(0.25, 0.75, r_far);
      const double wn = mi * ap.cover(v, std::abs(ci)) * dens;
      if (wf + wn > 0) {
        const V4 ci4 = F.fetch_src(q);
        for (size_t c = 0; c < 4; ++c) { Sf[c] += wf * ci4[c]; Sn[c] += wn * ci4[c]; }
        Wf += wf;
        Wn += wn;
      }
    }
    double alpha = std::clamp(Wn, 0.0, 1.0);  // the near field's coverage
    alpha += (1 - alpha) * (1 - smoothstep(0, 0.05, Wf / (Wf + Wn)));
    V4 o;
    for (size_t c = 0; c < 4; ++c)
      o[c] = alpha * Sn[c] / std::max(Wn, 1e-20) + (1 - alpha) * Sf[c] / std::max(Wf, 1e-20);
    return o;
  };
  // Wide CoCs at half resolution (issue 18): each 2×2 quad's top-left pixel gathers where
  // |CoC| >= DOF_REUSE_COC, and a pixel with such a CoC takes its result bilinearly from the
  // representatives around it in its DOF_LOCAL² workgroup's quad grid whose CoC has its sign and
  // lies within DOF_REUSE_TOL·|CoC| of its own (else it gathers itself).
  constexpr int kQuads = DOF_LOCAL / 2;
  struct Quad {
    bool done = false;
    double coc = 0.0;  // 0: no gather of its own
    V4 out{};
  };
  std::vector<Quad> quads(size_t((w + 1) / 2) * size_t((h + 1) / 2));
  auto quad = [&](int qx, int qy, double R) -> const Quad& {
    Quad& Q = quads[size_t(qy) * size_t((w + 1) / 2) + size_t(qx)];
    if (Q.done) return Q;
    Q.done = true;
    const double cr = coc[size_t(2 * qy) * w + 2 * qx];
    if (std::abs(cr) >= DOF_REUSE_COC) Q.coc = cr, Q.out = layered(2 * qx, 2 * qy, cr, R);
    return Q;
  };
  auto reuse = [&](int x, int y, double c0, double R, V4& m) {
    const int lx = x % int(DOF_LOCAL), ly = y % int(DOF_LOCAL);
    const QuadBilinear b = quad_bilinear(lx, ly, kQuads);
    V4 sum{};
    double ws = 0.0;
    for (int k = 0; k < 4; ++k) {
      const int qx = (x - lx) / 2 + b.qx + (k & 1), qy = (y - ly) / 2 + b.qy + (k >> 1);
      const double wgt = b.weight(k);
      if (wgt <= 0.0 || 2 * qx >= w || 2 * qy >= h) continue;
      const Quad& Q = quad(qx, qy, R);
      if (Q.coc * c0 <= 0.0 || std::abs(Q.coc - c0) > DOF_REUSE_TOL * std::abs(c0)) continue;
      for (size_t c = 0; c < 4; ++c) sum[c] += wgt * Q.out[c];
      ws += wgt;
    }
    if (ws > 0.0)
      for (size_t c = 0; c < 4; ++c) m[c] = sum[c] / ws;
    return ws >= DOF_REUSE_COVER;
  };
  std::vector<float> out(4 * n);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double c0 = coc[i];
      const float* t = tile_of(tiles, w, x, y);
      const double R = std::max(double(t[2]), 0.5);
      if (t[3] != 0.0f) { store(out, n, i, cheap(F, ap, grid_of(R), x, y, c0)); continue; }
      V4 m{};
      if (std::abs(c0) >= DOF_REUSE_COC && reuse(x, y, c0, R, m)) store(out, n, i, m);
      else store(out, n, i, layered(x, y, c0, R));
    }
  }
  return out;
}

// ---- GPU passes ----

struct DofPass::Kernels {
  std::unique_ptr<gpu::Kernel> coc, tiles, search, gather, layered;
};

DofPass::DofPass(gpu::Context& ctx, const DofSettings& s)
    : ctx_(ctx), s_(s), k_(std::make_unique<Kernels>()) {}
DofPass::~DofPass() = default;

namespace {
shaders::DofPush push_of(const DofSettings& s, uint32_t w, uint32_t h, bool has_alpha) {
  shaders::DofPush pc{};
  pc.width = w;
  pc.height = h;
  pc.tiles_x = dof_tiles_x(w);
  pc.tiles_y = dof_tiles_y(h);
  pc.grid = uint32_t(s.grid);
  pc.has_alpha = has_alpha ? 1u : 0u;
  pc.margin = margin_of(s);
  pc.z_f = float(s.lens.z_f);
  pc.c_inf = float(s.lens.c_inf);
  pc.max_coc = float(s.lens.max_coc);
  pc.rotation = float(s.rotation_deg * kPi / 180.0);
  pc.tile_skip = s.tile_skip ? 1u : 0u;
  pc.origin = s.window.packed_origin();
  pc.coc_source = uint32_t(s.coc_source);
  pc.depth_form = uint32_t(s.depth_form);
  pc.depth_near = float(s.depth_near);
  pc.depth_far = float(s.depth_far);
  pc.stretch_x = stretch_x(s);
  pc.stretch_y = stretch_y(s);
  return pc;
}
// `constants`: the passes that include dof_common.h take the blades (DOF_BLADES) as constant 0.
std::unique_ptr<gpu::Kernel> make_kernel(gpu::Context& ctx, const char* name,
                                         std::span<const uint32_t> spv,
                                         std::vector<gpu::Slot> slots,
                                         const std::vector<uint32_t>& constants = {}) {
  return std::make_unique<gpu::Kernel>(ctx, name, spv, std::move(slots),
                                       uint32_t(sizeof(shaders::DofPush)), DOF_LOCAL, DOF_LOCAL,
                                       constants);
}
constexpr gpu::Slot B = gpu::Slot::buffer, T = gpu::Slot::texels;
using Bind = gpu::Binding;
}  // namespace

void DofPass::record_coc(gpu::Sequence& seq, const gpu::Buffer& composite, bool has_alpha,
                         const gpu::Buffer& depth, const gpu::Buffer& coc,
                         const gpu::Buffer& input, uint32_t w, uint32_t h) {
  if (!k_->coc) k_->coc = make_kernel(ctx_, "dof.coc", isg_spv_dof_coc, {T, T, B, B});
  seq.dispatch(*k_->coc,
               {Bind::floats(composite), Bind::floats(depth), Bind::of(coc), Bind::of(input)},
               push_of(s_, w, h, has_alpha), w, h, "dof.coc");
}

void DofPass::record_tiles(gpu::Sequence& seq, const gpu::Buffer& coc, const gpu::Buffer& tiles,
                           uint32_t w, uint32_t h) {
  if (!k_->tiles) k_->tiles = make_kernel(ctx_, "dof.tiles", isg_spv_dof_tiles, {T, B});
  seq.dispatch(*k_->tiles, {Bind::floats(coc), Bind::of(tiles)},
               push_of(s_, w, h, false), dof_tiles_x(w) * DOF_LOCAL, dof_tiles_y(h) * DOF_LOCAL,
               "dof.tiles");  // one workgroup per tile
}

void DofPass::record_search(gpu::Sequence& seq, const gpu::Buffer& coc, const gpu::Buffer& tiles,
                            const gpu::Buffer& radius, uint32_t w, uint32_t h) {
  if (!k_->search)
    k_->search = make_kernel(ctx_, "dof.search", isg_spv_dof_search, {T, T, B}, blades());
  seq.dispatch(*k_->search,
               {Bind::floats(coc), Bind::floats(tiles), Bind::of(radius)},
               push_of(s_, w, h, false), w, h, "dof.search");
}

void DofPass::record_gather(gpu::Sequence& seq, const gpu::Buffer& input, const gpu::Buffer& coc,
                            const gpu::Buffer& tiles, const gpu::Buffer& radius,
                            const gpu::Buffer& composite, uint32_t w, uint32_t h) {
  if (!k_->gather)
    k_->gather = make_kernel(ctx_, "dof.gather", isg_spv_dof_gather, {T, T, T, T, B}, blades());
  seq.dispatch(*k_->gather,
               {Bind::float4s(input), Bind::floats(coc), Bind::floats(tiles), Bind::floats(radius),
                Bind::of(composite)},
               push_of(s_, w, h, false), w, h, "dof.gather");
}

void DofPass::record_layered(gpu::Sequence& seq, const gpu::Buffer& input, const gpu::Buffer& coc,
                             const gpu::Buffer& tiles, const gpu::Buffer& composite, uint32_t w,
                             uint32_t h) {
  if (!k_->layered)
    k_->layered = make_kernel(ctx_, "dof.layered", isg_spv_dof_layered, {T, T, T, B}, blades());
  seq.dispatch(*k_->layered,
               {Bind::float4s(input), Bind::floats(coc), Bind::floats(tiles), Bind::of(composite)},
               push_of(s_, w, h, false), w, h, "dof.layered");
}

double DofPass::cheap_fraction(const gpu::Buffer& tiles, uint32_t w, uint32_t h) {
  return dof_cheap_fraction(tiles.download_as<float>(size_t(4) * dof_tiles_x(w) * dof_tiles_y(h)));
}

}  // namespace isg::effects
