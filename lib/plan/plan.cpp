#include "plan/plan.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "effects/shadows/isg.h"
#include "effects/shadows/shadowmap.h"
#include "reflections_isg_io.h"

namespace isg::plan {

const Resource* Plan::resource(const std::string& name) const {
  for (const auto& r : resources)
    if (r.name == name) return &r;
  return nullptr;
}

uint64_t Plan::gpu_bytes() const {
  uint64_t b = 0;
  for (const auto& r : resources) b += r.bytes;
  return b;
}

std::string Plan::describe() const {
  std::ostringstream s;
  s << "plan for " << width << "x" << height << ":\n";
  s << "effects:\n";
  for (const auto& e : effects) {
    s << "  " << e.effect << ": " << (e.runs ? "runs (" + e.method + ")" : "skipped: " + e.why)
      << (e.runs && !e.why.empty() ? "; " + e.why : "") << "\n";
  }
  s << "passes:\n";
  for (const auto& p : passes) {
    s << "  " << p.label << "  reads";
    for (const auto& r : p.reads) s << " " << r;
    s << "  writes";
    for (const auto& w : p.writes) s << " " << w;
    s << "\n";
  }
  s << "GPU resources (" << (gpu_bytes() + (1 << 20) - 1) / (1 << 20) << " MiB):\n";
  for (const auto& r : resources) {
    s << "  " << r.name << ": " << r.planes << " plane" << (r.planes > 1 ? "s" : "") << ", "
      << r.bytes / 1024 << " KiB" << (r.upload ? ", uploaded" : "") << "\n";
  }
  if (!missing.empty()) {
    s << "cannot run: missing";
    for (const auto& m : missing) s << " " << m;
    s << "\n";
  }
  return s.str();
}

namespace {
std::string missing_of(const io::Roles& roles, const std::vector<std::string>& need) {
  std::string m;
  for (const auto& r : need)
    if (!roles.has(r)) m += (m.empty() ? "" : ", ") + r;
  return m;
}
}  // namespace

std::vector<EffectStatus> capabilities(const io::Roles& roles, const io::Scene& scene,
                                       bool has_camera) {
  std::vector<EffectStatus> out;
  for (const auto& l : roles.lights) {
    EffectStatus st{"shadows[" + l + "]", false, "", ""};
    const io::Light* light = scene.light(l);
    // Without L.shadow, a shadow map gives it (method isg, pass shadows.derive).
    const bool map_usable = light && effects::shadowmap_unsupported(light, l).empty();
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
  {
    EffectStatus st{"reflections", false, "", ""};
    std::string m = missing_of(roles, {"beauty", "refl", "refl.weight", "refl.dist", "normal"});
    if (!roles.has("position") && !roles.has("depth")) m += std::string(m.empty() ? "" : ", ") + "position or depth";
    if (!m.empty()) st.why = "missing " + m;
    else if (!has_camera) st.why = "no camera (scene file, or worldToCamera/worldToNDC in the header)";
    else st.runs = true;
    out.push_back(st);
  }
  {
    EffectStatus st{"dof", false, "", ""};
    std::string m = missing_of(roles, {"beauty", "depth"});
    if (!m.empty()) st.why = "missing " + m;
    else if (!has_camera) st.why = "no camera (scene file, or worldToCamera/worldToNDC in the header)";
    else st.runs = true;
    out.push_back(st);
  }
  return out;
}

Plan make_plan(const io::Roles& roles, const io::Scene& scene, const params::Params& p,
               int width, int height, const io::Camera* camera, const effects::Window& window) {
  Plan plan;
  plan.width = width;
  plan.height = height;
  const uint64_t plane_bytes = uint64_t(width) * uint64_t(height) * sizeof(float);
  // The camera's frame: the image, or the plate a tile is cut from.
  const int view_h = window.whole() ? height : window.frame_h;

  auto need = [&](const std::string& name, int planes, bool upload) {
    for (auto& r : plan.resources)
      if (r.name == name) return;
    plan.resources.push_back({name, planes, upload, plane_bytes * uint64_t(planes)});
  };

  if (!roles.has("beauty")) {
    plan.missing.push_back("beauty (R G B [A])");
    return plan;
  }

  // The composite target starts as the beauty; fg marks pixels effects may touch.
  need("composite", 4, true);
  std::vector<std::string> fg_reads = {"composite"};
  if (roles.has("depth")) {
    need("depth", 1, true);
    fg_reads.push_back("depth");
  }
  need("fg", 1, false);
  plan.passes.push_back({"foreground", "foreground", fg_reads, {"fg"}, ""});

  // Soft shadows, one per light.
  const std::string method = p.choice("shadows.method");
  for (const auto& l : roles.lights) {
    EffectStatus st{"shadows[" + l + "]", false, method, ""};
    const io::Light* light = scene.light(l);
    std::vector<std::string> absent;
    // Method isg can take L.shadow from the light's shadow map; L.direct it cannot do without.
    const bool map_usable = light && effects::shadowmap_unsupported(light, l).empty();
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
      const io::Camera* cam = camera ? camera : (scene.camera ? &*scene.camera : nullptr);
      std::string why = effects::shadows_isg_unsupported(light);
      if (why.empty() && !roles.has("position") && !roles.has("depth"))
        why = "missing channels for role position (or depth)";
      if (why.empty() && !cam) why = "no camera (scene file, or worldToCamera/worldToNDC in the header)";
      // Without L.occluder (or L.shadow) the shadow map provides them (pass shadows.derive).
      const bool derive = !roles.has(l + ".occluder") || !roles.has(l + ".shadow");
      if (why.empty() && derive && !map_usable)
        why = "missing channels for role " + l + ".occluder (and no usable shadow map: " +
              effects::shadowmap_unsupported(light, l) + ")";
      if (why.empty() && derive)
        plan.derived[l] = effects::shadowmap_settings(*light, cam, scene.scene_radius, p, "derive", view_h);
      st.runs = true;
      if (why.empty()) {
        plan.shadows[l] = effects::shadow_settings(*light, *cam, scene.scene_radius, p, view_h);
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
      const io::Camera* cam = camera ? camera : (scene.camera ? &*scene.camera : nullptr);
      std::string why = effects::shadowmap_unsupported(light, l);
      if (why.empty() && !roles.has("position") && !roles.has("depth"))
        why = "missing channels for role position (or depth)";
      if (why.empty() && !roles.has("position") && !cam)
        why = "no camera (scene file, or worldToCamera/worldToNDC in the header) to place Z";
      st.why = why;
      st.runs = why.empty();
      if (st.runs) plan.shadowmaps[l] = effects::shadowmap_settings(*light, cam, scene.scene_radius, p, method, view_h);
    } else {
      st.runs = true;
    }
    plan.effects.push_back(st);
    if (!st.runs) continue;
    plan.soft_lights.push_back(l);
    const std::string sh = l + ".shadow", dir = l + ".direct", soft = l + ".softshadow";
    need(sh, 1, roles.has(sh));  // else shadows.derive writes it
    need(dir, 3, true);
    need(soft, 1, false);
    if (plan.shadows.count(l)) {
      const std::string occ = l + ".occluder", geo = roles.has("position") ? "position" : "depth";
      const std::string tiles = l + ".shadow.tiles";
      need(geo, geo == "position" ? 3 : 1, true);
      if (plan.derived.count(l)) {
        // L.occluder (and L.shadow when the input has none) from the map, read by the run
        // from its own EXR.
        const std::string smap = l + ".shadowmap";
        const auto& sm = light->shadowmap.value();
        std::vector<std::string> writes = {occ};
        if (!roles.has(sh)) {
          need(sh, 1, false);
          writes.push_back(sh);
        }
        need(occ, 1, false);
        plan.resources.push_back({smap, 1, false, uint64_t(sm.width) * uint64_t(sm.height) * 4});
        plan.passes.push_back({"shadows.derive", "shadows.derive[" + l + "]", {geo, "fg", smap},
                               writes, l});
      }
      need(occ, 1, true);
      plan.resources.push_back({tiles, 1, false,
                                uint64_t(effects::shadows_isg_tiles_words(uint32_t(width),
                                                                          uint32_t(height))) * 4});
      // shadows.isg.tiles packs each pixel's tap data (P − eye, L.shadow) into one texel.
      need(l + ".isg.pack", 4, false);
      plan.passes.push_back({"shadows.isg", "shadows.isg[" + l + "]", {sh, occ, geo, "fg"},
                             {soft, tiles, l + ".isg.pack"}, l});
    } else if (plan.shadowmaps.count(l)) {
      // The map is read from its own EXR by the run, not from the input image.
      const std::string geo = roles.has("position") ? "position" : "depth", smap = l + ".shadowmap";
      need(geo, geo == "position" ? 3 : 1, true);
      const auto& sm = light->shadowmap.value();
      plan.resources.push_back({smap, 1, false, uint64_t(sm.width) * uint64_t(sm.height) * 4});
      plan.passes.push_back({"shadows." + method, "shadows." + method + "[" + l + "]",
                             {sh, geo, "fg", smap}, {soft}, l});
    } else {
      plan.passes.push_back({"shadows." + st.method, "shadows." + st.method + "[" + l + "]", {sh},
                             {soft}, l});
    }
    plan.passes.push_back({"composite_term", "composite[" + l + "]",
                           {"composite", dir, soft, sh, "fg"}, {"composite"}, l});
  }
  if (roles.lights.empty()) {
    plan.effects.push_back({"shadows", false, method, "no light channels (L.shadow) in the input"});
  }

  // Reflections and depth of field: slots for their issues.
  {
    EffectStatus st{"reflections", false, p.choice("reflections.method"), ""};
    const io::Camera* cam = camera ? camera : (scene.camera ? &*scene.camera : nullptr);
    std::string absent = missing_of(roles, {"refl", "refl.dist", "refl.weight", "normal"});
    if (!roles.has("position") && !roles.has("depth"))
      absent += std::string(absent.empty() ? "" : " ") + "position (or depth)";
    if (st.method == "none") st.why = "reflections.method = none";
    else if (!absent.empty()) st.why = "missing channels for role " + absent;
    else if (!cam) st.why = "no camera (scene file, or worldToCamera/worldToNDC in the header)";
    else st.runs = true;
    plan.effects.push_back(st);
    if (st.runs) {
      // Pass reflections.isg (both methods: isg and the naive blur), then the composite term
      // refl.weight·(refl.glossy − refl).
      plan.refl = effects::refl_settings(*cam, scene.scene_radius, p, view_h);
      need("refl", 3, true);
      need("refl.dist", 1, true);
      need("refl.weight", 3, true);
      need("normal", 3, true);
      const std::string geo = roles.has("position") ? "position" : "depth";
      need(geo, geo == "position" ? 3 : 1, true);
      std::vector<std::string> reads = {"refl", "refl.dist", "refl.weight", "normal", geo, "fg"};
      if (roles.has("roughness") && !plan.refl->roughness_override) {
        need("roughness", 1, true);
        reads.push_back("roughness");
      }
      // reflections.pack: the taps' data, two 16-byte texels a pixel (reflections.isg's input).
      need("refl.pack.geo", 4, false);
      need("refl.pack.color", 4, false);
      plan.passes.push_back({"reflections.pack", "reflections.pack", reads,
                             {"refl.pack.geo", "refl.pack.color"}, ""});
      reads = {"refl.pack.geo", "refl.pack.color"};
      if (roles.has("roughness") && !plan.refl->roughness_override) reads.push_back("roughness");
      need("refl.glossy", 3, false);
      const uint64_t tiles = uint64_t((width + REFL_TILE - 1) / REFL_TILE) *
                             uint64_t((height + REFL_TILE - 1) / REFL_TILE);
      plan.resources.push_back({"refl.tiles", 1, false, tiles * sizeof(float)});
      plan.passes.push_back({"reflections.isg", "reflections." + st.method, reads,
                             {"refl.glossy", "refl.tiles"}, ""});
      plan.passes.push_back({"composite_term", "composite[reflections]",
                             {"composite", "refl.weight", "refl.glossy", "refl", "fg"},
                             {"composite"}, ""});
    }
  }
  {
    // Depth of field runs last, on the finished composite (AOV_CONTRACT.md "Output").
    EffectStatus st{"dof", false, p.choice("dof.method"), ""};
    const io::Camera* cam = camera ? camera : (scene.camera ? &*scene.camera : nullptr);
    if (st.method == "none") st.why = "dof.method = none";
    else if (!roles.has("depth")) st.why = "missing channels for role depth";
    else if (!cam) st.why = "no camera (scene file, or worldToCamera/worldToNDC in the header)";
    else st.runs = true;
    plan.effects.push_back(st);
    if (st.runs) {
      io::Camera c = *cam;
      c.width = window.whole() ? width : window.frame_w;  // CoC in pixels of the frame
      plan.dof = effects::dof_settings(c, scene.units, p);
      need("dof.coc", 1, false);
      need("dof.input", 4, false);
      const uint64_t tiles = uint64_t((width + 15) / 16) * uint64_t((height + 15) / 16);
      plan.resources.push_back({"dof.tiles", 1, false, tiles * 4 * sizeof(float)});
      plan.passes.push_back({"dof.coc", "dof.coc", {"composite", "depth"}, {"dof.coc", "dof.input"}, ""});
      plan.passes.push_back({"dof.tiles", "dof.tiles", {"dof.coc"}, {"dof.tiles"}, ""});
      if (st.method == "isg") {
        need("dof.radius", 1, false);
        plan.passes.push_back({"dof.search", "dof.search", {"dof.coc", "dof.tiles"}, {"dof.radius"}, ""});
        plan.passes.push_back({"dof.gather", "dof.gather",
                               {"dof.input", "dof.coc", "dof.tiles", "dof.radius"}, {"composite"}, ""});
      } else {
        plan.passes.push_back({"dof.layered", "dof.layered", {"dof.input", "dof.coc", "dof.tiles"},
                               {"composite"}, ""});
      }
    }
  }
  // A tile of a larger frame: every setting takes the window.
  for (auto& [l, st] : plan.shadows) st.window = window;
  for (auto& [l, st] : plan.shadowmaps) st.window = window;
  for (auto& [l, st] : plan.derived) st.window = window;
  if (plan.refl) plan.refl->window = window;
  if (plan.dof) plan.dof->window = window;
  // Reach: shadows.isg and reflections.isg read their inputs within max_radius (and whole
  // 16x16 tiles' flags); the shadow-map methods the screen neighbours; depth of field reads
  // the composite within max_coc, through dof.tiles' margin and dof.search.
  double before_dof = 1.0;
  for (const auto& [l, st] : plan.shadows) before_dof = std::max(before_dof, st.max_radius + 16.0);
  if (plan.refl) before_dof = std::max(before_dof, plan.refl->max_radius + 16.0);
  const double dof = plan.dof ? 3.0 * (plan.dof->lens.max_coc + 1.0) + 16.0 : 0.0;
  plan.reach = int(std::ceil(before_dof + dof));
  return plan;
}

}  // namespace isg::plan
