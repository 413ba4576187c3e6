// The planner: from the roles present, the scene and the preset, the passes to run and the GPU
// resources they need, nothing more (Filament's frame graph plays this role there).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "effects/dof/settings.h"
#include "effects/reflections/settings.h"
#include "effects/shadows/settings.h"
#include "effects/shadows/shadowmap.h"
#include "io/roles.h"
#include "io/scene.h"
#include "params/params.h"

namespace isg::plan {

struct Resource {
  std::string name;  // a role ("beauty", "key.shadow") or a product ("fg", "key.softshadow")
  int planes = 1;
  bool upload = false;  // filled from the input image
  uint64_t bytes = 0;
};

struct Pass {
  std::string name;    // kernel stage, e.g. "shadows.hard"
  std::string label;   // name in timings, e.g. "shadows.hard[key]"
  std::vector<std::string> reads, writes;
  std::string light;   // for per-light passes
};

struct EffectStatus {
  std::string effect;  // "shadows[key]", "reflections", "dof"
  bool runs = false;
  std::string method;
  std::string why;     // why it cannot or does not run
};

struct Plan {
  int width = 0, height = 0;
  std::vector<Resource> resources;
  std::vector<Pass> passes;
  std::vector<EffectStatus> effects;
  std::vector<std::string> soft_lights;  // lights whose soft shadows are computed
  std::vector<std::string> missing;      // required roles absent: the run cannot go on
  std::optional<effects::DofSettings> dof;  // set when depth of field runs
  std::optional<effects::ReflSettings> refl;  // set when glossy reflections run
  std::map<std::string, effects::ShadowSettings> shadows;  // per light, where shadows.isg runs
  // Per light, where a shadow-map method (shadows.method = pcss) runs.
  std::map<std::string, effects::ShadowmapSettings> shadowmaps;
  // Per light, where method isg takes L.occluder (and L.shadow when absent) from the shadow map.
  std::map<std::string, effects::ShadowmapSettings> derived;
  // How far (pixels) any pass reads from a pixel, through every pass after it: the apron a
  // tile needs to compute its pixels as the whole frame would.
  int reach = 0;

  const Resource* resource(const std::string& name) const;
  uint64_t gpu_bytes() const;
  std::string describe() const;  // what `isg run --dry-run` prints
};

// Which effects the inputs allow at all, whatever the preset, and why not where they don't
// (what `isg info` reports).
std::vector<EffectStatus> capabilities(const io::Roles& roles, const io::Scene& scene,
                                       bool has_camera);

// `camera`: the scene file's, else the EXR header's (null: the scene file's, if any).
// `window`: the image is a tile of a larger frame (large plates, lib/run/job.cpp); the
// settings take the frame's focal length and principal point and the tile's hash origin.
Plan make_plan(const io::Roles& roles, const io::Scene& scene, const params::Params& p,
               int width, int height, const io::Camera* camera = nullptr,
               const effects::Window& window = {});

}  // namespace isg::plan
