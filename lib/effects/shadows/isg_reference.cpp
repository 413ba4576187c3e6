// shadows_isg_reference (isg.h): the double-precision mirror of the shadows.isg passes (§3.1,
// eq. 4-9), which the GPU tests compare them with. The passes themselves are in isg.cpp.
#include "effects/shadows/isg.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>

#include "effects/sampling.h"
#include "effects/view.h"
#include "shadows_isg_io.h"

namespace isg::effects {

namespace {
constexpr int kTile = SHADOWS_ISG_TILE;
using V2 = std::array<double, 2>;
using V3 = std::array<double, 3>;

V3 sub(V3 a, V3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double len3(V3 a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

struct Ctx {
  const ShadowInputs& in;
  const ShadowSettings& s;
  size_t n;
  bool fg(size_t i) const { return in.fg[i] != 0.0f; }
  V3 position(size_t i) const {
    if (!in.position.empty()) return {in.position[i], in.position[n + i], in.position[2 * n + i]};
    return PinholeView{s.f_px, s.eye, s.rot}.world(i, in.depth[i], in.w, in.h);
  }
  double eye_depth(V3 w) const {
    V3 d = sub(w, s.eye);
    const auto& r = s.rot;
    return -(r[6] * d[0] + r[7] * d[1] + r[8] * d[2]);
  }
  // Eq. 8: the penumbra radius R_s for an occluder at d, the light at D.
  double penumbra(double d, double D) const {
    return s.light_size * d / std::max(D - d, SHADOWS_ISG_MIN_GAP * D);
  }
  // Eq. 6-7 without inShadow: a gaussian of the world distance (scene_radius units).
  double range_l(double l) const {
    double u = l / s.scene_radius;
    return std::exp(-u * u / s.sigma);
  }
  // P's screen derivative at (x, y) along (ex, ey), one-sided next to a silhouette.
  V3 axis_diff(int x, int y, V3 P0, int ex, int ey) const {
    const int ax = x - ex, ay = y - ey, bx = x + ex, by = y + ey;
    const bool ha = ax >= 0 && ay >= 0 && fg(size_t(ay) * in.w + ax);
    const bool hb = bx < in.w && by < in.h && fg(size_t(by) * in.w + bx);
    const V3 f = hb ? sub(position(size_t(by) * in.w + bx), P0) : V3{0, 0, 0};
    const V3 g = ha ? sub(P0, position(size_t(ay) * in.w + ax)) : V3{0, 0, 0};
    if (ha && hb) {
      const double lf = len3(f), lg = len3(g);
      if (std::max(lf, lg) < 2.0 * std::min(lf, lg)) return {f[0] + g[0], f[1] + g[1], f[2] + g[2]};
      return lf < lg ? f : g;
    }
    return ha ? g : f;
  }
  // The receiver's incidence at (x, y): c = cos θ_i (at least 1 / SHADOWS_ISG_MAX_STRETCH) and the
  // screen direction of the light's direction projected onto the receiver, along which the
  // penumbra's footprint is stretched by 1 / c (an ellipse).
  struct Incidence {
    double c = 1.0;
    V2 dir = {1.0, 0.0};
    V3 n = {0.0, 0.0, 0.0};  // the receiver's normal on the light's side; 0 where P gives none
  };
  Incidence incidence(int x, int y, V3 P0, V3 wl) const {
    Incidence r;
    const V3 a = axis_diff(x, y, P0, 1, 0), b = axis_diff(x, y, P0, 0, 1);
    V3 nn = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    const double ln = len3(nn);
    if (!(ln > 0.0)) return r;
    nn = {nn[0] / ln, nn[1] / ln, nn[2] / ln};
    const double wn = nn[0] * wl[0] + nn[1] * wl[1] + nn[2] * wl[2];
    r.n = wn < 0.0 ? V3{-nn[0], -nn[1], -nn[2]} : nn;
    r.c = std::max(std::abs(wn), 1.0 / SHADOWS_ISG_MAX_STRETCH);
    // The screen image of t = wl − (wl·n) n at P0: the derivative of the projection.
    const V3 t = {wl[0] - wn * nn[0], wl[1] - wn * nn[1], wl[2] - wn * nn[2]};
    const auto& m = s.rot;
    auto cam = [&](V3 v) {
      return V3{m[0] * v[0] + m[1] * v[1] + m[2] * v[2], m[3] * v[0] + m[4] * v[1] + m[5] * v[2],
                m[6] * v[0] + m[7] * v[1] + m[8] * v[2]};
    };
    const V3 cc = cam(sub(P0, s.eye)), dc = cam(t);
    const V2 d = {dc[2] * cc[0] - cc[2] * dc[0], cc[2] * dc[1] - dc[2] * cc[1]};
    const double dd = d[0] * d[0] + d[1] * d[1];
    if (dd > 1e-20) r.dir = {d[0] / std::sqrt(dd), d[1] / std::sqrt(dd)};
    return r;
  }
  // The distance along wl that across() takes off d, the depth at which the penumbra's
  // cross-section is measured: an occluder at distance t from a point d away from p_0 lies
  // t + along(d, wl) from p_0 (sphere lights: along the ray; disk and rect lights: up to the
  // plane through d parallel to the light's).
  double along(V3 d, V3 wl) const {
    auto dot = [](V3 a, V3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    if (!s.oriented) return dot(d, wl);
    double c = dot(wl, s.light_normal);
    c = c < 0.0 ? std::min(c, -SHADOWS_ISG_MIN_COS) : std::max(c, SHADOWS_ISG_MIN_COS);
    return dot(d, s.light_normal) / c;
  }
  // The distance in the penumbra's cross-section: d projected along the light direction wl onto
  // the plane across the ray (sphere lights) or onto the light's own plane (disk and rect).
  double across(V3 d, V3 wl) const { return len3(cross_section(d, wl)); }
  // d's offset in that cross-section: d − along(d, wl)·wl.
  V3 cross_section(V3 d, V3 wl) const {
    const double t = along(d, wl);
    return {d[0] - t * wl[0], d[1] - t * wl[1], d[2] - t * wl[2]};
  }
  // A tap's share of p_0's irradiance relative to the light's centre (the shader's
  // irradiance()): the tap at cross-section offset cs stands for the light point
  // w = cs · L / R_s; a light point at r = D·wl + w gives max(n·r, 0) · |n_l·r| / |r|⁴.
  double irradiance(V3 nr, V3 wl, double D, V3 cs, double Rs) const {
    auto dot = [](V3 a, V3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    if (nr[0] == 0.0 && nr[1] == 0.0 && nr[2] == 0.0) return 1.0;
    const double k = s.light_size / std::max(Rs, 1e-30);
    const V3 r = {D * wl[0] + k * cs[0], D * wl[1] + k * cs[1], D * wl[2] + k * cs[2]};
    const double q = D * D / dot(r, r);
    const double e = s.oriented ? std::abs(dot(s.light_normal, r)) /
                                      (D * std::max(std::abs(dot(s.light_normal, wl)), SHADOWS_ISG_MIN_COS))
                                : 1.0;
    return std::max(dot(nr, r), 0.0) / (D * std::max(dot(nr, wl), SHADOWS_ISG_MIN_CN)) * e * q * q;
  }
  // Bilinear taps of q (pixel centres at +0.5); taps outside the image get weight 0.
  void taps(V2 q, size_t t[4], double bw[4]) const {
    double x = q[0] - 0.5, y = q[1] - 0.5;
    double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
    const double wx[2] = {1 - fx, fx}, wy[2] = {1 - fy, fy};
    for (int j = 0; j < 4; ++j) {
      long long xx = (long long)x0 + (j & 1), yy = (long long)y0 + (j >> 1);
      bool inside = xx >= 0 && yy >= 0 && xx < in.w && yy < in.h;
      t[j] = inside ? size_t(yy) * size_t(in.w) + size_t(xx) : 0;
      bw[j] = inside ? wx[j & 1] * wy[j >> 1] : 0.0;
    }
  }
};
}  // namespace

std::vector<float> shadows_isg_reference(const ShadowInputs& in, const ShadowSettings& s,
                                         ShadowIsgStats* stats) {
  const size_t n = size_t(in.w) * in.h;
  Ctx c{in, s, n};
  std::vector<float> out(in.shadow.begin(), in.shadow.begin() + n);
  const int tx = (in.w + kTile - 1) / kTile, ty = (in.h + kTile - 1) / kTile;

  // shadows.isg.tiles: flags per tile and d_max.
  std::vector<uint32_t> flags(size_t(tx) * ty, 0);
  std::vector<float> d_tile(size_t(tx) * ty, 0.0f);
  float d_max = 0.0f;
  for (int y = 0; y < in.h; ++y) {
    for (int x = 0; x < in.w; ++x) {
      const size_t i = size_t(y) * in.w + x;
      if (!c.fg(i)) continue;
      const float sh = in.shadow[i];
      flags[size_t(y / kTile) * tx + x / kTile] |=
          (sh > 0.0f ? SHADOWS_ISG_FLAG_LIT : 0u) | (sh < 1.0f ? SHADOWS_ISG_FLAG_SHADOW : 0u);
      if (sh < 1.0f && in.occluder[i] > 0.0f) {
        float& dt = d_tile[size_t(y / kTile) * tx + x / kTile];
        dt = std::max(dt, in.occluder[i]);
        d_max = std::max(d_max, in.occluder[i]);
      }
    }
  }

  ShadowIsgStats st;
  st.d_max = d_max;
  size_t cheap_tiles = 0;
  for (int by = 0; by < ty; ++by) {
    for (int bx = 0; bx < tx; ++bx) {
      const int x0 = bx * kTile, x1 = std::min(in.w, x0 + kTile);
      const int y0 = by * kTile, y1 = std::min(in.h, y0 + kTile);
      // The reach of the widest penumbra in the image bounds the tiles to look at.
      // World size of a pixel at the receiver (Camera::pixel_size_at) shrunk by cos θ_i: the
      // penumbra's stretch along the receiver.
      auto pixel_size = [&](V3 P0, double cos_i) { return std::max(c.eye_depth(P0), 1e-6) / s.f_px * cos_i; };
      auto light_dir = [&](V3 P0) {
        const V3 v = sub(s.light, P0);
        const double D = std::max(len3(v), 1e-20);
        return V3{v[0] / D, v[1] / D, v[2] / D};
      };
      double rp_tile = 0.0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const size_t i = size_t(y) * in.w + x;
          if (!c.fg(i) || !(d_max > 0.0f)) continue;
          const V3 P0 = c.position(i);
          const double rp = c.penumbra(d_max, len3(sub(s.light, P0))) / pixel_size(P0, c.incidence(x, y, P0, light_dir(P0)).c);
          rp_tile = std::max(rp_tile, std::min(rp, s.max_radius));
        }
      // The tiles the search and the gather can reach (radius + 1 for the bilinear taps).
      const int reach = int(std::ceil(rp_tile)) + 1;
      const int lx = std::max((x0 - reach) / kTile, 0), ly = std::max((y0 - reach) / kTile, 0);
      const int hx = std::min((x0 + kTile - 1 + reach) / kTile, tx - 1);
      const int hy = std::min((y0 + kTile - 1 + reach) / kTile, ty - 1);
      uint32_t any = 0;
      float d_loc = 0.0f;
      for (int yy = ly; yy <= hy; ++yy)
        for (int xx = lx; xx <= hx; ++xx) {
          any |= flags[size_t(yy) * tx + xx];
          d_loc = std::max(d_loc, d_tile[size_t(yy) * tx + xx]);
        }
      const bool cheap =
          s.tile_skip && any != (SHADOWS_ISG_FLAG_LIT | SHADOWS_ISG_FLAG_SHADOW);
      if (cheap) {
        ++cheap_tiles;
        continue;  // L.softshadow = L.shadow
      }
      // A foreground receiver at (x, y): P0, the light's distance and direction, the pixel size.
      struct Recv {
        V3 P0, wl;
        double D, pix;
        Ctx::Incidence inc;
      };
      auto receiver = [&](int x, int y) {
        Recv R;
        R.P0 = c.position(size_t(y) * in.w + x);
        R.D = len3(sub(s.light, R.P0));
        R.wl = light_dir(R.P0);
        R.inc = c.incidence(x, y, R.P0, R.wl);
        R.pix = pixel_size(R.P0, R.inc.c);
        return R;
      };
      // The lattice point cs at (x, y) for a footprint of `raw` pixels along R's direction
      // (unclamped): turned by the pixel's hash angle, then stretched to the ellipse of radii
      // min(raw, max_radius) along it and min(raw·c, max_radius) across it.
      auto offset = [&](int x, int y, const Recv& R, double raw, V2 cs) {
        const double ang = s.rotate ? pixel_angle(uint32_t(x), uint32_t(y)) : 0.0;
        const double ca = std::cos(ang), sa = std::sin(ang);
        const V2 u = {ca * cs[0] - sa * cs[1], sa * cs[0] + ca * cs[1]};
        const double a = std::min(raw, s.max_radius), b = std::min(raw * R.inc.c, s.max_radius);
        const V2 d = R.inc.dir;
        const double along = d[0] * u[0] + d[1] * u[1], across = -d[1] * u[0] + d[0] * u[1];
        return V2{x + 0.5 + a * along * d[0] - b * across * d[1], y + 0.5 + a * along * d[1] + b * across * d[0]};
      };
      // Eq. 5: R_p covers the widest penumbra the occluders around can cast (unclamped).
      auto search_radius = [&](const Recv& R) { return d_loc > 0.0f ? c.penumbra(d_loc, R.D) / R.pix : 0.0; };
      // Parameter search (eq. 4, 6, 7), the centre tap included: the mean occluder distance from
      // p_0, or -1 where no occluder is within reach.
      auto search = [&](int x, int y, const Recv& R, double Rp) {
        const size_t i = size_t(y) * in.w + x;
        const double s0 = in.shadow[i], o0 = in.occluder[i];
        double sw = 0.0, swd = 0.0;
        if (s0 < 1.0 && o0 > 0.0) {
          sw = 1.0 - s0;
          swd = sw * o0;
        }
        for (int k = 0; k < s.grid_search * s.grid_search; ++k) {
          const V2 q = offset(x, y, R, Rp, concentric(k, s.grid_search));
          size_t t[4];
          double bw[4];
          c.taps(q, t, bw);
          for (int j = 0; j < 4; ++j) {
            if (bw[j] == 0.0 || !c.fg(t[j])) continue;
            const double sj = in.shadow[t[j]], oj = in.occluder[t[j]];
            if (!(sj < 1.0 && oj > 0.0)) continue;
            const V3 dP = sub(c.position(t[j]), R.P0);
            // The tap's occluder seen from p_0: its distance from p_0, not from the tap.
            const double tj = oj + c.along(dP, R.wl);
            if (!(tj > 0.0)) continue;  // behind p_0
            double r = c.range_l(len3(dP)) * (1.0 - sj) * bw[j];
            const double l = c.across(dP, R.wl);
            if (s.search_reach) {
              // PCSS's blocker test in image space: the occluder lies in p_0's cone to the light.
              const double Rt = c.penumbra(tj, R.D);
              r *= std::clamp((SHADOWS_ISG_REACH * Rt + R.pix - l) / R.pix, 0.0, 1.0);
            }
            sw += r;
            swd += r * tj;
          }
        }
        return sw > 0.0 ? swd / sw : -1.0;
      };
      // Gather (eq. 4): over the points within R_s of p_0 across the light direction (the
      // penumbra's footprint on the receiver), each weighed by its light point's irradiance.
      auto gather = [&](int x, int y, const Recv& R, double Rs) {
        const size_t i = size_t(y) * in.w + x;
        double sum = in.shadow[i], ws = 1.0;
        for (int k = 0; k < s.grid_gather * s.grid_gather; ++k) {
          const V2 q = offset(x, y, R, Rs / R.pix, concentric(k, s.grid_gather));
          size_t t[4];
          double bw[4];
          c.taps(q, t, bw);
          for (int j = 0; j < 4; ++j) {
            if (bw[j] == 0.0 || !c.fg(t[j])) continue;
            const V3 dP = sub(c.position(t[j]), R.P0);
            const V3 cs = c.cross_section(dP, R.wl);
            const double l = len3(cs);
            const double r = c.range_l(len3(dP)) * std::clamp((Rs + 0.5 * R.pix - l) / R.pix, 0.0, 1.0) * bw[j] *
                             c.irradiance(R.inc.n, R.wl, R.D, cs, Rs);
            sum += r * in.shadow[t[j]];
            ws += r;
          }
        }
        return sum / ws;
      };
      // The search and the wide gathers at half resolution (issue 18): per 2×2 quad of the tile,
      // its first foreground pixel (the representative) searches, and gathers where its R_g is at
      // least SHADOWS_ISG_REUSE_RADIUS.
      constexpr int kQuads = kTile / 2;
      struct Quad {
        size_t rep = size_t(-1);
        double d = -1.0, g = 0.0, Rg = -1.0;
      };
      std::array<Quad, kQuads * kQuads> quads{};
      for (int qy = 0; qy < kQuads; ++qy)
        for (int qx = 0; qx < kQuads; ++qx) {
          Quad& Q = quads[size_t(qy) * kQuads + qx];
          int rx = 0, ry = 0;
          for (int k = 0; k < 4 && Q.rep == size_t(-1); ++k) {
            const int px = x0 + 2 * qx + (k & 1), py = y0 + 2 * qy + (k >> 1);
            if (px < in.w && py < in.h && c.fg(size_t(py) * in.w + px)) Q.rep = size_t(py) * in.w + px, rx = px, ry = py;
          }
          if (Q.rep == size_t(-1)) continue;
          const Recv R = receiver(rx, ry);
          Q.d = search(rx, ry, R, search_radius(R));
          ++st.searches;
          if (Q.d < 0.0) continue;
          const double Rs = c.penumbra(Q.d, R.D), Rg = std::min(Rs / R.pix, s.max_radius);
          if (Rg >= SHADOWS_ISG_REUSE_RADIUS) Q.Rg = Rg, Q.g = gather(rx, ry, R, Rs), ++st.gathers;
        }
      auto same_surface = [&](size_t r, V3 P0) {
        return c.range_l(len3(sub(c.position(r), P0))) >= SHADOWS_ISG_QUAD_SAME;
      };
      // A wide penumbra's gather, bilinear from the representatives' around the pixel in the
      // tile's quad grid (on its surface, R_g within SHADOWS_ISG_REUSE_RATIO of its own); false
      // where they hold under SHADOWS_ISG_REUSE_COVER of the bilinear weight.
      auto reuse = [&](int x, int y, V3 P0, double Rg, double& m) {
        const QuadBilinear b = quad_bilinear(x - x0, y - y0, kQuads);
        double sum = 0.0, ws = 0.0;
        for (int k = 0; k < 4; ++k) {
          const Quad& Q = quads[size_t(b.qy + (k >> 1)) * kQuads + size_t(b.qx + (k & 1))];
          const double w = b.weight(k);
          if (w <= 0.0 || Q.Rg < 0.0 || Q.Rg * SHADOWS_ISG_REUSE_RATIO < Rg || Rg * SHADOWS_ISG_REUSE_RATIO < Q.Rg) continue;
          if (!same_surface(Q.rep, P0)) continue;
          sum += w * Q.g;
          ws += w;
        }
        m = ws > 0.0 ? sum / ws : 0.0;
        return ws >= SHADOWS_ISG_REUSE_COVER;
      };
      // A quad whose search found no occluder takes the mean occluder distance of the quads
      // around it (the 3x3 in the tile) whose search found one, on the pixel's surface, where
      // at least SHADOWS_ISG_BORROW_MIN did (the shader's borrowed_d); -1 else.
      auto borrowed = [&](int x, int y, V3 P0) {
        const int qx = (x - x0) / 2, qy = (y - y0) / 2;
        double sd = 0.0;
        int found = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = qx + dx, ny = qy + dy;
            if (nx < 0 || ny < 0 || nx >= kQuads || ny >= kQuads) continue;
            const Quad& N = quads[size_t(ny) * kQuads + size_t(nx)];
            if (!(N.d >= 0.0) || !same_surface(N.rep, P0)) continue;
            sd += N.d;
            ++found;
          }
        return found >= SHADOWS_ISG_BORROW_MIN ? sd / found : -1.0;
      };
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          const size_t i = size_t(y) * in.w + x;
          if (!c.fg(i)) continue;  // background is left untouched
          ++st.full_pixels;
          const Recv R = receiver(x, y);
          const double Rp_raw = search_radius(R);
          bool clamped = Rp_raw > s.max_radius;
          // The search: the quad representative's, unless the pixel lies on another surface.
          const Quad& Q = quads[size_t((y - y0) / 2) * kQuads + size_t((x - x0) / 2)];
          double d = Q.d;
          if (Q.rep != i && !same_surface(Q.rep, R.P0)) {
            d = search(x, y, R, Rp_raw), ++st.searches;
          } else if (d < 0.0) {
            d = borrowed(x, y, R.P0);
            if (d >= 0.0) ++st.borrowed;
          }
          if (d >= 0.0) {
            // Eq. 8-9.
            const double Rs = c.penumbra(d, R.D);
            const double Rg_raw = Rs / R.pix;
            clamped = clamped || Rg_raw > s.max_radius;
            const double Rg = std::min(Rg_raw, s.max_radius);
            double m = 0.0;
            if (Rg >= SHADOWS_ISG_REUSE_RADIUS && reuse(x, y, R.P0, Rg, m)) {
              out[i] = float(m);
            } else {
              out[i] = float(gather(x, y, R, Rs));
              ++st.gathers;
            }
          }
          if (clamped) ++st.clamped_pixels;
        }
      }
    }
  }
  st.skipped_fraction = tx * ty > 0 ? double(cheap_tiles) / (double(tx) * ty) : 0.0;
  if (stats) *stats = st;
  return out;
}

}  // namespace isg::effects
