// What the depth-of-field planner decides, for its recorder (no Vulkan).
#pragma once

#include "effects/dof/settings.h"
#include "effects/effect.h"

namespace isg::effects {

struct DofInstance : Instance {
  DofSettings s;
  // The composite within max_coc, through dof.tiles' margin and dof.search: three CoC radii
  // and a tile.
  double reach() const override { return 3.0 * (s.lens.max_coc + 1.0) + 16.0; }
  void set_window(const Window& w) override { s.window = w; }
};

}  // namespace isg::effects
