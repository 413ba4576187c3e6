#include "effects/shadowmaps/shadowmap.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "effects/sampling.h"
#include "effects/shadowmaps/method.h"
#include "effects/shadows/settings.h"
#include "effects/view.h"
#include "io/image.h"
#include "isg/shaders/shadowmap_pcss.spv.h"
#include "shadowmap_io.h"

namespace isg::effects {

using detail::Geom;
using detail::kPi;
using detail::V2;
using detail::Plane;
using detail::Shaded;
using detail::V3;

std::vector<float> shadowmap_taps(int n, const std::string& pattern) {
  std::vector<float> t;
  if (pattern == "stratified") {
    const int g = grid_of(n);
    for (int k = 0; k < g * g; ++k) {
      const auto c = concentric(k, g);
      t.push_back(float(c[0]));
      t.push_back(float(c[1]));
    }
    return t;
  }
  // Poisson disk by dart throwing: the distance shrinks until n darts fit.
  std::mt19937 rng(12345u);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double dmin = 1.6 / std::sqrt(double(std::max(n, 1)));
  std::vector<V2> pts;
  int fails = 0;
  while (int(pts.size()) < n) {
    V2 c{u(rng), u(rng)};
    if (c[0] * c[0] + c[1] * c[1] > 1.0) continue;
    bool ok = true;
    for (const auto& q : pts)
      if ((q[0] - c[0]) * (q[0] - c[0]) + (q[1] - c[1]) * (q[1] - c[1]) < dmin * dmin) ok = false;
    if (ok) {
      pts.push_back(c);
      fails = 0;
    } else if (++fails > 1000) {
      dmin *= 0.95;
      fails = 0;
    }
  }
  for (const auto& q : pts) {
    t.push_back(float(q[0]));
    t.push_back(float(q[1]));
  }
  return t;
}

std::vector<float> pcss_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                  const ShadowmapSettings& s, ShadowmapStats* stats) {
  Geom G(in, map, s);
  const auto taps = shadowmap_taps(s.taps, s.pattern);
  const size_t nt = taps.size() / 2;
  ShadowmapStats st;
  const double k = G.k();
  auto out =
      detail::shade_receivers(G, st, [&](int px, int py, const V3& q, const Plane& g, const V3& P, const V3& nrm) -> Shaded {
        double texel_world = G.texel_world(q[2]);
        double a = s.rotate ? pixel_angle(uint32_t(px), uint32_t(py)) : 0.0;
        double ca = std::cos(a), sa = std::sin(a);
        auto unit = [&](size_t t) -> V2 {  // the tap's offset in the filter's unit disk, turned
          const double x = taps[2 * t], y = taps[2 * t + 1];
          return {ca * x - sa * y, sa * x + ca * y};
        };
        auto tap = [&](size_t t, double r) -> V2 {
          const V2 u = unit(t);
          return {std::floor(q[0] + u[0] * r) + 0.5, std::floor(q[1] + u[1] * r) + 0.5};
        };
        // The blocker search over the disk of radius r: whether it finds blockers, their mean
        // depth in db.
        auto search = [&](double r, double& db) {
          double sum = 0;
          size_t cnt = 0;
          for (size_t t = 0; t < nt; ++t) {
            V2 c = tap(t, r);
            if (!G.in_map(c[0], c[1])) continue;
            double zm = G.fetch(c[0], c[1]);
            if (zm < G.threshold(q, g, c[0], c[1], texel_world)) {
              sum += zm;
              ++cnt;
            }
          }
          db = cnt > 0 ? sum / double(cnt) : 0.0;
          return cnt > 0;
        };
        double rs = G.cone_radius(k, map.min_depth, q[2], 1.0, s.max_radius);
        double db = 0;
        bool found = search(rs, db);
        // Narrowed to the blockers' cone, while it shrinks (shadowmap_pcss.comp).
        for (int pass = 0; found && pass < s.pcss_narrow; ++pass) {
          const double rn = G.cone_radius(k, db, q[2], PCSS_NARROW_MARGIN, s.max_radius);
          if (rn >= rs) break;
          found = search(rn, db);
          rs = rn;
        }
        if (!found) {
          ++st.skipped;
          return {1.0, 0.0};
        }
        double rf = k * G.gap(db, q[2]);
        if (rf > s.max_radius) {
          rf = s.max_radius;
          ++st.clamped;
        }
        // The filter's blockers: in front of the receiver plane and within reach; each tap
        // weighed by the irradiance of the light point it stands for.
        double lit = 0, all = 0;
        for (size_t t = 0; t < nt; ++t) {
          const V2 u = unit(t);
          const double wt = G.irradiance(P, nrm, u[0], u[1]);
          all += wt;
          V2 c = tap(t, rf);
          if (!G.in_map(c[0], c[1])) {
            lit += wt;
            continue;
          }
          const double zm = G.fetch(c[0], c[1]);
          if (zm >= G.threshold(q, g, c[0], c[1], texel_world) ||
              !G.reaches(q, c[0], c[1], zm, s.reach * k))
            lit += wt;
        }
        return {all > 0 ? lit / all : 1.0, rf};
      });
  if (stats) *stats = st;
  return out;
}

