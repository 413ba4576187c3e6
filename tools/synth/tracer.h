// Inside the ray tracer (not a public header): random numbers, intersection, the shading model,
// the camera, light sampling and GGX, shared by the renderers in render.cpp (whose header
// comment gives the shading model).
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <thread>

#include "synth.h"

namespace isg::synth::detail {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = std::numbers::pi;
constexpr float kBackgroundZ = 1e10f;

// ---- random numbers: a counter-based stream per (pixel, sample, purpose) ----

enum Purpose : uint64_t { kAovJitter = 1, kLight = 2, kGlossy = 3, kLens = 4, kBeauty = 5 };
// lights[0] samples with kLight (so one-light scenes keep their images), lights[k] with 16 + k.
inline uint64_t light_purpose(size_t light) { return light == 0 ? kLight : 16 + uint64_t(light); }

uint64_t mix64(uint64_t z) {  // splitmix64's finaliser
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

struct Rng {
  uint64_t state;
  Rng(uint64_t pixel, uint64_t sample, uint64_t purpose)
      : state(mix64(mix64(mix64(pixel + 0x9E3779B97F4A7C15ull) ^ sample) ^ (purpose << 56))) {}
  double next() {
    state += 0x9E3779B97F4A7C15ull;
    return double(mix64(state) >> 11) * 0x1.0p-53;
  }
};

// Sample s of n in [0,1)²: jittered on a k×k grid when n = k², otherwise uniform.
inline std::pair<double, double> stratified(int s, int n, Rng& rng, bool stratify) {
  const double a = rng.next(), b = rng.next();
  const int k = int(std::lround(std::sqrt(double(n))));
  if (!stratify || k * k != n) return {a, b};
  return {((s % k) + a) / k, ((s / k) + b) / k};
}

// A per-pixel random permutation of the strata, so that several stratified dimensions of one
// sample are not correlated with each other.
inline std::vector<int> permutation(uint64_t pixel, uint64_t purpose, int n) {
  std::vector<int> p(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) p[size_t(i)] = i;
  Rng rng(pixel, 0xFFFFFFFFull, purpose);
  for (int i = n - 1; i > 0; --i)
    std::swap(p[size_t(i)], p[size_t(std::min(i, int(rng.next() * (i + 1))))]);
  return p;
}

// Shirley's concentric map of [0,1)² onto the unit disk (keeps strata compact).
inline std::pair<double, double> concentric_disk(double u, double v) {
  const double a = 2 * u - 1, b = 2 * v - 1;
  if (a == 0 && b == 0) return {0, 0};
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4) * (b / a);
  } else {
    r = b;
    phi = kPi / 2 - (kPi / 4) * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

void basis(Vec3 n, Vec3& t, Vec3& b) {  // Duff et al. 2017, orthonormal basis around n
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double c = n.x * n.y * a;
  t = {1 + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

// ---- intersection ----

struct Ray {
  Vec3 o, d;
  int skip = -1;  // the primitive a secondary ray leaves, which it cannot hit again
};

struct Hit {
  double t = kInf;
  Vec3 p, n;  // n: unit outward (quads: facing the ray origin)
  int prim = -1;
};

// Every primitive is convex, so a secondary ray leaving one outward (or leaving a quad either
// way) cannot hit it again: it starts exactly at the hit point and skips that primitive, with
// no offset that would depend on the scene's scale. A ray entering a solid (toward a light
// behind its tangent plane) starts an epsilon inside, scaled by the magnitude of the hit
// position so that the same scene far from the origin traces the same rays.
inline double epsilon(Vec3 p) {
  return 1e-9 * std::max({1.0, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
}

inline bool intersect_sphere(const Primitive& s, const Ray& r, double tmax, Hit& h) {
  const Vec3 oc = r.o - s.centre;  // small in every scene frame, even at 1e5
  const double b = dot(oc, r.d);
  const double c = dot(oc, oc) - s.radius * s.radius;
  const double disc = b * b - c;
  if (disc < 0) return false;
  const double sq = std::sqrt(disc);
  // Stable roots: q = −b − sign(b)·sq, t0 = q, t1 = c/q (|d| = 1).
  const double q = -b - std::copysign(sq, b);
  double t0 = q, t1 = q != 0 ? c / q : q;
  if (t0 > t1) std::swap(t0, t1);
  double t = t0 > 0 ? t0 : t1;
  if (t <= 0 || t >= tmax) return false;
  h.t = t;
  h.n = normalize(oc + r.d * t);
  return true;
}

inline bool intersect_box(const Primitive& bx, const Ray& r, double tmax, Hit& h) {
  const Vec3 o = r.o - bx.centre;
  const double oa[3] = {o.x, o.y, o.z}, da[3] = {r.d.x, r.d.y, r.d.z};
  const double ha[3] = {bx.half.x, bx.half.y, bx.half.z};
  double tn = -kInf, tf = kInf;
  int an = 0, af = 0;
  for (int i = 0; i < 3; ++i) {
    if (da[i] == 0) {
      if (std::abs(oa[i]) > ha[i]) return false;
      continue;
    }
    double t0 = (-ha[i] - oa[i]) / da[i], t1 = (ha[i] - oa[i]) / da[i];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > tn) tn = t0, an = i;
    if (t1 < tf) tf = t1, af = i;
  }
  if (tn > tf) return false;
  double t = tn;
  int axis = an;
  if (t <= 0) t = tf, axis = af;
  if (t <= 0 || t >= tmax) return false;
  const double p = oa[axis] + da[axis] * t;
  Vec3 n{};
  (axis == 0 ? n.x : axis == 1 ? n.y : n.z) = p > 0 ? 1 : -1;
  h.t = t;
  h.n = n;
  return true;
}

inline bool intersect_cylinder(const Primitive& c, const Ray& r, double tmax, Hit& h) {
  const Vec3 o = r.o - c.centre;
  bool found = false;
  // Side.
  const double a = r.d.x * r.d.x + r.d.y * r.d.y;
  if (a > 0) {
    const double b = o.x * r.d.x + o.y * r.d.y;
    const double cc = o.x * o.x + o.y * o.y - c.radius * c.radius;
    const double disc = b * b - a * cc;
    if (disc >= 0) {
      const double sq = std::sqrt(disc);
      for (double t : {(-b - sq) / a, (-b + sq) / a}) {
        if (t <= 0 || t >= tmax) continue;
        const double z = o.z + r.d.z * t;
        if (std::abs(z) > c.half.z) continue;
        tmax = t;
        h.t = t;
        h.n = normalize(Vec3{o.x + r.d.x * t, o.y + r.d.y * t, 0});
        found = true;
        break;
      }
    }
  }
  // Caps.
  if (r.d.z != 0) {
    for (double zc : {-c.half.z, c.half.z}) {
      const double t = (zc - o.z) / r.d.z;
      if (t <= 0 || t >= tmax) continue;
      const double x = o.x + r.d.x * t, y = o.y + r.d.y * t;
      if (x * x + y * y > c.radius * c.radius) continue;
      tmax = t;
      h.t = t;
      h.n = {0, 0, zc > 0 ? 1.0 : -1.0};
      found = true;
    }
  }
  return found;
}

inline bool intersect_quad(const Primitive& q, const Ray& r, double tmax, Hit& h) {
  Vec3 n = normalize(cross(q.u, q.v));
  const double dn = dot(r.d, n);
  if (dn == 0) return false;
  const Vec3 oc = q.centre - r.o;
  const double t = dot(oc, n) / dn;
  if (t <= 0 || t >= tmax) return false;
  const Vec3 rel = r.d * t - oc;  // hit − centre
  if (std::abs(dot(rel, q.u)) > dot(q.u, q.u) || std::abs(dot(rel, q.v)) > dot(q.v, q.v))
    return false;
  h.t = t;
  h.n = dn > 0 ? -n : n;
  return true;
}

inline Hit trace(const Scene& s, const Ray& r, double tmax = kInf) {
  Hit best;
  for (size_t i = 0; i < s.prims.size(); ++i) {
    if (int(i) == r.skip) continue;
    const Primitive& p = s.prims[i];
    Hit h;
    bool hit = false;
    switch (p.kind) {
      case Primitive::Kind::sphere:
        hit = intersect_sphere(p, r, tmax, h);
        break;
      case Primitive::Kind::box:
        hit = intersect_box(p, r, tmax, h);
        break;
      case Primitive::Kind::cylinder:
        hit = intersect_cylinder(p, r, tmax, h);
        break;
      case Primitive::Kind::quad:
        hit = intersect_quad(p, r, tmax, h);
        break;
    }
    if (hit) {
      tmax = h.t;
      best = h;
      best.prim = int(i);
    }
  }
  if (best.prim >= 0) best.p = r.o + r.d * best.t;
  return best;
}

// n: the normal facing the side the primitive was seen from (outside for solids).
inline Ray spawn(const Scene& s, Vec3 p, Vec3 n, int prim, Vec3 dir) {
  if (s.prims[size_t(prim)].kind == Primitive::Kind::quad || dot(n, dir) >= 0)
    return {p, dir, prim};
  return {p - n * epsilon(p), dir, -1};
}

inline bool occluded(const Scene& s, Vec3 p, Vec3 n, int prim, Vec3 q, double* dist = nullptr) {
  const Vec3 to = q - p;
  const double d = length(to);
  const Ray r = spawn(s, p, n, prim, to / d);
  const Hit h = trace(s, r, d * (1 - 1e-9));
  if (h.prim < 0) return false;
  if (dist) *dist = length(h.p - p);
  return true;
}

// Toward a distant light along unit `dir`: anything in the way occludes.
inline bool occluded_along(const Scene& s, Vec3 p, Vec3 n, int prim, Vec3 dir,
                           double* dist = nullptr) {
  const Hit h = trace(s, spawn(s, p, n, prim, dir));
  if (h.prim < 0) return false;
  if (dist) *dist = length(h.p - p);
  return true;
}

// ---- shading ----

struct Surface {
  Vec3 p, n, wo;  // n faces wo
  const Material* m = nullptr;
  Vec3 weight;  // refl.weight
  double kd = 1;
  Vec3 other;  // emission + ambient
  int prim = -1;
};

inline Surface surface(const Scene& s, const Hit& h, Vec3 dir) {
  Surface sf;
  sf.p = h.p;
  sf.wo = -dir;
  sf.n = dot(h.n, sf.wo) < 0 ? -h.n : h.n;
  sf.prim = h.prim;
  sf.m = &s.materials[size_t(s.prims[size_t(h.prim)].material)];
  const Material& m = *sf.m;
  double spec = 0;
  if (m.spec == Material::Spec::fresnel) {
    const double f0 = std::pow((m.ior - 1) / (m.ior + 1), 2);
    spec = f0 + (1 - f0) * std::pow(1 - std::clamp(dot(sf.n, sf.wo), 0.0, 1.0), 5);
  } else if (m.spec == Material::Spec::constant) {
    spec = m.weight;
  }
  sf.weight = m.spec_colour * spec;
  sf.kd = 1 - spec;
  sf.other = m.emission + m.albedo * s.fill * sf.kd;
  return sf;
}

// The point light's emitted intensity toward `from` (W/sr): 0 behind a disk/rect light, shaped
// by the cone for a spot (not for a sun).
inline Vec3 light_intensity(const Light& l, Vec3 dir_from_light) {
  if (l.type == Light::Type::sphere) return l.intensity;
  if (l.type == Light::Type::spot) return l.intensity * spot_attenuation(l, dir_from_light);
  return l.intensity * std::max(0.0, dot(l.normal, dir_from_light));
}

// A sun's direct light from unit direction `dir`: diffuse BSDF × irradiance × cosine.
inline Vec3 sun_direct(const Light& l, const Surface& sf, Vec3 dir) {
  const double cos = dot(sf.n, dir);
  if (cos <= 0) return {};
  return sf.m->albedo * (sf.kd / kPi) * l.intensity * cos;
}

// <name>.direct: diffuse BSDF × the point light's radiance × cosine (a sun: along its
// direction), unoccluded.
inline Vec3 light_direct(const Light& light, const Surface& sf) {
  if (light.type == Light::Type::sun) return sun_direct(light, sf, light.direction);
  const Vec3 to = light.position - sf.p;
  const double d2 = dot(to, to);
  const Vec3 l = to / std::sqrt(d2);
  const double cos = dot(sf.n, l);
  if (cos <= 0) return {};
  return sf.m->albedo * (sf.kd / kPi) * light_intensity(light, -l) * (cos / d2);
}

struct Hard {
  Vec3 direct;
  double shadow = 1, occluder = 0;
};

inline Hard hard_shadow(const Scene& s, const Surface& sf, const Light& light) {
  Hard r;
  r.direct = light_direct(light, sf);
  if (luminance(r.direct) <= 0) return r;  // facing away: 1 by convention, as cases/ do
  double dist = 0;
  const bool hidden = light.type == Light::Type::sun
                          ? occluded_along(s, sf.p, sf.n, sf.prim, light.direction, &dist)
                          : occluded(s, sf.p, sf.n, sf.prim, light.position, &dist);
  if (hidden) {
    r.shadow = 0;
    r.occluder = dist;
  }
  return r;
}

// Radiance leaving a surface toward the viewer without its specular layer: what reflections
// see (and the glossy reference's incoming radiance).
inline Vec3 radiance_seen_in_reflection(const Scene& s, const Ray& r) {
  const Hit h = trace(s, r);
  if (h.prim < 0) return s.fill;
  const Surface sf = surface(s, h, r.d);
  Vec3 c = sf.other;
  for (const Light& l : s.lights) {
    const Hard hs = hard_shadow(s, sf, l);
    c += hs.direct * hs.shadow;
  }
  return c;
}

Vec3 reflect(Vec3 d, Vec3 n) { return d - n * (2 * dot(d, n)); }

struct Primary {
  bool hit = false;
  Hit h;
  Surface sf;
  std::vector<Hard> hs;  // per light
  Vec3 refl;
  double refl_dist = 0;
  Vec3 beauty;
};

// The AOV shading of a primary ray: point light, hard shadows, sharp reflections.
inline Primary shade_primary(const Scene& s, const Ray& r) {
  Primary pr;
  pr.h = trace(s, r);
  if (pr.h.prim < 0) return pr;
  pr.hit = true;
  pr.sf = surface(s, pr.h, r.d);
  pr.hs.reserve(s.lights.size());
  for (const Light& l : s.lights) pr.hs.push_back(hard_shadow(s, pr.sf, l));
  if (luminance(pr.sf.weight) > 0) {
    const Vec3 d = reflect(r.d, pr.sf.n);
    const Ray rr = spawn(s, pr.sf.p, pr.sf.n, pr.sf.prim, d);
    const Hit h2 = trace(s, rr);
    pr.refl = radiance_seen_in_reflection(s, rr);
    pr.refl_dist = h2.prim >= 0 ? length(h2.p - pr.sf.p) : 0;
  }
  Vec3 lit = pr.sf.other;
  for (const Hard& hs : pr.hs) lit += hs.direct * hs.shadow;
  pr.beauty = lit + pr.sf.weight * pr.refl;
  return pr;
}

// ---- camera ----

struct CameraFrame {
  Vec3 pos, r, u, f;
  double tan_x, tan_y;
  int w, h;
};

inline CameraFrame camera_frame(const Camera& c) {
  CameraFrame cf;
  const auto m = world_to_camera(c);
  cf.pos = c.position;
  cf.r = {m[0], m[1], m[2]};
  cf.u = {m[4], m[5], m[6]};
  cf.f = {-m[8], -m[9], -m[10]};
  cf.tan_x = c.sensor_width_mm / (2 * c.focal_length_mm);
  cf.tan_y = cf.tan_x * c.height / c.width;
  cf.w = c.width;
  cf.h = c.height;
  return cf;
}

// Direction (not normalised, unit component along f) through film position (fx, fy) pixels.
inline Vec3 film_dir(const CameraFrame& cf, double fx, double fy) {
  const double sx = (2 * fx / cf.w - 1) * cf.tan_x;
  const double sy = (1 - 2 * fy / cf.h) * cf.tan_y;
  return cf.r * sx + cf.u * sy + cf.f;
}

inline Ray pinhole_ray(const CameraFrame& cf, double fx, double fy) {
  return {cf.pos, normalize(film_dir(cf, fx, fy))};
}

// Thin lens: aperture diameter focal_length / fstop, focus plane at focus_distance (planar).
inline Ray thin_lens_ray(const Camera& c, const CameraFrame& cf, double fx, double fy, double lu,
                  double lv) {
  const Vec3 focus = cf.pos + film_dir(cf, fx, fy) * c.focus_distance;
  const double radius = 0.5 * (c.focal_length_mm * 1e-3) / c.fstop;
  const auto [dx, dy] = concentric_disk(lu, lv);
  const Vec3 o = cf.pos + cf.r * (dx * radius) + cf.u * (dy * radius);
  return {o, normalize(focus - o)};
}

// Pixel position of sample s of n: the centre when n = 1, else stratified jitter.
inline std::pair<double, double> pixel_position(int x, int y, int s, int n, Rng& rng) {
  if (n == 1) return {x + 0.5, y + 0.5};
  const auto [a, b] = stratified(s, n, rng, true);
  return {x + a, y + b};
}

template <class F>
inline void parallel_rows(int height, int threads, F&& row) {
  int n = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
  n = std::min(n, height);
  std::atomic<int> next{0};
  auto work = [&] {
    for (int y; (y = next.fetch_add(1)) < height;) row(y);
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < n; ++i) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
}

uint64_t pixel_id(int x, int y, int w) { return uint64_t(y) * uint64_t(w) + uint64_t(x); }

inline void put3(Image& img, int x, int y, int c, Vec3 v) {
  img.at(x, y, c) = float(v.x);
  img.at(x, y, c + 1) = float(v.y);
  img.at(x, y, c + 2) = float(v.z);
}

// ---- light sampling ----

// A uniformly distributed point on a light's area (sphere: the disk facing p; spot: the disk
// across its axis).
inline Vec3 sample_light(const Light& l, Vec3 p, double u, double v) {
  if (l.type == Light::Type::rect) {
    const Vec3 ua = normalize(l.u_axis - l.normal * dot(l.u_axis, l.normal));
    const Vec3 va = cross(l.normal, ua);
    return l.position + ua * ((u - 0.5) * l.size_u) + va * ((v - 0.5) * l.size_v);
  }
  const Vec3 axis = l.type == Light::Type::sphere ? normalize(l.position - p) : l.normal;
  Vec3 t, b;
  basis(axis, t, b);
  const auto [dx, dy] = concentric_disk(u, v);
  return l.position + t * (dx * l.radius) + b * (dy * l.radius);
}

// Area-light direct lighting of one light sample q (radiance intensity/area):
// kd·albedo/π · L_e·A · cos·cos_l / d², i.e. the point light's formula with q for the centre.
// A spot's cone is evaluated from its centre toward the receiver for every sample (Cycles
// evaluates it from the sampled point; the two differ only in a band about r/d wide at the
// cone's edge): the cone shapes how much light arrives at the receiver, which <name>.direct
// carries, and the soft shadow stays the disk's, so the contract's composite holds exactly.
inline Vec3 area_direct(const Light& light, const Surface& sf, Vec3 q) {
  const Vec3 to = q - sf.p;
  const double d2 = dot(to, to);
  const Vec3 l = to / std::sqrt(d2);
  const double cos = dot(sf.n, l);
  if (cos <= 0) return {};
  const Vec3 e = light.type == Light::Type::spot
                     ? light.intensity * spot_attenuation(light, normalize(sf.p - light.position))
                     : light_intensity(light, -l);
  return sf.m->albedo * (sf.kd / kPi) * e * (cos / d2);
}

// A direction uniformly distributed in solid angle over a sun's disk, the cone of half-angle
// angle/2 around `direction`: 1 − cos θ = r²·(1 − cos θ_max) with (r, φ) from the concentric map,
// which keeps the strata compact.
inline Vec3 sample_sun(const Light& l, double u, double v) {
  const auto [dx, dy] = concentric_disk(u, v);
  const double r2 = dx * dx + dy * dy;
  if (r2 == 0) return l.direction;
  const double half = 0.5 * l.angle_deg * kPi / 180;
  const double one_minus_cos = r2 * 2 * std::pow(std::sin(half / 2), 2);
  const double sin_t = std::sqrt(std::max(0.0, one_minus_cos * (2 - one_minus_cos)));
  Vec3 t, b;
  basis(l.direction, t, b);
  return normalize(l.direction * (1 - one_minus_cos) + (t * dx + b * dy) * (sin_t / std::sqrt(r2)));
}

// One light sample of the references: its direct light (area_direct; a sun: sun_direct along a
// direction over its disk) and the point or direction its visibility is traced to.
struct LightSample {
  Vec3 direct, q, dir;
  bool distant = false;
};

inline LightSample sample_light_direct(const Light& l, const Surface& sf, double u, double v) {
  LightSample ls;
  if (l.type == Light::Type::sun) {
    ls.distant = true;
    ls.dir = sample_sun(l, u, v);
    ls.direct = sun_direct(l, sf, ls.dir);
    return ls;
  }
  ls.q = sample_light(l, sf.p, u, v);
  ls.direct = area_direct(l, sf, ls.q);
  return ls;
}

inline bool visible(const Scene& s, const Surface& sf, const LightSample& ls) {
  return ls.distant ? !occluded_along(s, sf.p, sf.n, sf.prim, ls.dir)
                    : !occluded(s, sf.p, sf.n, sf.prim, ls.q);
}

// ---- GGX (alpha = roughness²), visible-normal sampling (Heitz 2018) ----

inline double smith_lambda(double alpha, double cos) {
  if (cos >= 1) return 0;
  const double tan2 = std::max(0.0, 1 - cos * cos) / (cos * cos);
  return 0.5 * (-1 + std::sqrt(1 + alpha * alpha * tan2));
}

// Samples wi for the lobe around n seen from wo; returns the weight G2/G1(wo) of the
// estimator f·cos/pdf up to the constant Fresnel (0 below the surface).
inline double sample_ggx(Vec3 n, Vec3 wo, double alpha, double u1, double u2, Vec3& wi) {
  Vec3 t, b;
  basis(n, t, b);
  const Vec3 wl{dot(wo, t), dot(wo, b), dot(wo, n)};
  const Vec3 vh = normalize(Vec3{alpha * wl.x, alpha * wl.y, wl.z});
  const double lensq = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = lensq > 0 ? Vec3{-vh.y, vh.x, 0} / std::sqrt(lensq) : Vec3{1, 0, 0};
  const Vec3 t2 = cross(vh, t1);
  const double r = std::sqrt(u1), phi = 2 * kPi * u2;
  const double p1 = r * std::cos(phi);
  double p2 = r * std::sin(phi);
  const double sh = 0.5 * (1 + vh.z);
  p2 = (1 - sh) * std::sqrt(std::max(0.0, 1 - p1 * p1)) + sh * p2;
  const Vec3 nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0, 1 - p1 * p1 - p2 * p2));
  const Vec3 ne = normalize(Vec3{alpha * nh.x, alpha * nh.y, std::max(1e-12, nh.z)});
  const Vec3 m = t * ne.x + b * ne.y + n * ne.z;
  wi = reflect(-wo, m);
  const double cos_i = dot(wi, n);
  if (cos_i <= 0) return 0;
  const double lo = smith_lambda(alpha, std::clamp(wl.z, 1e-12, 1.0));
  const double li = smith_lambda(alpha, std::min(1.0, cos_i));
  return (1 + lo) / (1 + lo + li);  // G2(wo, wi) / G1(wo), height-correlated Smith
}

}  // namespace isg::synth::detail
