// The planner on its own (issue 56): this program links isg_plan and nothing else, so it builds
// only while lib/plan and every effect's planner side stay free of the GPU stack; ctest
// `layers.planner_links_without_vulkan` (no_vulkan.cmake) then checks that the program pulls in
// no Vulkan library or symbol, and runs it: a plan for a frame with a sun and a key light, every
// pass named, no device.
#include <cstdio>

#include "effects/params.h"
#include "io/roles.h"
#include "io/scene.h"
#include "plan/plan.h"

int main() {
  isg::io::Scene scene;
  isg::io::Light key, sun;
  key.name = "key";
  key.type = isg::io::LightType::sphere;
  key.position = {0, 0, 4};
  key.radius = 0.3;
  sun.name = "sun";
  sun.type = isg::io::LightType::sun;
  sun.direction = {0, 0.6, 0.8};
  sun.angle_deg = 2.0;
  scene.lights = {key, sun};
  isg::io::Camera cam;
  cam.width = 64;
  cam.height = 32;
  scene.camera = cam;
  std::vector<std::string> channels = {"R", "G", "B", "A", "Z"};
  for (const char* l : {"key", "sun"})
    for (const char* c : {".shadow", ".occluder", ".direct.R", ".direct.G", ".direct.B"})
      channels.push_back(std::string(l) + c);
  const auto roles = isg::io::resolve_roles(channels, {}, "frame.exr");
  const auto plan = isg::plan::make_plan(roles, scene, isg::effects::default_params(), 64, 32);
  size_t shadow_passes = 0;
  for (const auto& p : plan.passes) {
    std::printf("pass %s\n", p.name.c_str());
    shadow_passes += p.name.rfind("shadows", 0) == 0 ? 1 : 0;
  }
  const bool ok = plan.missing.empty() && plan.instance("shadows[key]") && plan.instance("shadows[sun]") && shadow_passes > 0;
  std::printf("%s: %zu passes, %zu of them shadows'\n", ok ? "planned" : "NOT planned", plan.passes.size(), shadow_passes);
  return ok ? 0 : 1;
}