double depth_eps(const ShadowmapData& map) { return SHADOWMAP_NOISE_EPS * map.noise; }

shaders::ShadowmapParams shadowmap_params(const ShadowmapSettings& s, const ShadowmapData& map,
                                          uint32_t w, uint32_t h, bool has_position,
                                          uint32_t taps) {
  shaders::ShadowmapParams p{};
  p.width = w;
  p.height = h;
  p.map_w = uint32_t(map.width);
  p.map_h = uint32_t(map.height);
  p.has_position = has_position ? 1u : 0u;
  p.taps = taps;
  p.rotate = s.rotate ? 1u : 0u;
  p.facing = s.facing ? 1u : 0u;
  if (s.pcss_narrow < 0 || s.pcss_narrow > 4) throw std::invalid_argument("shadows.pcss_narrow out of range");
  p.pcss_narrow = uint32_t(s.pcss_narrow);
  const auto& m = s.world_to_light;
  float* L[12] = {&p.l00, &p.l01, &p.l02, &p.l03, &p.l10, &p.l11,
                  &p.l12, &p.l13, &p.l20, &p.l21, &p.l22, &p.l23};
  // The shaders project P − light (exact in float near the light, however far from the origin);
  // the light's centre is rounded to float, and the translation column takes up what that moved.
  const io::Mat4 inv = io::inverse(s.world_to_light);
  p.light_x = float(inv[3]);
  p.light_y = float(inv[7]);
  p.light_z = float(inv[11]);
  const double e[3] = {double(p.light_x), double(p.light_y), double(p.light_z)};
  for (int r = 0; r < 3; ++r) {
    const size_t row = 4 * size_t(r);
    for (int k = 0; k < 3; ++k) *L[r * 4 + k] = float(m[row + size_t(k)]);
    *L[r * 4 + 3] = float(m[row] * e[0] + m[row + 1] * e[1] + m[row + 2] * e[2] + m[row + 3]);
  }
  // Perspective: tan of the half fields of view; orthographic (a sun): the half extents.
  const double tan_y = s.ortho ? 0.5 * s.height_m : std::tan(s.yfov_deg * kPi / 360.0);
  p.tan_y = float(tan_y);
  p.tan_x = float(s.ortho ? 0.5 * s.width_m : tan_y * map.width / map.height);
  p.ortho = s.ortho ? 1u : 0u;
  p.light_radius = float(s.light_radius);
  p.min_depth = float(std::min(map.min_depth, 1e30));
  p.far_clip = float(std::min(s.far_clip, 1e30));
  p.max_radius = float(s.max_radius);
  p.bias = float(s.bias);
  p.slope_max = float(s.slope_max);
  p.spread_bias = float(s.spread_bias);
  p.depth_eps = float(depth_eps(map));
  p.input_ulps = float(s.depth_ulps);
  p.reach = float(s.reach);
  p.input_edges = float(s.input_edges);
  p.has_camera = s.has_camera ? 1u : 0u;
  p.f_px = float(s.f_px);
  p.cx = float(s.window.cx(int(w)));
  p.cy = float(s.window.cy(int(h)));
  p.origin = s.window.packed_origin();
  p.eye_rel_x = float(s.eye[0] - e[0]);
  p.eye_rel_y = float(s.eye[1] - e[1]);
  p.eye_rel_z = float(s.eye[2] - e[2]);
  float* R[9] = {&p.r0, &p.r1, &p.r2, &p.r3, &p.r4, &p.r5, &p.r6, &p.r7, &p.r8};
  for (int k = 0; k < 9; ++k) *R[k] = float(s.rot[size_t(k)]);
  return p;
}

