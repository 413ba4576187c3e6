#include "plan/plan.h"

#include <algorithm>
#include <sstream>

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
      << "\n";
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
    std::string m = missing_of(roles, {"beauty", l + ".shadow", l + ".direct"});
    const io::Light* light = scene.light(l);
    if (!m.empty()) st.why = "missing " + m;
    else if (light && light->type == io::LightType::point) st.why = "point light: hard shadows are right";
    else st.runs = true;
    out.push_back(st);
  }
  if (roles.lights.empty()) out.push_back({"shadows", false, "", "no light channels (L.shadow, L.direct)"});
  {
    EffectStatus st{"reflections", false, "", ""};
    std::string m = missing_of(roles, {"beauty", "refl", "refl.weight", "refl.dist", "normal"});
    if (!roles.has("position") && !roles.has("depth")) m += std::string(m.empty() ? "" : ", ") + "position or depth";
    if (!m.empty()) st.why = "missing " + m;
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
               int width, int height) {
  Plan plan;
  plan.width = width;
  plan.height = height;
  const uint64_t plane_bytes = uint64_t(width) * uint64_t(height) * sizeof(float);

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
    for (const std::string& r : {l + ".shadow", l + ".direct"})
      if (!roles.has(r)) absent.push_back(r);
    if (method == "none") {
      st.why = "shadows.method = none";
    } else if (!absent.empty()) {
      st.why = "missing channels for role";
      for (const auto& a : absent) st.why += " " + a;
    } else if (light && light->type == io::LightType::point) {
      st.why = "point light: hard shadows are already right";
    } else {
      st.runs = true;
    }
    plan.effects.push_back(st);
    if (!st.runs) continue;
    plan.soft_lights.push_back(l);
    const std::string sh = l + ".shadow", dir = l + ".direct", soft = l + ".softshadow";
    need(sh, 1, true);
    need(dir, 3, true);
    need(soft, 1, false);
    plan.passes.push_back({"shadows." + method, "shadows." + method + "[" + l + "]", {sh},
                           {soft}, l});
    plan.passes.push_back({"composite_term", "composite[" + l + "]",
                           {"composite", dir, soft, sh, "fg"}, {"composite"}, l});
  }
  if (roles.lights.empty()) {
    plan.effects.push_back({"shadows", false, method, "no light channels (L.shadow) in the input"});
  }

  // Reflections and depth of field: slots for their issues.
  {
    EffectStatus st{"reflections", false, p.choice("reflections.method"), ""};
    if (st.method == "none") st.why = "reflections.method = none";
    plan.effects.push_back(st);
  }
  {
    EffectStatus st{"dof", false, p.choice("dof.method"), ""};
    if (st.method == "none") st.why = "dof.method = none";
    plan.effects.push_back(st);
  }
  return plan;
}

}  // namespace isg::plan
