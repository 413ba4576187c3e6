// Soft shadows, one instance per light: the parameter table, what the inputs allow, the plan
// (method isg, the shadow-map methods, or the input's hard shadow kept), the load stage (the
// light's shadow map) and the statistics in words. No Vulkan (recorder.cpp records the passes).
#include <algorithm>
#include <cstdio>

#include "effects/composite/effect.h"
#include "effects/shadows/instance.h"
#include "effects/shadows/params.h"
#include "effects/shadows/settings.h"
#include "io/image.h"
#include "shadows_isg_io.h"

namespace isg::effects {

namespace {

std::string missing_of(const io::Roles& roles, const std::vector<std::string>& need) {
  std::string m;
  for (const auto& r : need)
    if (!roles.has(r)) m += (m.empty() ? "" : ", ") + r;
  return m;
}

std::string percent(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3f", x * 100.0);
  return b;
}

class Shadows final : public Effect {
 public:
  const char* name() const override { return "shadows"; }

  std::vector<params::Def> params() const override {
    return {
      params::def(shadow_keys::method, "isg", {"none", "hard", "isg", "pcss", "vssm", "cssm", "auto"},
       "soft-shadow method for every light with L.shadow and L.direct: isg (the paper's "
       "parameter search and gather, eq. 4-9; needs P or Z, the camera, the light's scene entry "
       "and L.occluder, which the light's shadow map provides where the input has none), hard (keep the input's hard shadow), pcss (percentage-closer "
       "soft shadows from the light's shadow map, thesis §2.4.2), vssm (variance soft shadow "
       "maps, thesis ch. 7), cssm (convolution soft shadow maps, thesis ch. 5); the shadow-map "
       "methods need P, or Z and the camera, and the light's shadowmap in the scene file; auto "
       "(per light, from the frame's pixels: pcss where the light stands above most receivers "
       "near the world origin and its penumbrae span 3 map texels or more, else isg; "
       "the choice and why are printed). isg and pcss weigh each "
       "point of the light by the irradiance it gives the receiver, as a renderer's soft shadow does "
       "(under a low light its top outweighs its bottom); vssm and cssm filter the map uniformly"),
      params::def(shadow_keys::search_samples, "25", 1, 1024,
       "parameter-search samples per pixel, rounded to a square grid through the concentric "
       "disk map (rotated per pixel)"),
      params::def(shadow_keys::gather_samples, "49", 1, 1024,
       "gather samples per pixel, rounded to a square grid (as search_samples)"),
      params::def(shadow_keys::sigma, "0.01", 1e-9, 1e6,
       "eq. 6: σ of the gaussian range function (l measured in units of the scene's "
       "scene_radius)"),
      params::def(shadow_keys::max_radius, "64", 0.5, 1024,
       "largest search and gather radius; pixels that need more are clamped and counted "
       "(--timings)", "pixels"),
      params::def(shadow_keys::rotate, "true",
       "rotate the sample grid per pixel (a hash of the pixel, the same every frame)"),
      params::def(shadow_keys::search_reach, "true",
       "the parameter search counts only occluders within the pixel's cone to the light, "
       "each at its distance from the pixel (PCSS's blocker test, in image space)"),
      params::def(shadow_keys::tile_skip, "true",
       "16x16 tiles with no shadow boundary within the search radius keep L.shadow (fully lit "
       "or umbra)"),
      // Shadow-map methods (lib/effects/shadowmaps/shadowmap.h).
      params::def(shadow_keys::pcss_taps, "32", 1, 1024,
       "pcss: blocker-search and PCF taps per pixel (stratified: rounded to a square grid)"),
      params::def(shadow_keys::pcss_pattern, "stratified", {"stratified", "poisson"},
       "pcss: tap pattern in the disk, rotated per pixel when shadows.rotate is on"),
      params::def(shadow_keys::pcss_narrow, "1", 0, 4,
       "pcss: passes that search for blockers again, with the same taps, over the disk of the "
       "light's cone at the mean blocker depth found so far (x1.5), while it shrinks: blockers "
       "outside it cannot shadow the receiver, yet they moved the mean (the first search is "
       "sized for the nearest depth in the map); 0: the thesis's single search; each pass "
       "costs the search's taps again"),
      params::def(shadow_keys::reach, "2", 0, 1e3,
       "pcss, vssm: a filter tap's texel in front of the receiver plane shadows the pixel only "
       "within this many times the reach of the light's cone from the pixel at the texel's depth "
       "(plus 1.5 texels): a floor in front of a ramp lit at grazing no longer darkens it; 0: "
       "every such texel, as the thesis (PCSS §2.4.2, VSSM's PCF §7.4.2)"),
      params::def(shadow_keys::input_edges, "2", 0, 1e3,
       "pcss, vssm, cssm: where the penumbra's radius is within this many shadow-map texels the "
       "input's ray-traced L.shadow stands (a map texel places an edge only to within itself); "
       "beyond, it weighs (this / radius)^2 against the filtered map; for cssm at least the radius "
       "a blocker casts from x0/s_z of the map's depth range in front of the receiver, where its "
       "expansion's step crosses 1/2 (nearer blockers it shadows by less than half); 0: the map "
       "alone", "texels"),
      params::def(shadow_keys::bias, "2", 0, 100,
       "shadow-map methods: constant depth bias, in shadow-map texel footprints at the "
       "receiver, on top of the receiver-plane depth (fitted from the screen neighbours)",
       "texels"),
      params::def(shadow_keys::slope_max, "16", 0, 1e3,
       "shadow-map methods: the receiver-plane depth may differ from the receiver's by at "
       "most this many texel footprints per texel of lateral offset (grazing-angle clamp); where "
       "the screen neighbours show a smooth receiver, the plane is trusted up to 64 (89 degrees "
       "from the normal)"),
      params::def(shadow_keys::spread_bias, "2", 0, 100,
       "shadow-map methods: extra depth bias, times the smallest light-depth step from the "
       "pixel to a screen neighbour (large where P blends two surfaces at a silhouette)"),
      params::def(shadow_keys::depth_ulps, "1", 0, 1e3,
       "shadow-map methods: the receiver's input precision, added to its depth uncertainty "
       "(times shadows.spread_bias) with the map's own (measured from its depths): this many "
       "float32 steps of P at its distance from the world origin (6 cm a step at 1e6 m), or of "
       "Z", "steps"),
      params::def(shadow_keys::smap_max_radius, "64", 0.5, 1024,
       "shadow-map methods: largest blocker-search and filter radius; pixels that need more "
       "are clamped and counted (--timings)", "texels"),
      params::def(shadow_keys::vssm_m, "5", 1, 16,
       "vssm: the blocker search's kernel is split into m x m sub-kernels (thesis §7.4.2; the "
       "first search's is shadows.vssm_m_wide where narrowed ones follow); 1: no subdivision"),
      params::def(shadow_keys::vssm_m_wide, "3", 1, 16,
       "vssm: where narrowed searches follow (shadows.vssm_narrow), the first search, over "
       "PCSS's whole region, is split into this many sub-kernels a side, not m: it only has to "
       "find blockers and a first mean depth for the narrowed ones, and it runs for every pixel "
       "the HSM leaves (3 against 5: every case's error within 1 %, the 1080p pass 1.8x faster)"),
      params::def(shadow_keys::vssm_h, "2", 0, 5,
       "vssm: height of the quad-tree the filter kernel is subdivided by where it is not "
       "planar (Algorithm 3); 0: no subdivision"),
      params::def(shadow_keys::vssm_leaf_taps, "4", 0, 64,
       "vssm: PCF taps (a square grid) in each non-planar leaf sub-kernel; 0: such leaves are "
       "taken as lit, as plain variance shadow maps do"),
      params::def(shadow_keys::vssm_flat, "0.0001", 0, 1,
       "vssm: a sub-kernel whose mean depth is behind the receiver and whose variance is below "
       "this times scene_radius is fully lit (thesis §7.5.5)"),
      params::def(shadow_keys::vssm_contact, "0.01", 0, 1,
       "vssm: where the receiver is closer than this times scene_radius behind the mean "
       "blocker, the shadow is a 3x3 PCF (contact shadows, thesis §7.5.4)"),
      params::def(shadow_keys::vssm_narrow, "2", 0, 4,
       "vssm: passes that search for blockers again over the box of the light's cone at the "
       "mean blocker depth found so far, while it shrinks: blockers outside it cannot shadow "
       "the receiver, yet they moved the mean (the first search is PCSS's region, sized for the "
       "nearest possible blocker); 0: the thesis's single search; each pass costs a search"),
      params::def(shadow_keys::cssm_order, "8", 1, 16,
       "cssm: Fourier terms M of the shadow test's expansion (eq. 5.10); 4, 8 and 16 are "
       "the thesis's settings (8: the best error on the shared contact case, 4M + 1 basis "
       "images)"),
      params::def(shadow_keys::cssm_filter, "sat", {"sat", "mipmap"},
       "cssm: prefiltering of the basis images, summed-area tables (32-bit integers, boxes "
       "snapped to whole texels) or mipmaps (§5.3.1)"),
      params::def(shadow_keys::cssm_max_basis, "1024", 64, 16384,
       "cssm: largest side of the basis images, texels; a larger map is box-averaged 2x2 "
       "(exactly, the basis being linear in its texels) until it fits, and further where the "
       "device's storage-buffer range cannot hold 4M + 1 images (kernels narrower than the "
       "averaged texel lose their detail)"),
      params::def(shadow_keys::cssm_split, "4", 1, 8,
       "cssm: most sub-kernels a side each lookup is split into where the receiver plane's "
       "depth changes across the kernel by more than the expansion's step shift (a grazing "
       "or sloped receiver): each sub-kernel is tested against the receiver's depth at its "
       "centre, so the receiver does not shadow itself; 1: one receiver depth per pixel, as "
       "the thesis (ch. 5); cost up to split^2 lookups"),
      params::def(shadow_keys::cssm_narrow, "2", 0, 4,
       "cssm: passes that search for blockers again over the box of the light's cone at the "
       "mean blocker depth found so far (x1.7), while it shrinks: blockers outside it cannot "
       "shadow the receiver, yet they moved the mean (the first search is PCSS's region, sized "
       "for the nearest possible blocker); 0: the thesis's single search; each pass costs two "
       "lookups"),
      params::def(shadow_keys::cssm_sharpen_a, "30", 0, 1e3,
       "cssm: A of the sharpening exponent p = 1 + A exp(-B (d - z_avg)) (eq. 5.9); 0: none"),
      params::def(shadow_keys::cssm_sharpen_b, "100", 0, 1e6,
       "cssm: B of eq. 5.9, per unit of normalised depth (the map's depth range is 1)"),
  };
  }

