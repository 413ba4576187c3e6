// Method settings of the soft shadows, resolved from the light, the camera and the preset, and
// the shadow map read in the load stage (no GPU here: the planner's side).
#include "effects/shadows/settings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "effects/composite/effect.h"
#include "effects/sampling.h"
#include "effects/shadows/params.h"
#include "effects/view.h"
#include "io/image.h"
#include "shadows_isg_io.h"

namespace isg::effects {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr int kTile = SHADOWS_ISG_TILE;
// shadows.method=auto takes isg where the light stands under this many degrees above most lit
// receivers (issue 19): own Cycles `grazing` (8 degrees) isg 0.38 of doing nothing's error
// against pcss 0.44; `lowlight` and the shared cases (higher) pcss 0.23-0.39 against isg 0.20-0.52.
constexpr double kAutoGrazingDegrees = 14.0;
// shadows.method=auto takes isg where the penumbrae span fewer than this many map texels (their
// radius eq. 8 gives from L.occluder at the shadowed receivers, median; issue 52): within
// shadows.input_edges (2 texels) the input's hard edge stands, and a little beyond pcss still
// adds little. Penumbra radius in texels and RMSE over doing nothing's, pcss against isg:
// isg-synth `sun` (its 20 m map) at 480x270, 1024² 1.5, 0.95 against 0.36 (at 320x180 also 1.5:
// 0.95 against 0.55); own Cycles `sun` (12.75 m map, 1024²) 2.3, 0.64 against 0.40; isg-synth
// `sun` with a 4096² map 6.0, 0.26 against 0.36; isg-synth contact 1e6 m from the origin, P
// refitted (tests/gpu/test_vssm.cpp, 192x108, 512² map) 3.8, RMSE 0.0172 against 0.0287; shared
// contact 7.6, 0.21 against 0.35; shared rowdepth 11.9 (pcss). The cut lies between 2.3 and 3.8.
constexpr double kAutoPenumbraTexels = 3.0;
}  // namespace

// A sun, for method isg (eq. 5 and 8 take a light's centre and radius): a sphere light this many
// times the larger of the scene radius and the camera's focus distance (how far the set is) from
// the camera along its direction, of the radius that subtends the sun's angle. Eq. 8's penumbra
// L·d/(D − d) is then tan(angle/2)·d within d/D (≤ 2e-4 for occluders within two scene radii of
// the receiver), and the rays to it from points of the set part by at most 2e-4 rad (2 scene
// radii or the camera's distance apart), under a tenth of a 0.5° sun's half angle; in float32
// the centre (camera-relative) keeps 6e-8 of D.
constexpr double kSunDistance = 1e4;

double light_size(const io::Light& light) {
  switch (light.type) {
    case io::LightType::sphere:
    case io::LightType::disk:
    case io::LightType::spot: return light.radius;  // a spot's shadow is its disk's (contract)
    case io::LightType::rect: {
      const double a = 0.5 * light.size[0], b = 0.5 * light.size[1];
      return std::sqrt(4.0 * a * b / kPi);
    }
    case io::LightType::point: return 0.0;
    case io::LightType::sun: return std::tan(light.angle_deg * kPi / 360.0);
  }
  return 0.0;
}

std::array<double, 3> light_centre_for(const io::Light& light, const std::array<double, 3>& eye,
                                       double scale, double* radius) {
  if (!light.distant()) {
    if (radius) *radius = light_size(light);
    return light.position;
  }
  const double D = kSunDistance * std::max(scale, 1e-6);
  if (radius) *radius = D * light_size(light);
  return {eye[0] + D * light.direction[0], eye[1] + D * light.direction[1], eye[2] + D * light.direction[2]};
}

std::string shadows_isg_unsupported(const io::Light* light) {
  if (!light) return "no scene entry for the light: isg needs its position and size";
  if (light->type == io::LightType::point) return "point light: hard shadows are already right";
  if (!(light_size(*light) > 0.0)) return "light of size 0: hard shadows are already right";
  return "";
}

