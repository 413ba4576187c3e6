// What the reflections planner decides, for its recorder (no Vulkan).
#pragma once

#include "effects/effect.h"
#include "effects/reflections/settings.h"

namespace isg::effects {

struct ReflInstance : Instance {
  ReflSettings s;
  // reflections.isg reads within max_radius, and whole 16x16 tiles' flags.
  double reach() const override { return s.max_radius + 16.0; }
  void set_window(const Window& w) override { s.window = w; }
};

}  // namespace isg::effects
