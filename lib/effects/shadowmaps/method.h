// Inside the shadow-map methods (not a public header): the double mirror of
// shaders/shadowmap_common.h that every reference shares, and the interface each method's GPU
// pass implements behind ShadowmapPass.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "effects/shadowmaps/shadowmap.h"
#include "effects/view.h"
#include "shadowmap_io.h"

namespace isg::effects::detail {
constexpr double kPi = 3.14159265358979323846;
constexpr double kBoxOfDisk = SM_BOX_OF_DISK;  // √π / 2: a square of the disk's area
using V2 = std::array<double, 2>;
using V3 = std::array<double, 3>;
// A receiver plane: d(1/z)/du, d(1/z)/dv, the depth spread (bias), the slope bound (texel
// footprints per texel of lateral offset); sm_receiver_plane in shaders/shadowmap_common.h.
using Plane = std::array<double, 4>;

// The double mirror of shadowmap_common.h.
struct Geom {
  const ShadowmapInputs& in;
  const ShadowmapData& map;
  const ShadowmapSettings& s;
  double tan_x, tan_y;
  size_t n;
  Geom(const ShadowmapInputs& i, const ShadowmapData& m, const ShadowmapSettings& st)
      : in(i), map(m), s(st) {
    // Perspective: tan of the half fields of view; orthographic (a sun): the half extents.
    tan_y = s.ortho ? 0.5 * s.height_m : std::tan(s.yfov_deg * kPi / 360.0);
    tan_x = s.ortho ? 0.5 * s.width_m : tan_y * double(m.width) / double(m.height);
    n = size_t(in.w) * size_t(in.h);
    const io::Mat4 inv = io::inverse(s.world_to_light);
    light_pos = {inv[3], inv[7], inv[11]};
    eps = double(float(depth_eps(m)));  // as the passes read it (ShadowmapParams::depth_eps)
  }
  V3 light_pos{0, 0, 0};
  double eps = 0;
  // shadowmap_common.h's sm_w, sm_w_inv, sm_gap, sm_k, sm_texel_world: w(z) is linear over the
  // map on a plane (1/z; a sun's orthographic map: −z) and the light's cone from depth qz has the
  // radius k·(w(z) − w(qz)) texels at depth z.
  double w(double z) const { return s.ortho ? -z : 1.0 / z; }
  double w_inv(double v) const { return s.ortho ? -v : (v > 0 ? 1.0 / v : 1e30); }
  double gap(double z, double qz) const { return std::max(w(z) - w(qz), 0.0); }
  double k() const { return s.light_radius * map.height / (2.0 * tan_y); }
  double texel_world(double z) const { return 2.0 * (s.ortho ? 1.0 : z) * tan_y / map.height; }
  // The direction toward the light's centre from P (world): a sun's is its axis (sm_to_light).
  V3 to_light(const V3& P) const {
    const auto& m = s.world_to_light;
    if (s.ortho) return {m[8], m[9], m[10]};
    return {light_pos[0] - P[0], light_pos[1] - P[1], light_pos[2] - P[2]};
  }
  // The float32 spacing of pixel i's input (sm_input_step): of P's largest component, else of Z.
  double input_step(size_t i) const {
    const float m = !in.position.empty()
                        ? std::max({std::abs(in.position[i]), std::abs(in.position[n + i]), std::abs(in.position[2 * n + i])})
                        : std::abs(in.depth[i]);
    return float32_step(m);
  }
  V3 position(size_t i) const {
    if (!in.position.empty()) return {in.position[i], in.position[n + i], in.position[2 * n + i]};
    return PinholeView{s.f_px, s.eye, s.rot}.world(i, in.depth[i], in.w, in.h);
  }
  V3 project(const V3& P) const {
    const auto& m = s.world_to_light;
    double x = m[0] * P[0] + m[1] * P[1] + m[2] * P[2] + m[3];
    double y = m[4] * P[0] + m[5] * P[1] + m[6] * P[2] + m[7];
    double z = -(m[8] * P[0] + m[9] * P[1] + m[10] * P[2] + m[11]);
    if (z <= 1e-6) return {-1, -1, -1};
    const double sx = s.ortho ? tan_x : z * tan_x, sy = s.ortho ? tan_y : z * tan_y;
    return {(x / sx * 0.5 + 0.5) * map.width, (0.5 - y / sy * 0.5) * map.height, z};
  }
  bool inside(const V3& q) const {
    return q[2] > 0 && q[2] <= double(float(std::min(s.far_clip, 1e30))) && q[0] >= 0 && q[1] >= 0 && q[0] < map.width && q[1] < map.height;
  }
  // normal: where given, the receiver's normal on the light's side (0 where the neighbours give
  // none; sm_n).
  Plane receiver_plane(int px, int py, const V3& q, const V3& P, bool& back, V3* normal = nullptr) const {
    std::array<V3, 2> d{}, t{}, other{};  // other: the neighbour of each pair left out of the fit
    std::array<bool, 2> has_other{false, false};
    back = false;
    int found = 0;
    double spread = 1e30;
    for (int axis = 0; axis < 2; ++axis) {
      double best = 1e30;
      V3 bd{0, 0, 0}, bt{0, 0, 0};
      for (int sg = -1; sg <= 1; sg += 2) {
        int nx = px + (axis == 0 ? sg : 0), ny = py + (axis == 1 ? sg : 0);
        if (nx < 0 || ny < 0 || nx >= in.w || ny >= in.h) continue;
        size_t j = size_t(ny) * in.w + nx;
        if (in.fg[j] == 0.0f) continue;
        V3 Pn = position(j);
        V3 qn = project(Pn);
        if (qn[2] <= 0) continue;
        double dz = std::abs(qn[2] - q[2]);
        const V3 dn = {qn[0] - q[0], qn[1] - q[1], w(qn[2]) - w(q[2])};
        if (dz < best) {
          if (best < 1e30) other[size_t(axis)] = bd, has_other[size_t(axis)] = true;
          best = dz;
          bd = dn;
          bt = {Pn[0] - P[0], Pn[1] - P[1], Pn[2] - P[2]};
        } else {
          other[size_t(axis)] = dn, has_other[size_t(axis)] = true;
        }
      }
      if (best < 1e30) { t[size_t(found)] = bt; d[size_t(found++)] = bd; }
      spread = std::min(spread, best);
    }
    spread = (spread >= 1e30 ? 0.0 : spread) + eps +
             double(float(s.depth_ulps)) * input_step(size_t(py) * size_t(in.w) + size_t(px));
    if (found < 2) return {0, 0, spread, s.slope_max};
    const V3 nr = {t[0][1] * t[1][2] - t[0][2] * t[1][1], t[0][2] * t[1][0] - t[0][0] * t[1][2],
                   t[0][0] * t[1][1] - t[0][1] * t[1][0]};
    const V3 tl_dir = to_light(P);
    const double tl = nr[0] * tl_dir[0] + nr[1] * tl_dir[1] + nr[2] * tl_dir[2];
    if (normal) {  // unit, on the light's side
      const double ln = std::sqrt(nr[0] * nr[0] + nr[1] * nr[1] + nr[2] * nr[2]);
      if (ln > 0) {
        const double k = (tl < 0 ? -1.0 : 1.0) / ln;
        *normal = {nr[0] * k, nr[1] * k, nr[2] * k};
      }
    }
    if (s.has_camera) {
      auto dot_to = [&](const std::array<double, 3>& X) {
        return nr[0] * (X[0] - P[0]) + nr[1] * (X[1] - P[1]) + nr[2] * (X[2] - P[2]);
      };
      double se = dot_to(s.eye) < 0 ? -1.0 : 1.0;
      back = se * tl < 0;
    }
    double det = d[0][0] * d[1][1] - d[0][1] * d[1][0];
    if (std::abs(det) < 1e-8) return {0, 0, spread, s.slope_max};
    const double gx = (d[0][2] * d[1][1] - d[1][2] * d[0][1]) / det;
    const double gy = (d[0][0] * d[1][2] - d[1][0] * d[0][2]) / det;
    // Planarity: each left-out neighbour's 1/z against the plane's, relative to its step; a
    // planar receiver's plane is trusted to SHADOWMAP_TRUSTED_SLOPE, however grazing the light.
    bool planar = false;
    for (size_t axis = 0; axis < 2; ++axis) {
      if (!has_other[axis]) continue;
      const V3& o = other[axis];
      const double pred = gx * o[0] + gy * o[1];
      planar = std::abs(o[2] - pred) <= SHADOWMAP_PLANE_TOL * std::max(std::abs(o[2]), std::abs(pred));
      if (!planar) break;
    }
    return {gx, gy, spread, planar ? std::max(s.slope_max, SHADOWMAP_TRUSTED_SLOPE) : s.slope_max};
  }
  // A filter tap's share of the receiver's irradiance relative to the light's centre
  // (sm_irradiance): the tap at unit offset (ux, uy) of the filter's disk (texel axes, v down)
  // stands for the light point w = L·(ux, −uy) in the light's frame; at r = w − (P − light) it
  // gives max(n·r, 0)·|n_l·r| / |r|⁴ (n_l: the disk facing the receiver for a sphere light, the
  // map's axis for a disk or rect light). A sun's tap is the direction ω = axis + tan(half
  // angle)·(ux, −uy) in the map's frame: max(n·ω̂, 0) relative to n·axis. 1 where the normal n is
  // unknown.
  double irradiance(const V3& P, const V3& nrm, double ux, double uy) const {
    if (nrm[0] == 0 && nrm[1] == 0 && nrm[2] == 0) return 1.0;
    const auto& m = s.world_to_light;
    if (s.ortho) {
      V3 o;
      for (int k = 0; k < 3; ++k)
        o[size_t(k)] = m[size_t(8 + k)] + s.light_radius * (ux * m[size_t(k)] - uy * m[size_t(4 + k)]);
      const double lo = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
      const double na = nrm[0] * m[8] + nrm[1] * m[9] + nrm[2] * m[10];
      return std::max((nrm[0] * o[0] + nrm[1] * o[1] + nrm[2] * o[2]) / lo, 0.0) / std::max(na, SHADOWMAP_MIN_CN);
    }
    const V3 d = {P[0] - light_pos[0], P[1] - light_pos[1], P[2] - light_pos[2]};
    V3 r, nl;
    for (int k = 0; k < 3; ++k) {
      r[size_t(k)] = s.light_radius * (ux * m[size_t(k)] - uy * m[size_t(4 + k)]) - d[size_t(k)];
      nl[size_t(k)] = s.facing ? d[size_t(k)] : m[size_t(8 + k)];
    }
    auto dot = [](const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    const double D2 = dot(d, d), q = D2 / dot(r, r);
    const V3 c = {-d[0], -d[1], -d[2]};
    return std::max(dot(nrm, r), 0.0) * std::abs(dot(nl, r)) /
           (std::max(dot(nrm, c), SHADOWMAP_MIN_CN * std::sqrt(D2)) * std::max(std::abs(dot(nl, c)), 1e-30)) * q * q;
  }
  double threshold(const V3& q, const Plane& g, double cx, double cy, double texel_world) const {
    double ox = cx - q[0], oy = cy - q[1];
    double zc = w_inv(w(q[2]) + g[0] * ox + g[1] * oy);
    double lim = g[3] * texel_world * std::sqrt(ox * ox + oy * oy);
    zc = std::clamp(zc, q[2] - lim, q[2] + lim);
    return zc - s.bias * texel_world - s.spread_bias * g[2];
  }
  // Whether the light's cone from the receiver reaches texel (cx, cy) at map depth zm: kr is
  // shadows.reach times k(); 0: always (shadowmap_common.h's sm_reaches).
  bool reaches(const V3& q, double cx, double cy, double zm, double kr) const {
    if (kr <= 0.0) return true;
    const double r = kr * gap(zm, q[2]) + SHADOWMAP_REACH_MARGIN;
    const double ox = cx - q[0], oy = cy - q[1];
    return ox * ox + oy * oy <= r * r;
  }
  // The radius of the light's cone from the receiver (depth qz) at map depth z, widened margin
  // times, within max_radius (shadowmap_common.h's sm_cone_radius).
  double cone_radius(double k, double z, double qz, double margin, double max_radius) const {
    return std::min(margin * k * gap(z, qz), max_radius);
  }
  // The narrowed blocker search's box (sm_cone_box): the half-width of the square of the cone's
  // area, at least a texel wide.
  double cone_box(double k, double z, double qz, double margin, double max_radius) const {
    return std::max(kBoxOfDisk * cone_radius(k, z, qz, margin, max_radius), 0.5);
  }
  // Bounds of threshold() over the box [lo, hi): w(z) is linear in (u, v), so the plane's depth
  // is extreme at the corners; its clamp to q.z ± g[3]·tw·|o| is bounded by the farthest corner.
  std::array<double, 2> threshold_range(const V3& q, const Plane& g, V2 lo, V2 hi, double tw) const {
    double zmin = 1e30, zmax = -1e30, far = 0;
    for (int k = 0; k < 4; ++k) {
      const double ox = ((k & 1) ? hi[0] : lo[0]) - q[0], oy = ((k & 2) ? hi[1] : lo[1]) - q[1];
      const double zc = w_inv(w(q[2]) + g[0] * ox + g[1] * oy);
      zmin = std::min(zmin, zc);
      zmax = std::max(zmax, zc);
      far = std::max(far, std::sqrt(ox * ox + oy * oy));
    }
    const double lim = g[3] * tw * far, b = s.bias * tw + s.spread_bias * g[2];
    return {std::max(q[2] - lim, std::min(zmin, q[2])) - b, std::min(q[2] + lim, std::max(q[2], zmax)) - b};
  }
  bool in_map(double cx, double cy) const {
    return cx >= 0 && cy >= 0 && cx < map.width && cy < map.height;
  }
  double fetch(double cx, double cy) const {
    return map.z[size_t(cy) * size_t(map.width) + size_t(cx)];
  }
  // shadows.input_edges (sm_input_edges_at): the input's L.shadow where the penumbra's radius rf
  // is within r0 texels, weighing (r0/rf)² beyond; r0 at least the method's r_min.
  double input_edges(double v, double hard_in, double rf, double r_min = 0.0) const {
    double r0 = double(float(s.input_edges));
    if (r0 <= 0.0) return v;
    r0 = std::max(r0, r_min);
    const double w = rf <= r0 ? 1.0 : (r0 / rf) * (r0 / rf);
    return std::clamp(v + w * (hard_in - v), 0.0, 1.0);
  }
};

// One receiver shaded by a method: its filtered visibility and the filter's radius in texels
// (0 where the map's verdict stood alone: a lit or umbra region, or no blocker found); r_min,
// the narrowest penumbra the method can place (texels, input_edges' floor; cssm's, else 0).
struct Shaded {
  double s;
  double rf;
  double r_min = 0.0;
};

// Every reference's loop over the receivers, as every shadow-map pass does it: background and
// pixels outside the map keep the hard shadow; back-facing receivers too (counted as skipped);
// `shade(px, py, q, g, P, n)` gives the rest (q: the receiver in light space, g: its receiver
// plane, P: its position, n: its normal on the light's side or 0), which input_edges finishes.
template <class Shade>
std::vector<float> shade_receivers(const Geom& G, ShadowmapStats& st, Shade&& shade) {
  const auto& in = G.in;
  std::vector<float> out(G.n);
  for (int py = 0; py < in.h; ++py)
    for (int px = 0; px < in.w; ++px) {
      const size_t i = size_t(py) * size_t(in.w) + size_t(px);
      out[i] = in.hard[i];
      if (in.fg[i] == 0.0f) continue;
      const V3 P = G.position(i), q = G.project(P);
      if (!G.inside(q)) continue;
      ++st.pixels;
      bool back = false;
      V3 nrm{0, 0, 0};
      const Plane g = G.receiver_plane(px, py, q, P, back, &nrm);
      if (back) { ++st.skipped; continue; }
      const Shaded r = shade(px, py, q, g, P, nrm);
      out[i] = float(G.input_edges(r.s, double(in.hard[i]), r.rf, r.r_min));
    }
  return out;
}

// One method's GPU resources and passes (pcss: shadowmap.cpp, vssm: vssm.cpp, cssm: cssm.cpp).
class ShadowmapMethod {
 public:
  virtual ~ShadowmapMethod() = default;
  virtual void record(gpu::Sequence& seq, const gpu::Buffer& geo, const gpu::Buffer& fg,
                      const gpu::Buffer& hard, const gpu::Buffer& map, const gpu::Buffer& soft,
                      const std::string& label) = 0;
  virtual ShadowmapStats stats() const = 0;
  virtual uint64_t gpu_bytes() const = 0;  // the method's own buffers
};

std::unique_ptr<ShadowmapMethod> make_pcss(gpu::Context& ctx, const ShadowmapSettings& s,
                                           const ShadowmapData& map, uint32_t w, uint32_t h,
                                           bool has_position);
std::unique_ptr<ShadowmapMethod> make_vssm(gpu::Context& ctx, const ShadowmapSettings& s,
                                           const ShadowmapData& map, uint32_t w, uint32_t h,
                                           bool has_position);
std::unique_ptr<ShadowmapMethod> make_cssm(gpu::Context& ctx, const ShadowmapSettings& s,
                                           const ShadowmapData& map, uint32_t w, uint32_t h,
                                           bool has_position);

// The counters every method adds to (SHADOWMAP_STAT_*): a zeroed buffer, read back after the
// sequence ran.
gpu::Buffer zeroed_stats(gpu::Context& ctx);
ShadowmapStats read_stats(const gpu::Buffer& stats);

// The own list of a method run as two dispatches of one shader (shadowmap_common.h's
// sm_pixel_of): the pixels the first leaves to the second, and the second's dispatch.
class OwnList {
 public:
  OwnList(gpu::Context& ctx, uint32_t w, uint32_t h);
  // Empties the list (a copy, so that every recorded frame starts from an empty one).
  void reset(gpu::Sequence& seq, const std::string& label) const;
  // The second dispatch, over the listed pixels.
  template <class P>
  void dispatch(gpu::Sequence& seq, const gpu::Kernel& k, const std::vector<gpu::Binding>& b,
                const P& push, const std::string& label) const {
    seq.dispatch_indirect(k, b, push, list_, 4, label);
  }
  const gpu::Buffer& buffer() const { return list_; }

 private:
  gpu::Buffer list_, empty_;
};

}  // namespace isg::effects::detail
