#include "plan/plan.h"

#include <algorithm>
#include <cmath>
#include <sstream>


namespace isg::plan {

const effects::Instance* Plan::instance(const std::string& key) const {
  for (const auto& i : instances)
    if (i->key == key) return i.get();
  return nullptr;
}

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

std::vector<EffectStatus> capabilities(const io::Roles& roles, const io::Scene& scene,
                                       bool has_camera) {
  std::vector<EffectStatus> out;
  for (const effects::Effect* e : effects::all_effects()) {
    auto s = e->capabilities(roles, scene, has_camera);
    out.insert(out.end(), s.begin(), s.end());
  }
  return out;
}

effects::Choices choose_from_pixels(const io::Roles& roles, const io::Scene& scene,
                                    const params::Params& p, const io::Image& img,
                                    const io::Camera* camera) {
  const io::Camera* cam = camera ? camera : (scene.camera ? &*scene.camera : nullptr);
  const effects::PlanContext c{roles, scene, p, img.width, img.height, cam, {}};
  effects::Choices out;
  for (const effects::Effect* e : effects::all_effects()) e->choose(c, img, out);
  return out;
}

Plan make_plan(const io::Roles& roles, const io::Scene& scene, const params::Params& p,
               int width, int height, const io::Camera* camera, const effects::Window& window,
               const effects::Choices* choices) {
  Plan plan;
  plan.width = width;
  plan.height = height;
  if (!roles.has("beauty")) {
    plan.missing.push_back("beauty (R G B [A])");
    return plan;
  }
  const uint64_t plane_bytes = uint64_t(width) * uint64_t(height) * sizeof(float);
  const io::Camera* cam = camera ? camera : (scene.camera ? &*scene.camera : nullptr);
  const effects::PlanContext c{roles, scene, p, width, height, cam, window, choices};
  effects::PlanOut out(plan.resources, plan.passes, plan.effects, plan.instances, plane_bytes);
  for (const effects::Effect* e : effects::all_effects()) e->plan(c, out);
  // A tile of a larger frame: every setting takes the window.
  for (auto& i : plan.instances) i->set_window(window);
  // Reach: the effects on the inputs read within their radii (the largest counts: their terms
  // only add up); each effect on the finished composite reads the composite within its own,
  // through every pass before it.
  double inputs = 1.0, composite = 0.0;
  for (const auto& i : plan.instances) {
    if (effects::effect_named(i->effect).stage() == effects::Stage::inputs)
      inputs = std::max(inputs, i->reach());
    else
      composite += i->reach();
  }
  plan.reach = int(std::ceil(inputs + composite));
  return plan;
}

}  // namespace isg::plan
