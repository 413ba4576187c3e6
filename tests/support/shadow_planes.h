// The shadow-map methods' test scene: the light at the origin looking down -Z, an occluder
// half-plane over a receiver plane (parallel: the closed-form penumbra), and the GPU run of one
// method on it.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "effects/shadowmaps/derive.h"
#include "effects/shadowmaps/shadowmap.h"
#include "gpu/gpu.h"
#include "synth.h"

namespace isg::test {
namespace gpu = isg::gpu;
namespace fx = isg::effects;

inline constexpr double kPi = 3.14159265358979323846;

// The light at the origin looking down -Z (world_to_light = identity), 90° map. An occluder
// half-plane x < edge·d_o at depth d_o (none where d_o <= 0); the receiver z = -(z_r + slope·x)
// (slope 0: parallel planes).
//
// ortho: a sun overhead instead (contract input 3): the map orthographic, `extent` across, the
// occluder's edge at x = edge (world), R the tan of the sun's half angle; every ray to it is
// parallel to the axis. Parallel planes only (slope 0).
struct Planes {
  double d_o = 2.0, z_r = 4.0, slope = 0.0, R = 0.2;
  double edge = 0.0;  // the occluder's edge, x/z (tan) from the light (ortho: x, world)
  double far = 1e3;  // the receiver plane ends at this depth (a sloped one; background beyond)
  int map = 256, w = 96, h = 96;
  bool ortho = false;
  double extent = 2.0;  // ortho: the map's width and height, world units
  fx::ShadowmapData shadowmap() const {
    std::vector<float> z(size_t(map) * map);
    for (int j = 0; j < map; ++j)
      for (int i = 0; i < map; ++i) {
        if (ortho) {  // the texel centre's x, world
          const double x = ((i + 0.5) / map - 0.5) * extent;
          z[size_t(j) * map + i] = float(x < edge && d_o > 0.0 ? d_o : z_r);
          continue;
        }
        double a = 2.0 * (i + 0.5) / map - 1.0;  // x/z at the texel centre (tan 45° = 1)
        // The receiver's depth along that ray: z = z_r + slope·a·z; rays that miss it see
        // background (1e30, as a renderer writes it).
        double den = 1.0 - slope * a;
        z[size_t(j) * map + i] = float(a < edge && d_o > 0.0 ? d_o : (den > z_r / far ? z_r / den : 1e30));
      }
    return fx::make_shadowmap(map, map, std::move(z), ortho ? extent / map : 0.0);
  }
  // The same map with texels [x0, x1) x [y0, y1) set to depth d (an extra blocker).
  fx::ShadowmapData shadowmap_with(int x0, int x1, int y0, int y1, float d) const {
    auto z = shadowmap().z;
    for (int j = y0; j < y1; ++j)
      for (int i = x0; i < x1; ++i) z[size_t(j) * size_t(map) + size_t(i)] = d;
    return fx::make_shadowmap(map, map, std::move(z), ortho ? extent / map : 0.0);
  }
  // Receivers on a grid x, y ∈ [-1, 1] (as P); L.shadow the renderer's hard verdict, the ray
  // from the light's centre (the origin) to the receiver: blocked where it crosses depth d_o at
  // x < edge·d_o, i.e. x / z < edge with the occluder in front.
  fx::ShadowmapInputs inputs() const {
    fx::ShadowmapInputs in;
    in.w = w;
    in.h = h;
    const size_t n = size_t(w) * h;
    in.position.resize(3 * n);
    in.fg.assign(n, 1.0f);
    in.hard.assign(n, 1.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        size_t i = size_t(y) * w + x;
        double px = 2.0 * (x + 0.5) / w - 1.0, py = 1.0 - 2.0 * (y + 0.5) / h;
        in.position[i] = float(px);
        in.position[n + i] = float(py);
        in.position[2 * n + i] = float(-(z_r + slope * px));
        const bool behind = ortho ? px < edge : px / (z_r + slope * px) < edge;
        if (d_o > 0.0 && d_o < z_r + slope * px && behind) in.hard[i] = 0.0f;
      }
    return in;
  }
  // Receiver i at (x, y, −z) on its plane: the line from it through the edge meets the light's
  // plane z = 0 at x = c; the light points beyond (x > c) are the ones it sees.
  // ortho: the directions to the sun past the edge, in tan of their angle from the axis (a ray
  // at tan t along x crosses the occluder's depth at x + t·(z − d_o)).
  double chord(double x) const {
    const double z = z_r + slope * x;
    if (ortho) return (edge - x) / (z - d_o);
    return (edge * z - x) * d_o / (z - d_o);
  }
  // Closed form: the part of the light's disk (radius R) seen past the edge, as its share of
  // receiver i's irradiance (the receiver's cosine, the disk's, the inverse square: what a
  // renderer's soft shadow is; isg-synth's quadrature).
  double visible(const fx::ShadowmapInputs& in, size_t i) const {
    const size_t n = size_t(in.w) * size_t(in.h);
    const double x = in.position[i], c = chord(x), ns = std::sqrt(1.0 + slope * slope);
    if (c >= R) return 0.0;
    if (c <= -R) return 1.0;
    // A sun: its disk in tan space (the cone of directions within its half angle; the receiver
    // faces the axis, so n·ω varies by under R²/2 over it: uniform).
    if (ortho) return isg::synth::disk_visible_fraction(c, R);
    return isg::synth::disk_irradiance_beyond_chord({x, double(in.position[n + i]), -(z_r + slope * x)},
                                                    {slope / ns, 0.0, 1.0 / ns}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, R, c);
  }
  // The same part as the plain fraction of the disk (every light point weighed alike).
  double visible_uniform(const fx::ShadowmapInputs& in, size_t i) const {
    return isg::synth::disk_visible_fraction(chord(in.position[i]), R);
  }
  fx::ShadowmapSettings settings(int taps, const std::string& pattern,
                                 const std::string& method = "pcss") const {
    fx::ShadowmapSettings s;
    s.method = method;
    s.yfov_deg = 90.0;
    s.ortho = ortho;
    s.width_m = s.height_m = extent;
    s.light_radius = R;
    s.facing = false;  // a disk light in the map's plane, as the closed form has it
    s.taps = taps;
    s.pattern = pattern;
    return s;
  }
};

inline gpu::Buffer upload(gpu::Context& ctx, const std::vector<float>& v, const char* name) {
  gpu::Buffer b(ctx, std::max<size_t>(v.size(), 1) * sizeof(float), name);
  if (!v.empty()) b.upload(std::span<const float>(v));
  return b;
}

inline std::vector<float> run_gpu(gpu::Context& ctx, const fx::ShadowmapInputs& in,
                           const fx::ShadowmapData& map, const fx::ShadowmapSettings& s,
                           fx::ShadowmapStats* stats) {
  const bool has_p = !in.position.empty();
  auto geo = upload(ctx, has_p ? in.position : in.depth, "geo");
  auto fg = upload(ctx, in.fg, "fg"), hard = upload(ctx, in.hard, "hard"),
       mb = upload(ctx, map.z, "map");
  gpu::Buffer soft(ctx, in.fg.size() * sizeof(float), "soft");
  fx::ShadowmapPass pass(ctx, s, map, uint32_t(in.w), uint32_t(in.h), has_p);
  gpu::Sequence seq(ctx);
  pass.record(seq, geo, fg, hard, mb, soft, "shadows." + s.method);
  seq.submit();
  if (stats) *stats = pass.stats();
  return soft.download_as<float>(in.fg.size());
}

// Pass shadows.derive on the GPU (L.shadow and L.occluder from the map), P given.
inline fx::DerivedShadow run_derive_gpu(gpu::Context& ctx, const fx::ShadowmapInputs& in,
                                        const fx::ShadowmapData& map, const fx::ShadowmapSettings& s) {
  const size_t n = in.fg.size();
  auto geo = upload(ctx, in.position, "geo"), fg = upload(ctx, in.fg, "fg"), mb = upload(ctx, map.z, "map");
  gpu::Buffer shadow(ctx, n * sizeof(float), "shadow"), occ(ctx, n * sizeof(float), "occluder");
  fx::ShadowmapDerivePass pass(ctx, s, map, uint32_t(in.w), uint32_t(in.h), true);
  gpu::Sequence seq(ctx);
  pass.record(seq, geo, fg, mb, shadow, true, occ, "shadows.derive");
  seq.submit();
  return {shadow.download_as<float>(n), occ.download_as<float>(n)};
}

// Pixels where GPU and reference differ by more than 1e-3 (a tap landing in the other texel
// through float rounding of floor(), or a blocker test at its threshold, moves one tap).
inline size_t mismatches(const std::vector<float>& a, const std::vector<float>& b, double* max_diff) {
  size_t bad = 0;
  *max_diff = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    double d = std::abs(double(a[i]) - b[i]);
    *max_diff = std::max(*max_diff, d);
    if (d > 1e-3) ++bad;
  }
  return bad;
}

// RMSE of `got` against the closed-form visibility of the parallel planes.
inline double planes_rmse(const Planes& pl, const fx::ShadowmapInputs& in, const std::vector<float>& got) {
  double e = 0;
  for (int y = 0; y < in.h; ++y)
    for (int x = 0; x < in.w; ++x) {
      const size_t i = size_t(y) * in.w + x;
      e += std::pow(got[i] - pl.visible(in, i), 2);
    }
  return std::sqrt(e / double(in.w * in.h));
}

}  // namespace isg::test
