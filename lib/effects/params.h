// Every effect's parameter table, concatenated: the one list the CLI, presets, provenance and
// docs read. A new effect adds its table here.
#pragma once

#include <vector>

#include "params/params.h"

namespace isg::effects {

std::vector<params::Def> shadows_params();
std::vector<params::Def> reflections_params();
std::vector<params::Def> dof_params();
std::vector<params::Def> output_params();

std::vector<params::Def> all_params();
// Default parameter values (every key at its default).
params::Params default_params();

}  // namespace isg::effects
