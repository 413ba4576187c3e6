// The parameter table: the job's own rows ([output], [limits]) and every effect's
// (Effect::params, in registry order): the one list the CLI, presets, provenance and docs read.
#pragma once

#include <vector>

#include "params/params.h"

namespace isg::effects {

// [output] and [limits]: the job's parameters (lib/effects/output_params.h has their keys).
std::vector<params::Def> output_params();

std::vector<params::Def> all_params();
// Default parameter values (every key at its default).
params::Params default_params();

}  // namespace isg::effects
