// The planner: from the roles present, the scene and the preset, the passes to run and the GPU
// resources they need, nothing more (Filament's frame graph plays this role there). It asks
// every effect of the registry (lib/effects/effect.h) in turn and names none; no Vulkan here.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "effects/effect.h"
#include "io/roles.h"
#include "io/scene.h"
#include "params/params.h"

namespace isg::plan {

using effects::EffectStatus;
using effects::Pass;
using effects::Resource;

struct Plan {
  int width = 0, height = 0;
  std::vector<Resource> resources;
  std::vector<Pass> passes;
  std::vector<EffectStatus> effects;
  // Each effect application's resolved settings (shadows: one per light), for its passes.
  std::vector<std::shared_ptr<effects::Instance>> instances;
  std::vector<std::string> missing;      // required roles absent: the run cannot go on
  // How far (pixels) any pass reads from a pixel, through every pass after it: the apron a
  // tile needs to compute its pixels as the whole frame would.
  int reach = 0;

  const Resource* resource(const std::string& name) const;
  uint64_t gpu_bytes() const;
  std::string describe() const;  // what `isg run --dry-run` prints
  // The instance with this key ("shadows[key]", "reflections"), or null.
  const effects::Instance* instance(const std::string& key) const;
  template <class T>
  const T* instance_as(const std::string& key) const {
    return dynamic_cast<const T*>(instance(key));
  }
};

// Which effects the inputs allow at all, whatever the preset, and why not where they don't
// (what `isg info` reports).
std::vector<EffectStatus> capabilities(const io::Roles& roles, const io::Scene& scene,
                                       bool has_camera);

// `camera`: the scene file's, else the EXR header's (null: the scene file's, if any).
// `window`: the image is a tile of a larger frame (large plates, lib/run/job.cpp); the
// settings take the frame's focal length and principal point and the tile's hash origin.
// `choices`: what the effects chose from the frame's pixels (choose_from_pixels), else null.
Plan make_plan(const io::Roles& roles, const io::Scene& scene, const params::Params& p,
               int width, int height, const io::Camera* camera = nullptr,
               const effects::Window& window = {}, const effects::Choices* choices = nullptr);

// The effects' choices from a frame's pixels (its header's plan inputs); empty where the preset
// leaves nothing to them.
effects::Choices choose_from_pixels(const io::Roles& roles, const io::Scene& scene,
                                    const params::Params& p, const io::Image& img,
                                    const io::Camera* camera);

}  // namespace isg::plan
