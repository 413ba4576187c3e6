// The [output] and [limits] parameters' keys (the job's, not an effect's).
// Declared once, here; the table (with default, range, help and unit) is in the effect's
// effect.cpp, and every read goes through these typed constants (Params::get).
#pragma once

#include "params/params.h"

namespace isg::effects::output_keys {
inline constexpr params::Choice compression{"output.compression"};
inline constexpr params::Number max_megapixels{"limits.max_megapixels"};
inline constexpr params::Int max_channels{"limits.max_channels"};
inline constexpr params::Int max_memory_mb{"limits.max_memory_mb"};
inline constexpr params::Int tile_size{"limits.tile_size"};
inline constexpr params::Number check_seconds{"limits.check_seconds"};
inline constexpr params::Choice positions{"input.positions"};
}  // namespace isg::effects::output_keys
