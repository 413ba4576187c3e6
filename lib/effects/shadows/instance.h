// What the shadows planner decides for one light, for its recorder (no Vulkan).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "effects/effect.h"
#include "effects/shadows/settings.h"

namespace isg::effects {

struct ShadowsInstance : Instance {
  std::string light;
  std::string method;                         // the method that runs: hard, isg, pcss, vssm, cssm
  std::optional<ShadowSettings> isg;          // method isg
  std::optional<ShadowmapSettings> smap;      // pcss, vssm, cssm
  std::optional<ShadowmapSettings> derived;   // isg: L.occluder (and L.shadow) from the map
  uint64_t map_texels = 0;                    // the scene file's size of the map
  std::shared_ptr<const ShadowmapData> map;   // read in the load stage, shared by the tiles
  double frame_dmax = -1;  // tiles: the whole frame's largest occluder distance (-1: none)

  // shadows.isg reads within max_radius, and whole 16x16 tiles' flags.
  double reach() const override { return isg ? isg->max_radius + 16.0 : 0.0; }
  void set_window(const Window& w) override {
    if (isg) isg->window = w;
    if (smap) smap->window = w;
    if (derived) derived->window = w;
  }
};

}  // namespace isg::effects