  std::vector<EffectStatus> capabilities(const io::Roles& roles, const io::Scene& scene,
                                         bool) const override {
    std::vector<EffectStatus> out;
    for (const auto& l : roles.lights) {
      EffectStatus st{"shadows[" + l + "]", false, "", ""};
      const io::Light* light = scene.light(l);
      // Without L.shadow, a shadow map gives it (method isg, pass shadows.derive).
      const bool map_usable = light && shadowmap_unsupported(light, l).empty();
      std::vector<std::string> need = {"beauty", l + ".direct"};
      if (!map_usable) need.push_back(l + ".shadow");
      std::string m = missing_of(roles, need);
      if (!m.empty()) st.why = "missing " + m;
      else if (light && light->type == io::LightType::point) st.why = "point light: hard shadows are right";
      else st.runs = true;
      if (st.runs && !roles.has(l + ".shadow"))
        st.why = "L.shadow and L.occluder from the shadow map (method isg only)";
      else if (st.runs && !roles.has(l + ".occluder") && map_usable)
        st.why = "L.occluder from the shadow map for method isg";
      out.push_back(st);
    }
    if (roles.lights.empty()) out.push_back({"shadows", false, "", "no light channels (L.shadow, L.direct)"});
    return out;
  }

  // shadows.method = auto: each light's method from the frame's pixels. A shadow-map method
  // named explicitly where auto would take another runs as asked, with a note saying which and
  // why (issue 19): isg (a grazing light, a scene far from the origin), or pcss where cssm is
  // named (on every Cycles case where auto takes pcss, pcss's error is lower than cssm's:
  // docs/benchmark/shadow_cases.md). Where vssm is named it says nothing: with the narrowed
  // searches vssm's error is lower than pcss's on some of those cases (shared contact 0.20
  // against 0.21 of doing nothing's) and higher on others (own overlap 0.29 against 0.23), at
  // some 20 times pcss's GPU time on lavapipe.
  void choose(const PlanContext& c, const io::Image& img, Choices& out) const override {
    const std::string m = c.p.get(shadow_keys::method);
    const bool map_method = m == "pcss" || m == "vssm" || m == "cssm";
    if (m != "auto" && !map_method) return;
    for (const auto& l : c.roles.lights) {
      const ShadowAuto a = choose_shadow_method(img, c.roles, c.scene.light(l), l, c.camera);
      if (map_method) {
        if (a.method == "isg")
          out["shadows[" + l + "]/note"] = "shadows.method=auto would take isg here: " + a.why;
        else if (a.method == "pcss" && m == "cssm")
          out["shadows[" + l + "]/note"] =
              "shadows.method=auto would take pcss here: " + a.why +
              " (lower error than cssm's on every Cycles case where auto takes it)";
        continue;
      }
      out["shadows[" + l + "]"] = a.method;
      out["shadows[" + l + "]/why"] = a.why;
    }
  }

