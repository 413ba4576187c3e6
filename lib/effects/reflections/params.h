// The [reflections] parameters' keys.
// Declared once, here; the table (with default, range, help and unit) is in the effect's
// effect.cpp, and every read goes through these typed constants (Params::get).
#pragma once

#include "params/params.h"

namespace isg::effects::refl_keys {
inline constexpr params::Choice method{"reflections.method"};
inline constexpr params::Int search_samples{"reflections.search_samples"};
inline constexpr params::Int gather_samples{"reflections.gather_samples"};
inline constexpr params::Number roughness{"reflections.roughness"};
inline constexpr params::Flag roughness_override{"reflections.roughness_override"};
inline constexpr params::Number energy{"reflections.energy"};
inline constexpr params::Number a{"reflections.a"};
inline constexpr params::Number b{"reflections.b"};
inline constexpr params::Number sigma{"reflections.sigma"};
inline constexpr params::Number max_radius{"reflections.max_radius"};
inline constexpr params::Number blur_radius{"reflections.blur_radius"};
inline constexpr params::Flag search_reach{"reflections.search_reach"};
inline constexpr params::Flag search_misses{"reflections.search_misses"};
inline constexpr params::Flag masking{"reflections.masking"};
inline constexpr params::Flag anisotropic{"reflections.anisotropic"};
}  // namespace isg::effects::refl_keys