ShadowSettings shadow_settings(const io::Light& light, const io::Camera& cam, double scene_radius,
                               const params::Params& p, int height) {
  ShadowSettings s;
  s.grid_search = grid_of(p.get(shadow_keys::search_samples));
  s.grid_gather = grid_of(p.get(shadow_keys::gather_samples));
  s.sigma = p.get(shadow_keys::sigma);
  s.scene_radius = scene_radius > 0 ? scene_radius : 1.0;
  s.max_radius = p.get(shadow_keys::max_radius);
  s.rotate = p.get(shadow_keys::rotate);
  s.search_reach = p.get(shadow_keys::search_reach);
  s.tile_skip = p.get(shadow_keys::tile_skip);
  const auto v = PinholeView::of(cam, height);
  s.light = light_centre_for(light, v.eye, std::max(s.scene_radius, cam.focus_distance), &s.light_size);
  s.oriented = light.type == io::LightType::disk || light.type == io::LightType::rect ||
               light.type == io::LightType::spot;
  const double nl = std::sqrt(light.normal[0] * light.normal[0] + light.normal[1] * light.normal[1] +
                              light.normal[2] * light.normal[2]);
  if (nl > 0) s.light_normal = {light.normal[0] / nl, light.normal[1] / nl, light.normal[2] / nl};
  s.f_px = v.f_px;
  s.eye = v.eye;
  s.rot = v.rot;
  return s;
}

uint32_t shadows_isg_tiles(uint32_t w, uint32_t h) {
  return ((w + kTile - 1) / kTile) * ((h + kTile - 1) / kTile);
}

uint32_t shadows_isg_tiles_words(uint32_t w, uint32_t h) {
  return SHADOWS_ISG_TILES_WORDS(shadows_isg_tiles(w, h));
}

std::string shadowmap_unsupported(const io::Light* light, const std::string& name) {
  if (!light) return "light " + name + " is not in the scene file";
  if (!light->shadowmap) return "no shadowmap in the scene file for light " + name;
  if (light->type == io::LightType::point) return "point light: hard shadows are already right";
  return "";
}

ShadowmapSettings shadowmap_settings(const io::Light& light, const io::Camera* cam,
                                     double scene_radius, const params::Params& p,
                                     const std::string& method, int height) {
  ShadowmapSettings s;
  s.method = method;
  s.file = light.shadowmap->file;
  s.world_to_light = light.shadowmap->world_to_light;
  s.yfov_deg = light.shadowmap->yfov_deg;
  s.ortho = light.shadowmap->orthographic();
  s.width_m = light.shadowmap->width_m;
  s.height_m = light.shadowmap->height_m;
  s.far_clip = light.shadowmap->far_clip;
  s.light_radius = light_size(light);
  s.facing = light.type == io::LightType::sphere;
  s.taps = int(p.get(shadow_keys::pcss_taps));
  s.pcss_narrow = int(p.get(shadow_keys::pcss_narrow));
  s.pattern = p.get(shadow_keys::pcss_pattern);
  s.reach = p.get(shadow_keys::reach);
  s.input_edges = p.get(shadow_keys::input_edges);
  s.rotate = p.get(shadow_keys::rotate);
  s.bias = p.get(shadow_keys::bias);
  s.slope_max = p.get(shadow_keys::slope_max);
  s.spread_bias = p.get(shadow_keys::spread_bias);
  s.depth_ulps = p.get(shadow_keys::depth_ulps);
  s.max_radius = p.get(shadow_keys::smap_max_radius);
  s.scene_radius = scene_radius;
  s.vssm_m = int(p.get(shadow_keys::vssm_m));
  s.vssm_m_wide = int(p.get(shadow_keys::vssm_m_wide));
  s.vssm_h = int(p.get(shadow_keys::vssm_h));
  s.vssm_leaf_taps = int(p.get(shadow_keys::vssm_leaf_taps));
  s.vssm_flat = p.get(shadow_keys::vssm_flat);
  s.vssm_contact = p.get(shadow_keys::vssm_contact);
  s.vssm_narrow = int(p.get(shadow_keys::vssm_narrow));
  s.cssm_order = int(p.get(shadow_keys::cssm_order));
  s.cssm_filter = p.get(shadow_keys::cssm_filter);
  s.cssm_max_basis = int(p.get(shadow_keys::cssm_max_basis));
  s.cssm_split = int(p.get(shadow_keys::cssm_split));
  s.cssm_narrow = int(p.get(shadow_keys::cssm_narrow));
  s.cssm_a = p.get(shadow_keys::cssm_sharpen_a);
  s.cssm_b = p.get(shadow_keys::cssm_sharpen_b);
  s.has_camera = cam != nullptr;
  if (cam) {
    const auto v = PinholeView::of(*cam, height);
    s.f_px = v.f_px;
    s.eye = v.eye;
    s.rot = v.rot;
  }
  return s;
}