namespace detail {
gpu::Buffer zeroed_stats(gpu::Context& ctx) {
  const std::vector<uint32_t> zero(SHADOWMAP_STATS, 0u);
  gpu::Buffer b(ctx, zero.size() * sizeof(uint32_t), "shadowmap.stats");
  b.upload(std::span<const uint32_t>(zero));
  return b;
}

OwnList::OwnList(gpu::Context& ctx, uint32_t w, uint32_t h)
    : list_(ctx, (SHADOWMAP_OWN_HEAD + size_t(w) * h) * sizeof(uint32_t), "shadowmap.own"),
      empty_(ctx, SHADOWMAP_OWN_HEAD * sizeof(uint32_t), "shadowmap.own.empty") {
  const std::vector<uint32_t> e{0u, SHADOWMAP_OWN_ROW, 0u, 1u};
  empty_.upload(std::span<const uint32_t>(e));
}

void OwnList::reset(gpu::Sequence& seq, const std::string& label) const {
  seq.copy(empty_, list_, empty_.size(), label);
}

ShadowmapStats read_stats(const gpu::Buffer& stats) {
  auto v = stats.download_as<uint32_t>(SHADOWMAP_STATS);
  ShadowmapStats s;
  s.pixels = v[SHADOWMAP_STAT_PIXELS];
  s.skipped = v[SHADOWMAP_STAT_SKIPPED];
  s.clamped = v[SHADOWMAP_STAT_CLAMPED];
  s.contact = v[SHADOWMAP_STAT_CONTACT];
  return s;
}

namespace {
// PCSS: one kernel (shaders/shadowmap_pcss.comp); its taps and counters.
class Pcss final : public ShadowmapMethod {
 public:
  Pcss(gpu::Context& ctx, const ShadowmapSettings& s, const ShadowmapData& map, uint32_t w,
       uint32_t h, bool has_position)
      : kernel_(ctx, "shadows.pcss", isg_spv_shadowmap_pcss,
                {gpu::Slot::buffer, gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels,
                 gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::buffer, gpu::Slot::buffer},
                sizeof(shaders::ShadowmapPush), SHADOWMAP_LOCAL, SHADOWMAP_LOCAL),
        w_(w),
        h_(h) {
    const auto taps = shadowmap_taps(s.taps, s.pattern);
    const shaders::ShadowmapParams p =
        shadowmap_params(s, map, w, h, has_position, uint32_t(taps.size() / 2));
    params_ = gpu::Buffer(ctx, sizeof(p), "shadowmap.params");
    params_.upload(&p, sizeof(p));
    taps_ = gpu::Buffer(ctx, taps.size() * sizeof(float), "shadowmap.taps");
    taps_.upload(std::span<const float>(taps));
    stats_ = zeroed_stats(ctx);
  }
  void record(gpu::Sequence& seq, const gpu::Buffer& geo, const gpu::Buffer& fg,
              const gpu::Buffer& hard, const gpu::Buffer& map, const gpu::Buffer& soft,
              const std::string& label) override {
    shaders::ShadowmapPush pc{w_, h_};
    seq.dispatch(kernel_,
                 {gpu::Binding::of(params_), gpu::Binding::floats(geo), gpu::Binding::floats(fg),
                  gpu::Binding::floats(hard), gpu::Binding::floats(map),
                  gpu::Binding::texels(taps_, VK_FORMAT_R32G32_SFLOAT), gpu::Binding::of(soft),
                  gpu::Binding::of(stats_)},
                 pc, w_, h_, label);
  }
  ShadowmapStats stats() const override { return read_stats(stats_); }
  uint64_t gpu_bytes() const override { return params_.size() + taps_.size() + stats_.size(); }

