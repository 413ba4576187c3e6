#include "effects/params.h"

namespace isg::effects {

using params::Def;
using params::Type;

std::vector<Def> shadows_params() {
  return {
      {"shadows.method", Type::choice, "hard", 0, 0, {"none", "hard"},
       "soft-shadow method for every light with L.shadow and L.direct (hard: keep the input's "
       "hard shadow; the placeholder until the soft methods land)", ""},
  };
}

std::vector<Def> reflections_params() {
  return {
      {"reflections.method", Type::choice, "none", 0, 0, {"none"},
       "glossy reflection method (needs refl, refl.dist, refl.weight)", ""},
  };
}

std::vector<Def> dof_params() {
  return {
      {"dof.method", Type::choice, "none", 0, 0, {"none"},
       "depth-of-field method, applied last on the composite (needs depth and the camera)", ""},
  };
}

std::vector<Def> output_params() {
  return {
      {"output.compression", Type::choice, "zip", 0, 0,
       {"none", "rle", "zip", "zips", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"},
       "EXR compression of the output", ""},
      {"limits.max_megapixels", Type::number, "268.5", 0.001, 4096, {},
       "largest input image accepted, checked before decoding", "megapixels"},
      {"limits.max_channels", Type::integer, "1024", 1, 65536, {},
       "most channels accepted in one input file, checked before decoding", ""},
      {"limits.max_memory_mb", Type::integer, "16384", 16, 1 << 22, {},
       "most host memory the decoded input may take", "MiB"},
      {"limits.check_seconds", Type::number, "30", 0, 3600, {},
       "time OpenEXR's own checker may take on an input before decoding, in a child process "
       "(0 skips it)", "s"},
  };
}

std::vector<Def> all_params() {
  std::vector<Def> all;
  for (auto table : {shadows_params, reflections_params, dof_params, output_params}) {
    auto t = table();
    all.insert(all.end(), t.begin(), t.end());
  }
  return all;
}

params::Params default_params() { return params::Params(all_params()); }

}  // namespace isg::effects
