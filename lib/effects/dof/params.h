// The [dof] parameters' keys.
// Declared once, here; the table (with default, range, help and unit) is in the effect's
// effect.cpp, and every read goes through these typed constants (Params::get).
#pragma once

#include "params/params.h"

namespace isg::effects::dof_keys {
inline constexpr params::Choice method{"dof.method"};
inline constexpr params::Int samples{"dof.samples"};
inline constexpr params::Number focus_distance{"dof.focus_distance"};
inline constexpr params::Number fstop{"dof.fstop"};
inline constexpr params::Number coc_infinity{"dof.coc_infinity"};
inline constexpr params::Number coc_scale{"dof.coc_scale"};
inline constexpr params::Number max_coc{"dof.max_coc"};
inline constexpr params::Choice aperture{"dof.aperture"};
inline constexpr params::Int blades{"dof.blades"};
inline constexpr params::Number rotation{"dof.rotation"};
inline constexpr params::Number anamorphic{"dof.anamorphic"};
inline constexpr params::Flag tile_skip{"dof.tile_skip"};
inline constexpr params::Choice coc_source{"dof.coc_source"};
inline constexpr params::Choice depth_form{"dof.depth_form"};
inline constexpr params::Number depth_near{"dof.depth_near"};
inline constexpr params::Number depth_far{"dof.depth_far"};
}  // namespace isg::effects::dof_keys