  void plan(const PlanContext& c, PlanOut& out) const override {
    const auto& roles = c.roles;
    const auto& p = c.p;
    const std::string preset_method = p.get(shadow_keys::method);
    for (const auto& l : roles.lights) {
      // auto: the frame's choice; before the pixels are read (a dry run, the check of the
      // header's channels), isg.
      std::string method = preset_method, auto_why;
      if (method == "auto") {
        const std::string* m = c.choice("shadows[" + l + "]");
        const std::string* why = c.choice("shadows[" + l + "]/why");
        method = m ? *m : "isg";
        auto_why = m && why ? "auto: " + *why : "auto: isg or pcss, chosen when the pixels are read";
      }
      auto inst = make_instance<ShadowsInstance>("shadows", "shadows[" + l + "]");
      inst->light = l;
      EffectStatus st{"shadows[" + l + "]", false, method, ""};
      const io::Light* light = c.scene.light(l);
      std::vector<std::string> absent;
      // Method isg can take L.shadow from the light's shadow map; L.direct it cannot do without.
      const bool map_usable = light && shadowmap_unsupported(light, l).empty();
      for (const std::string& r : {l + ".shadow", l + ".direct"})
        if (!roles.has(r) && !(method == "isg" && map_usable && r == l + ".shadow")) absent.push_back(r);
      if (method == "none") {
        st.why = "shadows.method = none";
      } else if (!absent.empty()) {
        st.why = "missing channels for role";
        for (const auto& a : absent) st.why += " " + a;
      } else if (light && light->type == io::LightType::point) {
        st.why = "point light: hard shadows are already right";
      } else if (method == "isg") {
        // The search and gather need occluder distances, positions, the camera to turn world
        // radii into pixels, and the light's position and size.
        const io::Camera* cam = c.camera;
        std::string why = shadows_isg_unsupported(light);
        if (why.empty() && !roles.has("position") && !roles.has("depth"))
          why = "missing channels for role position (or depth)";
        if (why.empty() && !cam) why = "no camera (scene file, or worldToCamera/worldToNDC in the header)";
        // Without L.occluder (or L.shadow) the shadow map provides them (pass shadows.derive).
        const bool derive = !roles.has(l + ".occluder") || !roles.has(l + ".shadow");
        if (why.empty() && derive && !map_usable)
          why = "missing channels for role " + l + ".occluder (and no usable shadow map: " +
                shadowmap_unsupported(light, l) + ")";
        if (why.empty() && derive)
          inst->derived = shadowmap_settings(*light, cam, c.scene.scene_radius, p, "derive", c.view_h());
        st.runs = true;
        if (why.empty()) {
          inst->isg = shadow_settings(*light, *cam, c.scene.scene_radius, p, c.view_h());
        } else {
          // isg is the default: without what it needs the input's hard shadow is kept (method
          // hard), and the status says why.
          st.method = "hard";
          st.why = "isg cannot run: " + why;
          st.runs = roles.has(l + ".shadow");  // without L.shadow there is nothing to keep
        }
      } else if (method == "pcss" || method == "vssm" || method == "cssm") {
        // The shadow map and the receivers' positions (P, or Z through the camera); no
        // L.occluder.
        const io::Camera* cam = c.camera;
        std::string why = shadowmap_unsupported(light, l);
        if (why.empty() && !roles.has("position") && !roles.has("depth"))
          why = "missing channels for role position (or depth)";
        if (why.empty() && !roles.has("position") && !cam)
          why = "no camera (scene file, or worldToCamera/worldToNDC in the header) to place Z";
        st.why = why;
        st.runs = why.empty();
        if (st.runs) inst->smap = shadowmap_settings(*light, cam, c.scene.scene_radius, p, method, c.view_h());
      } else {
        st.runs = true;
      }
      if (!auto_why.empty() && st.why.empty()) st.why = auto_why;
      const std::string* note = c.choice("shadows[" + l + "]/note");
      if (note && st.runs && st.why.empty()) st.why = "note: " + *note;
      out.status(st);
      if (!st.runs) continue;
      inst->method = st.method;
      if (inst->smap || inst->derived) {
        const auto& sm = light->shadowmap.value();
        inst->map_texels = uint64_t(sm.width) * uint64_t(sm.height);
      }
      const int k = out.add(inst);
      const std::string sh = l + ".shadow", dir = l + ".direct", soft = l + ".softshadow";
      out.need(sh, 1, roles.has(sh));  // else shadows.derive writes it
      out.need(dir, 3, true);
      out.need(soft, 1, false);
      if (inst->isg) {
        const std::string occ = l + ".occluder", geo = c.geo();
        const std::string tiles = l + ".shadow.tiles";
        out.need(geo, c.geo_planes(), true);
        if (inst->derived) {
          // L.occluder (and L.shadow when the input has none) from the map, which the load
          // stage read from its own EXR.
          const std::string smap = l + ".shadowmap";
          std::vector<std::string> writes = {occ};
          if (!roles.has(sh)) {
            out.need(sh, 1, false);
            writes.push_back(sh);
          }
          out.need(occ, 1, false);
          out.buffer(smap, inst->map_texels * 4);
          out.pass("shadows", k, "shadows.derive", "shadows.derive[" + l + "]", {geo, "fg", smap},
                   writes, l);
        }
        out.need(occ, 1, true);
        out.buffer(tiles, uint64_t(shadows_isg_tiles_words(uint32_t(c.width), uint32_t(c.height))) * 4);
        // shadows.isg.tiles packs each pixel's tap data (P − eye, L.shadow) into one texel.
        out.need(l + ".isg.pack", 4, false);
        out.pass("shadows", k, "shadows.isg", "shadows.isg[" + l + "]", {sh, occ, geo, "fg"},
                 {soft, tiles, l + ".isg.pack"}, l);
      } else if (inst->smap) {
        // The map is read from its own EXR by the load stage, not from the input image.
        const std::string geo = c.geo(), smap = l + ".shadowmap";
        out.need(geo, c.geo_planes(), true);
        out.buffer(smap, inst->map_texels * 4);
        out.pass("shadows", k, "shadows." + method, "shadows." + method + "[" + l + "]",
                 {sh, geo, "fg", smap}, {soft}, l);
      } else {
        out.pass("shadows", k, "shadows." + st.method, "shadows." + st.method + "[" + l + "]",
                 {sh}, {soft}, l);
      }
      plan_composite_term(out, k, "composite[" + l + "]", dir, soft, sh, l);
    }
    if (roles.lights.empty())
      out.status({"shadows", false, preset_method, "no light channels (L.shadow) in the input"});
  }