 private:
  gpu::Kernel kernel_;
  gpu::Buffer params_, taps_, stats_;
  uint32_t w_, h_;
};
}  // namespace

std::unique_ptr<ShadowmapMethod> make_pcss(gpu::Context& ctx, const ShadowmapSettings& s,
                                           const ShadowmapData& map, uint32_t w, uint32_t h,
                                           bool has_position) {
  return std::make_unique<Pcss>(ctx, s, map, w, h, has_position);
}
}  // namespace detail

ShadowmapPass::ShadowmapPass(gpu::Context& ctx, const ShadowmapSettings& s,
                             const ShadowmapData& map, uint32_t w, uint32_t h, bool has_position) {
  if (s.method == "pcss")
    method_ = detail::make_pcss(ctx, s, map, w, h, has_position);
  else if (s.method == "vssm")
    method_ = detail::make_vssm(ctx, s, map, w, h, has_position);
  else if (s.method == "cssm")
    method_ = detail::make_cssm(ctx, s, map, w, h, has_position);
  else
    throw std::logic_error("no shadow-map method " + s.method);
}

ShadowmapPass::~ShadowmapPass() = default;

void ShadowmapPass::record(gpu::Sequence& seq, const gpu::Buffer& geo, const gpu::Buffer& fg,
                           const gpu::Buffer& hard, const gpu::Buffer& map, const gpu::Buffer& soft,
                           const std::string& label) {
  method_->record(seq, geo, fg, hard, map, soft, label);
}

ShadowmapStats ShadowmapPass::stats() const { return method_->stats(); }
uint64_t ShadowmapPass::gpu_bytes() const { return method_->gpu_bytes(); }

DerivedShadow shadowmap_derive_reference(const ShadowmapInputs& in, const ShadowmapData& map,
                                         const ShadowmapSettings& s) {
  Geom G(in, map, s);
  DerivedShadow out{std::vector<float>(G.n, 1.0f), std::vector<float>(G.n, 0.0f)};
  for (int py = 0; py < in.h; ++py) {
    for (int px = 0; px < in.w; ++px) {
      const size_t i = size_t(py) * in.w + px;
      if (in.fg[i] == 0.0f) continue;
      const V3 P = G.position(i), q = G.project(P);
      if (!G.inside(q)) continue;
      bool back = false;
      const Plane g = G.receiver_plane(px, py, q, P, back);
      if (back) continue;  // L.shadow 1 where key.direct vanishes (contract)
      const double texel_world = G.texel_world(q[2]);
      const double cx = std::floor(q[0]) + 0.5, cy = std::floor(q[1]) + 0.5;
      out.shadow[i] = G.fetch(cx, cy) >= G.threshold(q, g, cx, cy, texel_world) ? 1.0f : 0.0f;
      double zb = -1.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const double x = cx + dx, y = cy + dy;
          if (!G.in_map(x, y)) continue;
          const double zm = G.fetch(x, y);
          if (zm < G.threshold(q, g, x, y, texel_world)) zb = std::max(zb, zm);
        }
      if (zb > 0.0) {
        // Along the ray to the light's centre (sm_occluder_distance); a sun's is its axis.
        const double d = std::sqrt((P[0] - G.light_pos[0]) * (P[0] - G.light_pos[0]) +
                                   (P[1] - G.light_pos[1]) * (P[1] - G.light_pos[1]) +
                                   (P[2] - G.light_pos[2]) * (P[2] - G.light_pos[2]));
        out.occluder[i] = float(s.ortho ? q[2] - zb : d * (q[2] - zb) / q[2]);
      }
    }
  }
  return out;
}

}  // namespace isg::effects
