// The [shadows] parameters' keys.
// Declared once, here; the table (with default, range, help and unit) is in the effect's
// effect.cpp, and every read goes through these typed constants (Params::get).
#pragma once

#include "params/params.h"

namespace isg::effects::shadow_keys {
inline constexpr params::Choice method{"shadows.method"};
inline constexpr params::Int search_samples{"shadows.search_samples"};
inline constexpr params::Int gather_samples{"shadows.gather_samples"};
inline constexpr params::Number sigma{"shadows.sigma"};
inline constexpr params::Number max_radius{"shadows.max_radius"};
inline constexpr params::Flag rotate{"shadows.rotate"};
inline constexpr params::Flag search_reach{"shadows.search_reach"};
inline constexpr params::Flag tile_skip{"shadows.tile_skip"};
inline constexpr params::Int pcss_taps{"shadows.pcss_taps"};
inline constexpr params::Int pcss_narrow{"shadows.pcss_narrow"};
inline constexpr params::Choice pcss_pattern{"shadows.pcss_pattern"};
inline constexpr params::Number reach{"shadows.reach"};
inline constexpr params::Number input_edges{"shadows.input_edges"};
inline constexpr params::Number bias{"shadows.bias"};
inline constexpr params::Number slope_max{"shadows.slope_max"};
inline constexpr params::Number spread_bias{"shadows.spread_bias"};
inline constexpr params::Number depth_ulps{"shadows.depth_ulps"};
inline constexpr params::Number smap_max_radius{"shadows.smap_max_radius"};
inline constexpr params::Int vssm_m{"shadows.vssm_m"};
inline constexpr params::Int vssm_m_wide{"shadows.vssm_m_wide"};
inline constexpr params::Int vssm_h{"shadows.vssm_h"};
inline constexpr params::Int vssm_leaf_taps{"shadows.vssm_leaf_taps"};
inline constexpr params::Number vssm_flat{"shadows.vssm_flat"};
inline constexpr params::Number vssm_contact{"shadows.vssm_contact"};
inline constexpr params::Int vssm_narrow{"shadows.vssm_narrow"};
inline constexpr params::Int cssm_order{"shadows.cssm_order"};
inline constexpr params::Choice cssm_filter{"shadows.cssm_filter"};
inline constexpr params::Int cssm_max_basis{"shadows.cssm_max_basis"};
inline constexpr params::Int cssm_split{"shadows.cssm_split"};
inline constexpr params::Int cssm_narrow{"shadows.cssm_narrow"};
inline constexpr params::Number cssm_sharpen_a{"shadows.cssm_sharpen_a"};
inline constexpr params::Number cssm_sharpen_b{"shadows.cssm_sharpen_b"};
}  // namespace isg::effects::shadow_keys