  // The light's shadow map, read once per frame (tiles share it).
  void load(Instance& i, std::set<std::string>& warnings) const override {
    auto& inst = static_cast<ShadowsInstance&>(i);
    const ShadowmapSettings* s = inst.smap ? &*inst.smap : inst.derived ? &*inst.derived : nullptr;
    if (!s || inst.map) return;
    auto map = std::make_shared<ShadowmapData>(load_shadowmap(*s));
    if (map->nonfinite > 0)
      warnings.insert(s->file.string() + ": " + std::to_string(map->nonfinite) +
                      " NaN/Inf depths, each replaced by its farthest finite neighbour");
    if (uint64_t(map->z.size()) != inst.map_texels)
      throw io::IoError(s->file.string() + ": shadow map is " + std::to_string(map->width) + "x" +
                        std::to_string(map->height) + ", not the scene file's size");
    inst.map = std::move(map);
  }

  // Method isg on input occluders: the whole frame's d_max (eq. 8; what pass shadows.isg.tiles
  // finds over the foreground's shadowed pixels), which a tile must start from. Occluders from
  // the shadow map are left out: a tile then bounds its search by its own (apron included) d_max.
  void prepare_tiles(Instance& i, const io::Image& img, const io::Roles& roles) const override {
    auto& inst = static_cast<ShadowsInstance&>(i);
    if (!inst.isg || inst.derived) return;
    const auto* sb = roles.get(inst.light + ".shadow");
    const auto* ob = roles.get(inst.light + ".occluder");
    if (!sb || !ob) return;
    const size_t n = img.pixels();
    const auto fg = foreground_of(img, roles);
    const auto sh = io::gather_role(img, *sb, 1), oc = io::gather_role(img, *ob, 1);
    float dm = 0.0f;
    for (size_t j = 0; j < n; ++j)
      if (fg[j] != 0.0f && sh[j] < 1.0f && oc[j] > 0.0f) dm = std::max(dm, oc[j]);
    inst.frame_dmax = dm;
  }