namespace {
// ShadowmapData::noise: second differences of 1/z (linear on a plane under the map's
// perspective; of z under a sun's orthographic map) at texels whose two neighbours along the axis are surfaces too and where the
// depth changes (a plane rounded to float32 steps is flat between the steps: counting the flat
// texels would hide the steps of a surface whose depth changes slowly), not at silhouettes
// (a jump of over SILHOUETTE of the depth: 0.2 m at 4 m, where a float32 step 1e6 m from the
// origin is 62.5 mm; a sun's orthographic map, whose depth is measured from wherever its camera
// stands, a jump of over ORTHO_SILHOUETTE texels: steeper than 63° from its axis).
double depth_noise(const ShadowmapData& d, double ortho_texel) {
  const bool ortho = ortho_texel > 0.0;
  // A map over 1024² texels is measured on every step-th row and column (at most 2^20 texels, two
  // differences each: 16 MiB here rather than 268 MiB for a 4096² map).
  const int step = int(std::ceil(std::sqrt(double(d.width) * double(d.height) / double(1 << 20))));
  std::vector<double> r;
  const auto at = [&](int x, int y) { return double(d.z[size_t(y) * size_t(d.width) + size_t(x)]); };
  const auto surface = [](double z) { return z > 0.0 && z < ISG_BACKGROUND_DEPTH; };
  for (int y = 0; y < d.height; y += step)
    for (int x = 0; x < d.width; x += step) {
      const double z = at(x, y);
      if (!surface(z)) continue;
      for (int axis = 0; axis < 2; ++axis) {
        const int ax = axis == 0 ? 1 : 0, ay = 1 - ax;
        if (x - ax < 0 || y - ay < 0 || x + ax >= d.width || y + ay >= d.height) continue;
        const double a = at(x - ax, y - ay), b = at(x + ax, y + ay);
        constexpr double SILHOUETTE = 0.05, ORTHO_SILHOUETTE = 2.0;
        if (!surface(a) || !surface(b) || (a == z && b == z)) continue;
        if (std::max(std::abs(a - z), std::abs(b - z)) > (ortho ? ORTHO_SILHOUETTE * ortho_texel : SILHOUETTE * z)) continue;
        // A sun's orthographic map: z itself is linear on a plane.
        r.push_back((ortho ? std::abs(a - 2.0 * z + b) : std::abs(1.0 / a - 2.0 / z + 1.0 / b) * z * z) / std::sqrt(6.0));
      }
    }
  if (r.empty()) return 0.0;
  const auto k = r.begin() + std::ptrdiff_t(0.9 * double(r.size() - 1));
  std::nth_element(r.begin(), k, r.end());
  return *k;
}
}  // namespace

ShadowmapData make_shadowmap(int width, int height, std::vector<float> z, double ortho_texel) {
  ShadowmapData d;
  d.width = width;
  d.height = height;
  d.z = std::move(z);
  for (float v : d.z)
    if (v > 0.0f && v < ISG_BACKGROUND_DEPTH) d.min_depth = std::min(d.min_depth, double(v));
  d.noise = depth_noise(d, ortho_texel);
  return d;
}

ShadowmapData load_shadowmap(const ShadowmapSettings& s) {
  io::Image img = io::read_exr(s.file);
  io::Channel* zc = img.find("Z");
  if (!zc) throw io::IoError(s.file.string() + ": shadow map has no channel Z");
  auto& z = zc->data;
  const int W = img.width, H = img.height;
  const float background = float(10.0 * ISG_BACKGROUND_DEPTH);  // a renderer's background
  std::vector<size_t> bad;
  for (size_t i = 0; i < z.size(); ++i) {
    if (!std::isfinite(z[i])) bad.push_back(i);
    else if (z[i] > s.far_clip) z[i] = background;
  }
  // NaN/Inf texels take the farthest depth among their finite 8-neighbours, ring by ring inwards
  // for blocks of them: a plausible surface, where background would be a hole in a receiver that
  // the variance methods see as light bleeding through it (and a NaN would poison every sum of a
  // summed-area table). The farthest rather than the nearest, so a repair never adds a blocker.
  const uint64_t nonfinite = bad.size();
  while (!bad.empty()) {
    std::vector<std::pair<size_t, float>> fill;
    std::vector<size_t> left;
    for (size_t i : bad) {
      const int x = int(i % size_t(W)), y = int(i / size_t(W));
      float best = -1.0f;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int u = x + dx, v = y + dy;
          if ((dx || dy) && u >= 0 && v >= 0 && u < W && v < H) {
            const float n = z[size_t(v) * size_t(W) + size_t(u)];
            if (std::isfinite(n)) best = std::max(best, n);
          }
        }
      if (best >= 0.0f) fill.push_back({i, best});
      else left.push_back(i);
    }
    if (fill.empty()) {  // nothing finite reaches them: no surface at all
      for (size_t i : left) z[i] = background;
      break;
    }
    for (const auto& [i, v] : fill) z[i] = v;
    bad = std::move(left);
  }
  auto map = make_shadowmap(W, H, std::move(z), s.ortho ? s.height_m / double(std::max(H, 1)) : 0.0);
  map.nonfinite = nonfinite;
  return map;
}

