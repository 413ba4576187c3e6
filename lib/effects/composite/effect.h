// The composite's planner side (no Vulkan): the term an effect adds to the composite.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "effects/effect.h"
#include "io/image.h"
#include "io/roles.h"

namespace isg::effects {

// The foreground, as pass foreground finds it (its double reference): 1 on foreground, 0 on
// background (alpha 0, depth <= 0 or >= 1e9); either input may be null.
std::vector<float> foreground_reference(const float* alpha, const float* depth, size_t n);
// The same for an image: its beauty's alpha (when it has one) and its depth role (when bound).
std::vector<float> foreground_of(const io::Image& img, const io::Roles& roles);

// Pass composite_term of instance `inst`: C += W·(X − Y) on foreground pixels.
void plan_composite_term(PlanOut& out, int inst, const std::string& label, const std::string& W,
                         const std::string& X, const std::string& Y, const std::string& light = "");

}  // namespace isg::effects