  void from_frame(Instance& t, const Instance& f) const override {
    auto& tile = static_cast<ShadowsInstance&>(t);
    const auto& frame = static_cast<const ShadowsInstance&>(f);
    tile.map = frame.map;
    if (tile.isg && frame.frame_dmax >= 0) tile.isg->d_max_floor = frame.frame_dmax;
  }

  std::vector<std::string> describe(const Report& r) const override {
    if (r.sums.empty()) return {};
    if (r.sums.front().first == "tiles") {
      return {r.key + ": " + percent(r.get("skipped") / r.get("tiles")) +
              "% of tiles skipped (no shadow boundary within reach; shadows.isg dispatched on " +
              percent(r.get("dispatched") / r.get("tiles")) + "% of them), " +
              std::to_string(uint64_t(r.get("full_pixels"))) + " pixels searched and gathered, " +
              std::to_string(uint64_t(r.get("clamped_pixels"))) +
              " needed a radius over shadows.max_radius (clamped), " +
              std::to_string(uint64_t(r.get("borrowed"))) +
              " took the occluder distance of the quads around theirs (whose search found none)"};
    }
    const double px = r.get("pixels");
    char mib[32];
    std::snprintf(mib, sizeof mib, "%.3f", r.get("gpu_bytes") / 1048576.0);
    return {r.key + ": " + percent(px > 0 ? r.get("skipped") / px : 0.0) + "% of " +
            std::to_string(uint64_t(px)) +
            " pixels in the shadow map skipped the filter (fully lit or umbra), " +
            std::to_string(uint64_t(r.get("clamped"))) + " clamped to shadows.smap_max_radius; " +
            mib + " MiB of the method's own GPU buffers"};
  }
};

}  // namespace

const Effect& shadows_effect() {
  static const Shadows e;
  return e;
}

}  // namespace isg::effects
