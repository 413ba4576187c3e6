// The composite's planner side (no Vulkan): the term an effect adds to the composite.
#pragma once

#include <string>

#include "effects/effect.h"

namespace isg::effects {

// Pass composite_term of instance `inst`: C += W·(X − Y) on foreground pixels.
void plan_composite_term(PlanOut& out, int inst, const std::string& label, const std::string& W,
                         const std::string& X, const std::string& Y, const std::string& light = "");

}  // namespace isg::effects
