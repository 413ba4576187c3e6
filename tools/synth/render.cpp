// The ray tracer: intersection, the shading model, and every in-memory render.
//
// Shading at a hit (n faces the viewer, wo toward the viewer):
//   s      = Schlick Fresnel F(n·wo) with F0 = ((ior−1)/(ior+1))², or the constant weight
//   weight = spec_colour · s                   (refl.weight)
//   kd     = 1 − s                             (the diffuse layer's share)
//   other  = emission + kd·albedo·fill         (constant ambient from the uniform world)
//   direct = kd·albedo/π · I·c_l · max(0, n·l) / d²    (<light>.direct; c_l = 1 for a sphere
//            light, max(0, n_l·(−l)) for a disk or rect light, the cone's attenuation for a
//            spot); a sun: kd·albedo/π · E · max(0, n·direction)
//   beauty = other + Σ_lights direct·shadow + weight·refl
// refl is the radiance arriving along the mirror direction: at the reflected hit
// other + Σ direct·shadow (one bounce: the specular layer of a surface seen in a reflection is
// left out), the world colour `fill` on a miss.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <thread>

#include "synth.h"
#include "tracer.h"

namespace isg::synth {
using namespace detail;

double spot_attenuation(const Light& spot, Vec3 dir_from_light) {
  // Cycles: spot_smooth = 1 / ((1 − cos_half_spot_angle)·blend), smoothstepf of
  // (cos θ − cos_half_spot_angle)·spot_smooth, clamped to [0, 1].
  const double cos_half = std::cos(0.5 * spot.spot_angle_deg * kPi / 180);
  const double cos_t = dot(normalize(spot.normal), dir_from_light);
  if (spot.spot_blend <= 0) return cos_t > cos_half ? 1.0 : 0.0;
  const double t = std::clamp((cos_t - cos_half) / ((1 - cos_half) * spot.spot_blend), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

double disk_visible_fraction(double d, double R) {
  // Area of the circular segment beyond a chord at distance d from the centre of a disk of
  // radius R: R²·acos(d/R) − d·sqrt(R² − d²) (the standard circular-segment formula), over
  // the disk's area πR². It runs from 1 at d = −R to 0 at d = R; visible is the far side.
  const double x = std::clamp(d, -R, R);
  return (R * R * std::acos(x / R) - x * std::sqrt(R * R - x * x)) / (kPi * R * R);
}

double disk_irradiance_beyond_chord(Vec3 p, Vec3 n, Vec3 centre, Vec3 u, Vec3 v, double R, double c) {
  // x = R sin θ across the chord (θ from asin(c / R) to π/2), y = R cos θ · t along it
  // (t ∈ [−1, 1]): dx dy = R² cos² θ dθ dt, smooth in θ and t, integrated by Gauss-Legendre.
  static const std::vector<std::pair<double, double>> gl = [] {
    constexpr int kN = 48;
    std::vector<std::pair<double, double>> nodes;  // (x, weight) on [−1, 1]
    for (int i = 0; i < kN; ++i) {
      double x = std::cos(kPi * (i + 0.75) / (kN + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {  // Newton on the Legendre polynomial P_N
        double p0 = 1, p1 = x;
        for (int k = 2; k <= kN; ++k) {
          const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = kN * (x * p1 - p0) / (x * x - 1);
        const double dx = p1 / dp;
        x -= dx;
        if (std::abs(dx) < 1e-16) break;
      }
      nodes.emplace_back(x, 2 / ((1 - x * x) * dp * dp));
    }
    return nodes;
  }();
  const Vec3 nl = normalize(cross(u, v));
  auto part = [&](double c0) {
    const double t0 = std::asin(std::clamp(c0 / R, -1.0, 1.0)), t1 = kPi / 2;
    double sum = 0;
    for (const auto& [a, wa] : gl) {
      const double th = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * a, x = R * std::sin(th), ymax = R * std::cos(th);
      for (const auto& [b, wb] : gl) {
        const Vec3 r = centre + u * x + v * (ymax * b) - p;
        const double r2 = dot(r, r);
        sum += wa * wb * ymax * ymax * std::max(dot(n, r), 0.0) * std::abs(dot(nl, r)) / (r2 * r2);
      }
    }
    return sum * 0.5 * (t1 - t0);
  };
  const double all = part(-R);
  return all > 0 ? part(c) / all : disk_visible_fraction(c, R);
}

Image render_aovs(const Scene& s, const Options& o) {
  std::vector<std::string> names = {"R",   "G",   "B",   "A",   "Z",   "P.X",
                                    "P.Y", "P.Z", "N.X", "N.Y", "N.Z", "roughness"};
  const int c_light = int(names.size());  // 5 channels per light from here
  for (const Light& l : s.lights)
    for (const char* c : {".shadow", ".occluder", ".direct.R", ".direct.G", ".direct.B"})
      names.push_back(l.name + c);
  const int c_refl = int(names.size());
  for (const char* c : {"refl.R", "refl.G", "refl.B", "refl.dist", "refl.weight.R", "refl.weight.G",
                        "refl.weight.B", "other.R", "other.G", "other.B"})
    names.push_back(c);
  Image img(o.width, o.height, names);
  const size_t nl = s.lights.size();
  const CameraFrame cf = camera_frame(s.camera);
  const int n = o.aov_spp;
  parallel_rows(o.height, o.threads, [&](int y) {
    struct PerLight {
      Vec3 direct;
      double direct_shadowed = 0, direct_sum = 0, occ_sum = 0;
      int occ_n = 0;
    };
    for (int x = 0; x < o.width; ++x) {
      Rng rng(pixel_id(x, y, o.width), 0, kAovJitter);
      Vec3 beauty, refl, weight, other, P, N;
      double cover = 0, rough = 0, z = kBackgroundZ;
      double refl_dist_sum = 0;
      int refl_n = 0;
      std::vector<PerLight> pl(nl);
      for (int i = 0; i < n; ++i) {
        const auto [fx, fy] = pixel_position(x, y, i, n, rng);
        const Ray r = pinhole_ray(cf, fx, fy);
        const Primary pr = shade_primary(s, r);
        if (!pr.hit) continue;
        if (i == 0) z = float(dot(pr.h.p - cf.pos, cf.f));  // Z: the first sample
        cover += 1;
        beauty += pr.beauty;
        refl += pr.refl;
        weight += pr.sf.weight;
        other += pr.sf.other;
        P += pr.h.p;
        N += pr.sf.n;
        rough += pr.sf.m->roughness;
        for (size_t k = 0; k < nl; ++k) {
          const Hard& hs = pr.hs[k];
          pl[k].direct += hs.direct;
          pl[k].direct_sum += luminance(hs.direct);
          pl[k].direct_shadowed += luminance(hs.direct) * hs.shadow;
          if (hs.occluder > 0) pl[k].occ_sum += hs.occluder, ++pl[k].occ_n;
        }
        if (pr.refl_dist > 0 && luminance(pr.sf.weight) > 0)
          refl_dist_sum += pr.refl_dist, ++refl_n;
      }
      const double inv = 1.0 / n;
      put3(img, x, y, 0, beauty * inv);
      img.at(x, y, 3) = float(cover * inv);
      img.at(x, y, 4) = z;
      if (cover > 0) {  // geometric channels: averages over the foreground samples
        put3(img, x, y, 5, P / cover);
        put3(img, x, y, 8, length(N) > 0 ? normalize(N) : N);
        img.at(x, y, 11) = float(rough / cover);
      }
      for (size_t k = 0; k < nl; ++k) {
        const int c = c_light + 5 * int(k);
        const PerLight& p = pl[k];
        img.at(x, y, c) = float(p.direct_sum > 1e-12 ? p.direct_shadowed / p.direct_sum : 1.0);
        img.at(x, y, c + 1) = float(p.occ_n ? p.occ_sum / p.occ_n : 0);
        put3(img, x, y, c + 2, p.direct * inv);
      }
      put3(img, x, y, c_refl, refl * inv);
      img.at(x, y, c_refl + 3) = float(refl_n ? refl_dist_sum / refl_n : 0);
      put3(img, x, y, c_refl + 4, weight * inv);
      put3(img, x, y, c_refl + 7, other * inv);
    }
  });
  return img;
}

Image render_shadowmap(const Scene& s, int size, size_t light) {
  Image img(size, size, {"Z"});
  const ShadowMapView view = shadowmap_view(s, light);
  const auto& m = view.world_to_light;
  CameraFrame cf;
  cf.r = {m[0], m[1], m[2]};
  cf.u = {m[4], m[5], m[6]};
  cf.f = {-m[8], -m[9], -m[10]};
  // The map camera's position from the view matrix's translation column: −Rᵀ·t.
  cf.pos = (cf.r * m[3] + cf.u * m[7] - cf.f * m[11]) * -1.0;
  if (s.lights[light].type != Light::Type::sun) cf.pos = s.lights[light].position;
  // 90°: exactly 1 (tan(π/4) rounds below it).
  cf.tan_x = cf.tan_y = view.yfov_deg == 90 ? 1.0 : std::tan(0.5 * view.yfov_deg * kPi / 180);
  cf.w = cf.h = size;
  parallel_rows(size, 0, [&](int y) {
    for (int x = 0; x < size; ++x) {
      Ray r;
      if (view.orthographic) {
        // Parallel rays down the axis from the map camera's plane, over width_m × height_m.
        const double sx = (2 * (x + 0.5) / size - 1) * 0.5 * view.width_m;
        const double sy = (1 - 2 * (y + 0.5) / size) * 0.5 * view.height_m;
        r = {cf.pos + cf.r * sx + cf.u * sy, cf.f};
      } else {
        r = pinhole_ray(cf, x + 0.5, y + 0.5);
      }
      const Hit h = trace(s, r);
      img.at(x, y, 0) = h.prim < 0 ? kBackgroundZ : float(dot(h.p - r.o, cf.f));
    }
  });
  return img;
}

Image render_softshadow(const Scene& s, const Options& o, int spp, size_t light) {
  const Light& l = s.lights.at(light);
  Image img(o.width, o.height, {l.name + ".softshadow"});
  const CameraFrame cf = camera_frame(s.camera);
  parallel_rows(o.height, o.threads, [&](int y) {
    for (int x = 0; x < o.width; ++x) {
      const uint64_t id = pixel_id(x, y, o.width);
      Rng jitter(id, 0, kAovJitter);  // the AOVs' pixel samples, cycled
      // Σ direct·visible / Σ direct over the pixel's samples, each light sample's direct light
      // (area_direct) with its visibility: the luminance ratio of soft to unshadowed light that
      // the Cycles cases' references are, i.e. the visible fraction of the light weighted by the
      // irradiance each of its points gives (under a low light its top outweighs its bottom).
      double num = 0, den = 0;
      const int n_pos = o.aov_spp;
      std::vector<std::pair<double, double>> pos(static_cast<size_t>(n_pos));
      for (int i = 0; i < n_pos; ++i) pos[size_t(i)] = pixel_position(x, y, i, n_pos, jitter);
      for (int i = 0; i < spp; ++i) {
        const auto [fx, fy] = pos[size_t(i % n_pos)];
        const Ray r = pinhole_ray(cf, fx, fy);
        const Hit h = trace(s, r);
        if (h.prim < 0) continue;
        const Surface sf = surface(s, h, r.d);
        Rng rng(id, uint64_t(i), light_purpose(light));
        const auto [u, v] = stratified(i, spp, rng, o.stratified);
        const LightSample ls = sample_light_direct(l, sf, u, v);
        const double w = luminance(ls.direct);
        if (w > 0 && visible(s, sf, ls)) num += w;
        den += w;
      }
      // 1 where the light does not reach the surface (facing away) or on the background, as
      // the luminance ratio of cases/ gives.
      double value = 1;
      if (den > 1e-12) value = num / den;
      img.at(x, y, 0) = float(value);
    }
  });
  return img;
}

Image render_softshadow_closed_form(const Scene& s, const Options& o) {
  if (!s.parallel_planes || s.lights.front().type != Light::Type::disk)
    throw std::runtime_error("scene: the closed form needs the parallel-planes scene");
  const ParallelPlanes pp = *s.parallel_planes;
  const Light& key = s.lights.front();
  Image img(o.width, o.height, {key.name + ".softshadow"});
  const CameraFrame cf = camera_frame(s.camera);
  const double hl = key.position.z - pp.receiver_z, ho = pp.occluder_z - pp.receiver_z;
  parallel_rows(o.height, o.threads, [&](int y) {
    for (int x = 0; x < o.width; ++x) {
      const Hit h = trace(s, pinhole_ray(cf, x + 0.5, y + 0.5));
      double value = 1;
      if (h.prim >= 0 && h.p.z < pp.occluder_z - 1e-6) {
        // Light point q is hidden when the segment p→q crosses z = occluder_z at x < edge_x,
        // i.e. when q.x < x_line = p.x + (edge_x − p.x)·(z_l − p.z)/(z_o − p.z): the
        // occluder's edge projected from p onto the light plane is the chord x = x_line,
        // and the visible part of the disk is the circular segment beyond it.
        const double zl = hl - (h.p.z - pp.receiver_z), zo = ho - (h.p.z - pp.receiver_z);
        const double x_line = h.p.x + (pp.edge_x - h.p.x) * zl / zo;
        // The visible part's share of the irradiance (as render_softshadow weighs it).
        value = disk_irradiance_beyond_chord(h.p, {0, 0, 1}, key.position, {1, 0, 0}, {0, 1, 0},
                                             key.radius, x_line - key.position.x);
      }
      img.at(x, y, 0) = float(value);
    }
  });
  return img;
}

Image render_glossy(const Scene& s, const Options& o, int spp) {
  Image img(o.width, o.height, {"refl.glossy.R", "refl.glossy.G", "refl.glossy.B"});
  const CameraFrame cf = camera_frame(s.camera);
  parallel_rows(o.height, o.threads, [&](int y) {
    for (int x = 0; x < o.width; ++x) {
      const uint64_t id = pixel_id(x, y, o.width);
      Rng jitter(id, 0, kAovJitter);
      const int n_pos = o.aov_spp;
      std::vector<std::pair<double, double>> pos(static_cast<size_t>(n_pos));
      for (int i = 0; i < n_pos; ++i) pos[size_t(i)] = pixel_position(x, y, i, n_pos, jitter);
      // Per pixel position: Σ g·L / Σ g (an average of incoming radiance, like refl), then
      // averaged over positions with background positions counting 0 (premultiplied).
      std::vector<Vec3> num(static_cast<size_t>(n_pos));
      std::vector<double> den(size_t(n_pos), 0.0);
      std::vector<Vec3> sharp(static_cast<size_t>(n_pos));
      std::vector<int> kind(size_t(n_pos), -1);  // -1 unknown, 0 background, 1 foreground
      for (int i = 0; i < spp; ++i) {
        const size_t k = size_t(i % n_pos);
        const Ray r = pinhole_ray(cf, pos[k].first, pos[k].second);
        const Hit h = trace(s, r);
        if (h.prim < 0) {
          kind[k] = 0;
          continue;
        }
        const Surface sf = surface(s, h, r.d);
        if (kind[k] < 0) {
          kind[k] = 1;
          sharp[k] = shade_primary(s, r).refl;
        }
        if (luminance(sf.weight) <= 0) continue;
        Rng rng(id, uint64_t(i), kGlossy);
        const auto [u1, u2] = stratified(i / n_pos, (spp + n_pos - 1) / n_pos, rng, o.stratified);
        const double alpha = sf.m->roughness * sf.m->roughness;
        Vec3 wi;
        const double g = sample_ggx(sf.n, sf.wo, alpha, u1, u2, wi);
        if (g <= 0) continue;
        num[k] += radiance_seen_in_reflection(s, spawn(s, sf.p, sf.n, sf.prim, wi)) * g;
        den[k] += g;
      }
      Vec3 sum;
      for (size_t k = 0; k < size_t(n_pos); ++k) {
        if (kind[k] != 1) continue;
        sum += den[k] > 0 ? num[k] / den[k] : sharp[k];
      }
      put3(img, x, y, 0, sum / n_pos);
    }
  });
  return img;
}

namespace {

Image render_lens(const Scene& s, const Options& o, int spp, bool full, bool lens) {
  Image img(o.width, o.height, {"R", "G", "B", "A"});
  const CameraFrame cf = camera_frame(s.camera);
  parallel_rows(o.height, o.threads, [&](int y) {
    for (int x = 0; x < o.width; ++x) {
      const uint64_t id = pixel_id(x, y, o.width);
      Vec3 sum;
      double cover = 0;
      const std::vector<int> lens_perm = permutation(id, kLens, spp);
      const std::vector<int> light_perm = permutation(id, kLight, spp);
      const std::vector<int> gloss_perm = permutation(id, kGlossy, spp);
      // Lights after the first: their own permutations and streams (the first keeps the
      // one-light scenes' samples).
      std::vector<std::vector<int>> more_perm;
      if (full)
        for (size_t k = 1; k < s.lights.size(); ++k)
          more_perm.push_back(permutation(id, light_purpose(k), spp));
      for (int i = 0; i < spp; ++i) {
        Rng rng(id, uint64_t(i), full ? kBeauty : kLens);
        // The pixel box and the lens, each stratified when spp is a square.
        const auto [jx, jy] =
            o.aov_spp == 1 && !lens ? std::pair{0.5, 0.5} : stratified(i, spp, rng, o.stratified);
        const auto [lu, lv] = stratified(lens_perm[size_t(i)], spp, rng, o.stratified);
        const Ray r = lens ? thin_lens_ray(s.camera, cf, x + jx, y + jy, lu, lv)
                           : pinhole_ray(cf, x + jx, y + jy);
        if (!full) {
          const Primary pr = shade_primary(s, r);
          if (pr.hit) sum += pr.beauty, cover += 1;
          continue;
        }
        const Hit h = trace(s, r);
        if (h.prim < 0) continue;
        cover += 1;
        const Surface sf = surface(s, h, r.d);
        Vec3 c = sf.other;
        // Soft lights: one stratified light sample each.
        for (size_t k = 0; k < s.lights.size(); ++k) {
          Rng own(id, uint64_t(i), light_purpose(k));
          Rng& lr = k == 0 ? rng : own;
          const int stratum = k == 0 ? light_perm[size_t(i)] : more_perm[k - 1][size_t(i)];
          const auto [u, v] = stratified(stratum, spp, lr, o.stratified);
          const LightSample ls = sample_light_direct(s.lights[k], sf, u, v);
          if (luminance(ls.direct) > 0 && visible(s, sf, ls)) c += ls.direct;
        }
        // Glossy: one GGX sample, normalised by E[G2/G1] as in the glossy reference.
        if (luminance(sf.weight) > 0) {
          const auto [g1, g2] = stratified(gloss_perm[size_t(i)], spp, rng, o.stratified);
          const double alpha = sf.m->roughness * sf.m->roughness;
          Vec3 wi;
          const double g = sample_ggx(sf.n, sf.wo, alpha, g1, g2, wi);
          if (g > 0)
            c += sf.weight * radiance_seen_in_reflection(s, spawn(s, sf.p, sf.n, sf.prim, wi)) * g;
        }
        sum += c;
      }
      put3(img, x, y, 0, sum / spp);
      img.at(x, y, 3) = float(cover / spp);
    }
  });
  return img;
}

}  // namespace

Image render_dof(const Scene& s, const Options& o, int spp) {
  return render_lens(s, o, spp, false, true);
}

Image render_beauty_ref(const Scene& s, const Options& o, int spp) {
  return render_lens(s, o, spp, true, s.depth_of_field);
}

void add_mask(Image& ref, const Image& aovs, MaskKind kind, const std::string& light) {
  const size_t old_nc = ref.channels.size(), nc = old_nc + 1;
  std::vector<float> px(size_t(ref.width) * ref.height * nc);
  const int a = aovs.channel("A"), z = aovs.channel("Z"), d = aovs.channel(light + ".direct.R"),
            w = aovs.channel("refl.weight.R");
  auto lum = [&](int x, int y, int c) {
    return luminance({aovs.at(x, y, c), aovs.at(x, y, c + 1), aovs.at(x, y, c + 2)});
  };
  auto fg = [&](int x, int y) { return aovs.at(x, y, a) > 0.5f && aovs.at(x, y, z) < 1e9f; };
  double threshold = 0;
  if (kind == MaskKind::softshadow) {
    std::vector<double> v;
    for (int y = 0; y < aovs.height; ++y)
      for (int x = 0; x < aovs.width; ++x)
        if (fg(x, y)) v.push_back(lum(x, y, d));
    if (!v.empty()) {
      const size_t k = std::min(v.size() - 1, size_t(0.99 * double(v.size())));
      std::nth_element(v.begin(), v.begin() + long(k), v.end());
      threshold = 0.02 * v[k];
    }
  }
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x) {
      for (size_t c = 0; c < old_nc; ++c)
        px[(size_t(y) * ref.width + x) * nc + c] =
            ref.pixels[(size_t(y) * ref.width + x) * old_nc + c];
      bool m = fg(x, y);
      if (kind == MaskKind::softshadow) m = m && lum(x, y, d) >= threshold && threshold > 0;
      if (kind == MaskKind::glossy) m = m && lum(x, y, w) > 0;
      px[(size_t(y) * ref.width + x) * nc + nc - 1] = m ? 1.0f : 0.0f;
    }
  ref.pixels = std::move(px);
  ref.channels.push_back("mask");
}

}  // namespace isg::synth
