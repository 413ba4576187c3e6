// reflections_reference and ggx_cone_tan (reflections.h): the double-precision mirror of the
// reflections passes (§3.2), which the GPU tests compare them with. The passes are in
// reflections.cpp.
#include "effects/reflections/reflections.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "effects/sampling.h"
#include "effects/view.h"
#include "reflections_isg_io.h"

namespace isg::effects {

namespace {
using V2 = std::array<double, 2>;
using V3 = std::array<double, 3>;

V3 sub(V3 a, V3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot3(V3 a, V3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double len3(V3 a) { return std::sqrt(dot3(a, a)); }
double len2(V2 a) { return std::hypot(a[0], a[1]); }
double smoothstep(double e0, double e1, double x) {
  double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

struct Ctx {
  const ReflInputs& in;
  const ReflSettings& s;
  size_t n;
  uint64_t* searches;  // statistics: searches and gathers run (as the GPU's ReflTileStats)
  uint64_t* gathers;
  V3 rgb(const std::vector<float>& v, size_t i) const { return {v[i], v[n + i], v[2 * n + i]}; }
  double rough(size_t i) const {
    return in.roughness.empty() || s.roughness_override ? s.roughness : double(in.roughness[i]);
  }
  bool has_refl(size_t i) const {
    V3 w = rgb(in.weight, i);
    return in.fg[i] != 0.0f && std::max({w[0], w[1], w[2]}) > 0.0;
  }
  bool glossy(size_t i) const { return has_refl(i) && rough(i) > REFL_MIN_ROUGHNESS; }
  V3 cam(V3 w) const {  // world -> camera rotation applied to w − eye
    V3 d = sub(w, s.eye);
    const auto& r = s.rot;
    return {r[0] * d[0] + r[1] * d[1] + r[2] * d[2], r[3] * d[0] + r[4] * d[1] + r[5] * d[2],
            r[6] * d[0] + r[7] * d[1] + r[8] * d[2]};
  }
  V3 position(size_t i) const {
    if (!in.position.empty()) return rgb(in.position, i);
    return PinholeView{s.f_px, s.eye, s.rot}.world(i, in.depth[i], in.w, in.h);
  }
  V3 normal(size_t i) const {
    V3 v = rgb(in.normal, i);
    double l = len3(v);
    return l > 0 ? V3{v[0] / l, v[1] / l, v[2] / l} : V3{0, 0, 1};
  }
  V2 project(V3 w) const {
    V3 c = cam(w);
    double z = std::max(-c[2], 1e-6);
    return {0.5 * in.w + s.f_px * c[0] / z, 0.5 * in.h - s.f_px * c[1] / z};
  }
  // Point taps (issue 18): the pixel holding q, clamped to the image. With the lattice rotated
  // per pixel, bilinear taps bought no error against Cycles and cost four texels a sample.
  size_t tap(V2 q) const {
    const int x = std::clamp(int(std::floor(q[0])), 0, in.w - 1);
    const int y = std::clamp(int(std::floor(q[1])), 0, in.h - 1);
    return size_t(y) * in.w + x;
  }
  // The pixel a coarse tap reads (shaders/reflections_isg_io.h, REFL_COARSE): the one its cell
  // keeps, whose geometry and distance it takes; a gather tap takes the cell's colour (cell_refl).
  size_t tap_coarse(V2 q) const {
    const size_t t = tap(q);
    const auto pick = [](int v, int size) {
      return std::min(v / int(REFL_COARSE) * int(REFL_COARSE) + int(REFL_COARSE_PICK), size - 1);
    };
    return size_t(pick(int(t / in.w), in.h)) * in.w + pick(int(t % in.w), in.w);
  }
  // Eq. 10-12.
  double range(size_t j, V3 P0, V3 N0) const {
    double l = len3(sub(position(j), P0)) / s.scene_radius;
    double nn = 1.0 - dot3(normal(j), N0);
    return std::exp(-(s.a * l * l + s.b * nn * nn) / s.sigma);
  }
  // The coarse cells' colours (reflections.pack.cells), cell-major: refl averaged over the
  // cell's pixels that hold reflection data, each weighed by its range weight to the pixel the
  // cell keeps (tap_coarse's); that pixel's own refl where it holds none.
  std::vector<V3> cells;
  int cells_x() const { return (in.w + int(REFL_COARSE) - 1) / int(REFL_COARSE); }
  void make_cells() {
    const int C = int(REFL_COARSE), cy_n = (in.h + C - 1) / C;
    cells.assign(size_t(cells_x()) * cy_n, V3{});
    for (int cy = 0; cy < cy_n; ++cy)
      for (int cx = 0; cx < cells_x(); ++cx) {
        const size_t k = tap_coarse({cx * C + 0.5, cy * C + 0.5});
        V3& m = cells[size_t(cy) * cells_x() + cx];
        m = rgb(in.refl, k);
        if (!has_refl(k)) continue;
        const V3 P0 = position(k), N0 = normal(k);
        V3 sum{};
        double ws = 0;
        for (int y = cy * C; y < std::min(in.h, (cy + 1) * C); ++y)
          for (int x = cx * C; x < std::min(in.w, (cx + 1) * C); ++x) {
            const size_t j = size_t(y) * in.w + x;
            if (!has_refl(j)) continue;
            const double w = range(j, P0, N0);
            const V3 r = rgb(in.refl, j);
            for (int c3 = 0; c3 < 3; ++c3) sum[c3] += w * r[c3];
            ws += w;
          }
        m = {sum[0] / ws, sum[1] / ws, sum[2] / ws};
      }
  }
  // refl as a coarse tap reads it: the colour of the cell of pixel t (a tap_coarse pixel).
  V3 cell_refl(size_t t) const {
    return cells[(t / in.w) / REFL_COARSE * cells_x() + (t % in.w) / REFL_COARSE];
  }
  double angle(int x, int y) const {
    return pixel_angle(uint32_t(x) / REFL_ROTATION_BLOCK, uint32_t(y) / REFL_ROTATION_BLOCK);
  }

  V3 blur(int x, int y, size_t i) const {
    V2 p0 = {x + 0.5, y + 0.5};
    double ang = angle(x, y), ca = std::cos(ang), sa = std::sin(ang);
    V3 sum = rgb(in.refl, i);
    double ws = 1.0;
    for (int k = 0; k < s.grid_gather * s.grid_gather; ++k) {
      V2 c = concentric(k, s.grid_gather);
      V2 q = {p0[0] + s.blur_radius * (ca * c[0] - sa * c[1]),
              p0[1] + s.blur_radius * (sa * c[0] + ca * c[1])};
      const size_t t = tap(q);
      double w = has_refl(t) ? 1.0 : 0.0;
      V3 r = rgb(in.refl, t);
      for (int c3 = 0; c3 < 3; ++c3) sum[c3] += w * r[c3];
      ws += w;
    }
    return {sum[0] / ws, sum[1] / ws, sum[2] / ws};
  }

  // The pixel's lobe: the cone of eq. 13 and the screen footprint of eq. 14.
  struct Lobe {
    V2 p0;
    V3 P0, N0;
    double e, cos_i, alpha, theta_max, R_full, R_p, maj, minor, ca, sa;
    V2 d_maj, d_min;
    // Lattice point u (unit disk) scaled by R, rotated per REFL_ROTATION_BLOCK² block, on the
    // footprint's axes.
    V2 at(V2 c, double R, V2* u = nullptr) const {
      V2 r = {ca * c[0] - sa * c[1], sa * c[0] + ca * c[1]};
      if (u) *u = r;
      return {p0[0] + R * (r[0] * maj * d_maj[0] + r[1] * minor * d_min[0]),
              p0[1] + R * (r[0] * maj * d_maj[1] + r[1] * minor * d_min[1])};
    }
  };
  Lobe lobe(int x, int y, size_t i) const {
    Lobe L;
    L.p0 = {x + 0.5, y + 0.5};
    L.P0 = position(i), L.N0 = normal(i);
    V3 V = sub(s.eye, L.P0);
    L.e = std::max(len3(V), 1e-6);
    L.cos_i = std::clamp(dot3(L.N0, V) / L.e, REFL_MIN_COS, 1.0);
    L.alpha = rough(i) * rough(i);
    L.theta_max = std::min(2.0 * std::atan(ggx_cone_tan(L.alpha, s.energy)), REFL_MAX_THETA);
    // The shader keeps tan θ_max instead, from tan θ_h algebraically (the same quantity).
    L.R_full = s.f_px * std::tan(L.theta_max);  // eq. 13 as E → ∞
    L.R_p = std::min(L.R_full, s.max_radius);
    L.d_maj = {1, 0};
    if (s.anisotropic) {
      const V3 P0 = L.P0, N0 = L.N0;
      const double e = L.e;
      V2 a = project(P0), b = project({P0[0] + N0[0] * 0.01 * e, P0[1] + N0[1] * 0.01 * e,
                                       P0[2] + N0[2] * 0.01 * e});
      V2 d = {b[0] - a[0], b[1] - a[1]};
      double l = len2(d);
      if (l > 1e-6) L.d_maj = {d[0] / l, d[1] / l};
    }
    L.d_min = {-L.d_maj[1], L.d_maj[0]};
    L.maj = s.anisotropic ? 1.0 : L.cos_i, L.minor = L.cos_i;
    const double ang = angle(x, y);
    L.ca = std::cos(ang), L.sa = std::sin(ang);
    return L;
  }

  // Parameter search (eq. 4, 10-12) over t = E / (e + E); misses are t = 1 (eq. 13's limit).
  double search(const Lobe& L, size_t i) const {
    double d0 = in.dist[i];
    double st = d0 > 0 ? d0 / (L.e + d0) : 1.0, sw = 1.0;
    if (d0 <= 0 && !s.search_misses) st = sw = 0.0;
    const bool coarse = L.R_p >= REFL_COARSE_RADIUS;  // wide: the coarse cells' taps
    for (int k = 0; k < s.grid_search * s.grid_search; ++k) {
      V2 u;
      V2 q = L.at(concentric(k, s.grid_search), L.R_p, &u);
      const size_t t = coarse ? tap_coarse(q) : tap(q);
      if (!has_refl(t)) continue;
      double dj = in.dist[t];
      if (dj <= 0 && !s.search_misses) continue;
      double tj = dj > 0 ? dj / (L.e + dj) : 1.0;
      double w = range(t, L.P0, L.N0);
      if (s.search_reach) w *= std::clamp(tj * L.R_full - len2(u) * L.R_p + 0.5, 0.0, 1.0);
      st += w * tj;
      sw += w;
    }
    return sw > 1e-6 ? st / sw : 1.0;
  }

  // The gather's footprint (eq. 13 per reflected direction: a deviation θ lands k·tan θ pixels
  // away): k = t̄·f, the cone's half-angle and its radius R_s.
  struct Foot {
    double k_px, th_max, R_s;
  };
  Foot footprint(const Lobe& L, double t_bar) const {
    Foot F;
    F.k_px = t_bar * s.f_px;
    F.th_max = 0.5 * std::min(L.theta_max, std::atan(s.max_radius / std::max(F.k_px, 1e-6)));
    F.R_s = F.k_px * std::tan(2.0 * F.th_max);
    return F;
  }
  // Masking-shadowing loss: albedo 1 / (1 + 2·Λ(θ_i)) = 1 / sqrt(1 + α² tan²θ_i).
  double albedo(const Lobe& L) const {
    const double tan2 = (1.0 - L.cos_i * L.cos_i) / (L.cos_i * L.cos_i);
    return s.masking ? 1.0 / std::sqrt(1.0 + L.alpha * L.alpha * tan2) : 1.0;
  }
  // Eq. 4: the weighted mean of refl over the lobe, the centre included. Samples are reflected
  // directions placed by the lobe (NDF CDF in θ_h); weight 1/cos θ_h.
  V3 gather_mean(const Lobe& L, size_t i, const Foot& F) const {
    const double alpha = L.alpha;
    const double tm2 = std::tan(F.th_max) * std::tan(F.th_max);
    const double xi_max = tm2 / (alpha * alpha + tm2);
    V3 sum = rgb(in.refl, i);
    double ws = 1.0;
    for (int k = 0; k < s.grid_gather * s.grid_gather; ++k) {
      V2 c = concentric(k, s.grid_gather);
      const double rho_u = len2(c), xi = xi_max * rho_u * rho_u;
      const double th = std::atan(alpha * std::sqrt(xi / (1.0 - xi)));
      const double f = rho_u > 0 ? F.k_px * std::tan(2.0 * th) / rho_u : 0.0;
      const V2 q = L.at(c, f);
      const double wd = 1.0 / std::cos(th);
      const bool far = f * rho_u >= REFL_COARSE_GATHER;
      const size_t t = far ? tap_coarse(q) : tap(q);
      if (!has_refl(t)) continue;
      double w = wd * range(t, L.P0, L.N0);
      V3 r = far ? cell_refl(t) : rgb(in.refl, t);
      for (int c3 = 0; c3 < 3; ++c3) sum[c3] += w * r[c3];
      ws += w;
    }
    return {sum[0] / ws, sum[1] / ws, sum[2] / ws};
  }
  V3 gather(const Lobe& L, size_t i, const Foot& F) const {
    const double al = albedo(L);
    V3 c0 = rgb(in.refl, i);
    if (F.R_s < 0.25) return {al * c0[0], al * c0[1], al * c0[2]};
    const V3 mean = gather_mean(L, i, F);
    double m = smoothstep(0.25, 0.75, F.R_s);
    V3 out;
    for (int c3 = 0; c3 < 3; ++c3) out[c3] = al * (c0[c3] + (mean[c3] - c0[c3]) * m);
    return out;
  }

  // The search at half resolution and the wide gathers at quarter resolution (issue 18): one
  // search per 2×2 quad, from its first glossy pixel (the representative), and one gather per
  // 4×4 block, its top-left quad's representative's, where that footprint is at least
  // REFL_REUSE_RADIUS; a pixel on another surface than its representative (range weight below
  // REFL_QUAD_SAME) searches for itself. Quads are aligned to even pixels, blocks to multiples
  // of 4 (the tile's).
  struct Quad {
    bool done = false;
    size_t rep = size_t(-1);  // none: no glossy pixel in the quad
    double t = 1.0, R_s = -1.0;  // R_s < 0: no wide gather
    V3 mean{};
  };
  size_t quad_rep(int x, int y) const {
    const int qx = x & ~1, qy = y & ~1;
    for (int k = 0; k < 4; ++k) {
      const int px = qx + (k & 1), py = qy + (k >> 1);
      if (px < in.w && py < in.h && glossy(size_t(py) * in.w + px)) return size_t(py) * in.w + px;
    }
    return size_t(-1);
  }
  const Quad& quad(int qx, int qy, std::vector<Quad>& quads) const {
    Quad& Q = quads[size_t(qy) * ((in.w + 1) / 2) + qx];
    if (Q.done) return Q;
    Q.done = true;
    Q.rep = quad_rep(2 * qx, 2 * qy);
    if (Q.rep == size_t(-1)) return Q;
    const Lobe L = lobe(int(Q.rep % in.w), int(Q.rep / in.w), Q.rep);
    Q.t = search(L, Q.rep);
    ++*searches;
    const Foot F = footprint(L, Q.t);
    if (qx % 2 == 0 && qy % 2 == 0 && F.R_s >= REFL_REUSE_RADIUS) {
      Q.R_s = F.R_s, Q.mean = gather_mean(L, Q.rep, F);
      ++*gathers;
    }
    return Q;
  }
  // A wide lobe's mean, bilinear from the blocks' gathers around the pixel in the image's block
  // grid, across tile borders (those on its surface whose footprint is within REFL_REUSE_RATIO
  // of its own); false where they hold under REFL_REUSE_COVER of the bilinear weight.
  bool reuse(int x, int y, const Lobe& L, double R_s, std::vector<Quad>& quads, V3& m) const {
    const QuadBilinear b = cell_bilinear(x, y, (in.w + 3) / 4, (in.h + 3) / 4, 4);
    V3 sum{};
    double ws = 0.0;
    for (int k = 0; k < 4; ++k) {
      const int qx = 2 * (b.qx + (k & 1)), qy = 2 * (b.qy + (k >> 1));
      const double w = b.weight(k);
      if (w <= 0.0 || 2 * qx >= in.w || 2 * qy >= in.h) continue;
      const Quad& Q = quad(qx, qy, quads);
      if (Q.R_s < 0.0 || Q.R_s * REFL_REUSE_RATIO < R_s || R_s * REFL_REUSE_RATIO < Q.R_s) continue;
      if (range(Q.rep, L.P0, L.N0) < REFL_QUAD_SAME) continue;
      for (int c3 = 0; c3 < 3; ++c3) sum[c3] += w * Q.mean[c3];
      ws += w;
    }
    if (ws > 0.0) m = {sum[0] / ws, sum[1] / ws, sum[2] / ws};
    return ws >= REFL_REUSE_COVER;
  }
  V3 isg(int x, int y, size_t i, std::vector<Quad>& quads) const {
    const Lobe L = lobe(x, y, i);
    const Quad& Q = quad(x / 2, y / 2, quads);
    const bool same = Q.rep == i || range(Q.rep, L.P0, L.N0) >= REFL_QUAD_SAME;
    *searches += same ? 0 : 1;
    const Foot F = footprint(L, same ? Q.t : search(L, i));
    V3 m{};
    if (F.R_s >= REFL_REUSE_RADIUS && reuse(x, y, L, F.R_s, quads, m)) {
      const double al = albedo(L);
      return {al * m[0], al * m[1], al * m[2]};
    }
    *gathers += F.R_s >= 0.25 ? 1 : 0;
    return gather(L, i, F);
  }
};
}  // namespace

double ggx_cone_tan(double alpha, double energy) {
  return alpha * std::sqrt(energy / (1.0 - energy));
}

std::vector<float> reflections_reference(const ReflInputs& in, const ReflSettings& s,
                                         std::vector<float>* tiles, ReflTileStats* stats) {
  const size_t n = size_t(in.w) * in.h;
  ReflTileStats st;
  Ctx c{in, s, n, &st.searches, &st.gathers};
  if (s.method == "isg") c.make_cells();
  std::vector<float> out(in.refl.begin(), in.refl.begin() + 3 * n);
  const int tx = (in.w + REFL_TILE - 1) / REFL_TILE, ty = (in.h + REFL_TILE - 1) / REFL_TILE;
  if (tiles) tiles->assign(size_t(tx) * ty, 0.0f);
  std::vector<Ctx::Quad> quads(size_t((in.w + 1) / 2) * ((in.h + 1) / 2));
  for (int by = 0; by < ty; ++by) {
    for (int bx = 0; bx < tx; ++bx) {
      bool any = false;
      for (int y = by * REFL_TILE; y < std::min(in.h, (by + 1) * REFL_TILE); ++y)
        for (int x = bx * REFL_TILE; x < std::min(in.w, (bx + 1) * REFL_TILE); ++x)
          any = any || c.glossy(size_t(y) * in.w + x);
      if (tiles) (*tiles)[size_t(by) * tx + bx] = any ? 0.0f : 1.0f;
      st.skipped_fraction += any ? 0.0 : 1.0 / (double(tx) * ty);
      if (!any) continue;  // the cheap path: refl.glossy = refl
      for (int y = by * REFL_TILE; y < std::min(in.h, (by + 1) * REFL_TILE); ++y) {
        for (int x = bx * REFL_TILE; x < std::min(in.w, (bx + 1) * REFL_TILE); ++x) {
          const size_t i = size_t(y) * in.w + x;
          if (!c.glossy(i)) continue;
          ++st.glossy_pixels;
          V3 v = s.method == "blur" ? c.blur(x, y, i) : c.isg(x, y, i, quads);
          for (int k = 0; k < 3; ++k) out[k * n + i] = float(v[k]);
        }
      }
    }
  }
  if (stats) *stats = st;
  return out;
}

}  // namespace isg::effects
