// What the depth-of-field planner decides, for its recorder (no Vulkan).
#pragma once

#include <algorithm>
#include <cmath>

#include "effects/dof/settings.h"
#include "effects/effect.h"

namespace isg::effects {

struct DofInstance : Instance {
  DofSettings s;
  // The composite within max_coc, through dof.tiles' margin and dof.search: three CoC radii
  // and a tile; an anamorphic aperture reaches by its longer half-axis (dof.cpp's reach_scale).
  double reach() const override {
    const double k = std::sqrt(std::max(s.anamorphic, 1.0 / s.anamorphic));
    return 3.0 * (s.lens.max_coc + 1.0) * k + 16.0;
  }
  void set_window(const Window& w) override { s.window = w; }
};

}  // namespace isg::effects