ShadowAuto choose_shadow_method(const io::Image& img, const io::Roles& roles, const io::Light* light,
                                const std::string& name, const io::Camera* cam) {
  char b[320];
  if (const std::string why = shadowmap_unsupported(light, name); !why.empty()) return {"isg", why};
  if (!roles.has("position") && !(roles.has("depth") && cam)) return {"isg", "no positions for the shadow map"};
  // isg turns world radii into pixels through the camera; pcss needs only P and the map.
  if (!cam) return {"pcss", "no camera, which isg needs: the shadow map's pcss"};
  const io::ShadowMap& sm = *light->shadowmap;
  const PinholeView view = PinholeView::of(*cam, img.height);
  const std::array<double, 3> L = light->position;  // a sun: its direction, below
  // Far from the origin: the float32 step of positions there against a shadow-map texel at the
  // camera's distance from the light. Past a texel the map can no longer place the receiver
  // within its own texel and isg, which works from camera-relative depth, does better; under it
  // pcss still does, its narrow edges taken from the input (shadows.input_edges). Own Cycles
  // renders of contact (texel 0.0114 m; ratio to doing nothing, pcss against isg): 1e5 m from the
  // origin, a step of 0.69 texel, 0.26 against 0.39; 1e6 m, 5.5 texels, 0.82 against 0.62.
  double mag = light->distant() ? 0.0 : std::max({std::abs(L[0]), std::abs(L[1]), std::abs(L[2])});
  for (int k = 0; k < 3; ++k) mag = std::max(mag, std::abs(view.eye[size_t(k)]));
  const double dist = std::hypot(L[0] - view.eye[0], L[1] - view.eye[1], L[2] - view.eye[2]);
  // A texel at the camera's distance from the light (a sun's orthographic map: everywhere).
  const double texel = sm.orthographic() ? sm.height_m / double(std::max(sm.height, 1))
                                         : std::max(dist, 1e-6) * 2.0 * std::tan(sm.yfov_deg * kPi / 360.0) / double(std::max(sm.height, 1));
  const double step = float32_step(mag);
  // Positions refitted (input.positions, lib/run/positions.h) place receivers within a fraction
  // of the step: the contact case 1e6 m away, pcss 0.23 against isg 0.35 from P (the same at
  // the origin).
  const io::RoleBinding* depth = roles.get("depth");
  const bool refitted = !roles.has("position") && depth && depth->terms.size() == 1 &&
                        depth->terms[0].size() == 1 && depth->terms[0][0] == kRefitChannel;
  if (step > texel && !refitted) {
    std::snprintf(b, sizeof b, "the scene lies %.3g m from the world origin: float32 positions step by %.3g m there, more than a shadow-map texel (%.3g m)", mag, step, texel);
    return {"isg", b};
  }
  // The light's angle above the lit receivers: from N where the input has it, else from P's
  // screen derivatives; every stride-th pixel in both directions, at most ~65k of them.
  const int W = img.width, H = img.height;
  const size_t n = size_t(W) * size_t(H);
  const io::RoleBinding* pb = roles.get("position");
  const io::RoleBinding* db = roles.get("depth");
  const io::RoleBinding* nb = roles.get("normal");
  const std::vector<float> P = pb ? io::gather_role(img, *pb, 3) : std::vector<float>{};
  const std::vector<float> Z = db ? io::gather_role(img, *db, 1) : std::vector<float>{};
  const std::vector<float> N = nb ? io::gather_role(img, *nb, 3) : std::vector<float>{};
  const std::vector<float> mask = foreground_of(img, roles);
  auto fg = [&](size_t i) { return mask[i] != 0.0f; };
  using V3 = std::array<double, 3>;
  auto pos = [&](size_t i) -> V3 {
    if (!P.empty()) return {P[i], P[n + i], P[2 * n + i]};
    return view.world(i, Z[i], W, H);
  };
  const int stride = std::max(1, int(std::sqrt(double(n) / 65536.0)));
  std::vector<double> elev, penumbra;
  // A shadowed receiver's penumbra radius (eq. 8 from its L.occluder d; a sun: tan(angle/2)·d)
  // over the map's texel there (planar depth along the map's axis; a sun's map: its texel).
  const io::RoleBinding* ob = roles.get(name + ".occluder");
  const std::vector<float> occ = ob ? io::gather_role(img, *ob, 1) : std::vector<float>{};
  const auto& ml = sm.world_to_light;
  const double tan_y = std::tan(sm.yfov_deg * kPi / 360.0), size = light_size(*light);
  auto penumbra_texels = [&](const V3& P0, double d) {
    const double zl = -(ml[8] * P0[0] + ml[9] * P0[1] + ml[10] * P0[2] + ml[11]);
    const double tx = sm.orthographic() ? sm.height_m / double(std::max(sm.height, 1))
                                        : std::max(zl, 0.0) * 2.0 * tan_y / double(std::max(sm.height, 1));
    const double D = std::hypot(L[0] - P0[0], L[1] - P0[1], L[2] - P0[2]);
    const double rs = light->distant() ? size * d : size * d / std::max(D - d, 1e-6 * D);
    return rs / std::max(tx, 1e-30);
  };
  for (int y = 0; y + 1 < H; y += stride)
    for (int x = 0; x + 1 < W; x += stride) {
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      if (!fg(i)) continue;
      const V3 P0 = pos(i);
      if (!occ.empty() && occ[i] > 0.0f && std::isfinite(occ[i])) penumbra.push_back(penumbra_texels(P0, occ[i]));
      V3 nn;
      if (!N.empty()) {
        nn = {N[i], N[n + i], N[2 * n + i]};
      } else {
        if (!fg(i + 1) || !fg(i + size_t(W))) continue;
        const V3 a = pos(i + 1), c = pos(i + size_t(W));
        const V3 u = {a[0] - P0[0], a[1] - P0[1], a[2] - P0[2]}, v = {c[0] - P0[0], c[1] - P0[1], c[2] - P0[2]};
        nn = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        // Facing the camera (screen derivatives give either orientation).
        if (nn[0] * (view.eye[0] - P0[0]) + nn[1] * (view.eye[1] - P0[1]) + nn[2] * (view.eye[2] - P0[2]) < 0.0)
          nn = {-nn[0], -nn[1], -nn[2]};
      }
      const double ln = std::hypot(nn[0], nn[1], nn[2]);
      const V3 wl = light->distant() ? light->direction : V3{L[0] - P0[0], L[1] - P0[1], L[2] - P0[2]};
      const double lw = std::hypot(wl[0], wl[1], wl[2]);
      if (!(ln > 0.0) || !(lw > 0.0)) continue;
      const double c = (nn[0] * wl[0] + nn[1] * wl[1] + nn[2] * wl[2]) / (ln * lw);
      if (c > 0.0) elev.push_back(std::asin(std::min(c, 1.0)) * 180.0 / kPi);  // lit side only
    }
  if (elev.empty()) return {"isg", "no receivers facing the light"};
  const auto mid = elev.begin() + std::ptrdiff_t(elev.size() / 2);
  std::nth_element(elev.begin(), mid, elev.end());
  if (*mid < kAutoGrazingDegrees) {
    std::snprintf(b, sizeof b, "the light grazes most receivers: %.1f degrees above them (median), under %.1f", *mid, kAutoGrazingDegrees);
    return {"isg", b};
  }
  char pen[96] = "";
  if (!penumbra.empty()) {
    const auto pmid = penumbra.begin() + std::ptrdiff_t(penumbra.size() / 2);
    std::nth_element(penumbra.begin(), pmid, penumbra.end());
    if (*pmid < kAutoPenumbraTexels) {
      std::snprintf(b, sizeof b, "the shadow map is too coarse for these penumbrae: their radius spans %.2f of its texels (median over the shadowed receivers), under %.1f", *pmid, kAutoPenumbraTexels);
      return {"isg", b};
    }
    std::snprintf(pen, sizeof pen, ", penumbrae %.1f map texels wide (radius, median)", *pmid);
  }
  std::snprintf(b, sizeof b, "the light stands %.1f degrees above most receivers (median; grazing under %.1f), %.3g m from the world origin%s: the shadow map's pcss", *mid, kAutoGrazingDegrees, mag, pen);
  return {"pcss", b};
}

}  // namespace isg::effects
