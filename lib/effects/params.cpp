#include "effects/params.h"

#include "effects/effect.h"
#include "effects/output_params.h"

namespace isg::effects {

std::vector<params::Def> output_params() {
  return {
      params::def(output_keys::compression, "zip",
       {"none", "rle", "zip", "zips", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"},
       "EXR compression of the output"),
      params::def(output_keys::positions, "auto", {"P", "Z", "auto"},
       "where positions come from: P as the renderer wrote it (consistent with a shadow map the "
       "renderer computed in the same float32 world), refitted into a planar depth over its "
       "screen neighbours where its float32 step is wider than a 16th of a pixel at a scene radius "
       "from the camera (far from the world origin: 7.8 mm a step at 1e5 m, 6 cm at 1e6 m); or Z "
       "and the camera, refitted the same way there. auto: P where the input has it, else Z"),
      params::def(output_keys::max_megapixels, "268.5", 0.001, 4096,
       "largest input image accepted, checked before decoding", "megapixels"),
      params::def(output_keys::max_channels, "1024", 1, 65536,
       "most channels accepted in one input file, checked before decoding"),
      params::def(output_keys::max_memory_mb, "16384", 16, 1 << 22,
       "most host memory the decoded input may take", "MiB"),
      params::def(output_keys::tile_size, "0", 0, 1 << 16,
       "process the image in tiles of this many pixels a side (rounded up to 16), each with the "
       "apron its passes read, giving what one piece would; 0: only when the plan's buffers "
       "exceed the device's memory (half of a discrete GPU's; on unified memory, its whole heap) or "
       "its largest storage buffer", "pixels"),
      params::def(output_keys::check_seconds, "30", 0, 3600,
       "time OpenEXR may take to decode an input, in a child process where a damaged file "
       "cannot crash or hang isg (0: decode in isg itself, for trusted files only)", "s"),
  };
}

std::vector<params::Def> all_params() {
  std::vector<params::Def> all;
  for (const Effect* e : all_effects()) {
    auto t = e->params();
    all.insert(all.end(), t.begin(), t.end());
  }
  auto t = output_params();
  all.insert(all.end(), t.begin(), t.end());
  return all;
}

params::Params default_params() { return params::Params(all_params()); }

}  // namespace isg::effects
