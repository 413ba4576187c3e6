#include "effects/params.h"

#include "effects/dof/params.h"
#include "effects/effect.h"
#include "effects/output_params.h"

namespace isg::effects {

std::vector<params::Def> output_params() {
  return {
      params::def(output_keys::compression, "zip",
       {"none", "rle", "zip", "zips", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"},
       "EXR compression of the output"),
      params::def(output_keys::max_megapixels, "268.5", 0.001, 4096,
       "largest input image accepted, checked before decoding", "megapixels"),
      params::def(output_keys::max_channels, "1024", 1, 65536,
       "most channels accepted in one input file, checked before decoding"),
      params::def(output_keys::max_memory_mb, "16384", 16, 1 << 22,
       "most host memory the decoded input may take", "MiB"),
      params::def(output_keys::tile_size, "0", 0, 1 << 16,
       "process the image in tiles of this many pixels a side (rounded up to 16), each with the "
       "apron its passes read, giving what one piece would; 0: only when the plan's buffers "
       "exceed half the device's memory or its largest storage buffer", "pixels"),
      params::def(output_keys::check_seconds, "30", 0, 3600,
       "time OpenEXR may take to decode an input, in a child process where a damaged file "
       "cannot crash or hang isg (0: decode in isg itself, for trusted files only)", "s"),
  };
}

// Depth of field's table, until dof moves to the effect interface.
std::vector<params::Def> dof_params() {
  return {
      params::def(dof_keys::method, "none", {"none", "isg", "layered"},
       "depth-of-field method, applied last on the composite (needs depth and the camera): isg "
       "(the paper's parameter search and gather, eq. 15-17), layered (near and far fields "
       "gathered apart, the near field composited over the far by its coverage)"),
      params::def(dof_keys::samples, "64", 1, 1024,
       "samples per pixel per gather pass, rounded to a square grid through the concentric disk "
       "map (rotated per pixel)"),
      params::def(dof_keys::focus_distance, "0", 0, 1e9,
       "focus distance z_f of eq. 15 (0: the camera's focus_distance)", "scene units"),
      params::def(dof_keys::fstop, "0", 0, 1024, "f-number (0: the camera's fstop)"),
      params::def(dof_keys::coc_infinity, "0", 0, 1024,
       "c_inf of eq. 15, the CoC radius at infinity (0: thin lens from focal length, f-stop, "
       "focus distance, sensor width and image width)", "pixels"),
      params::def(dof_keys::coc_scale, "1", 0, 100, "multiplies every circle of confusion"),
      params::def(dof_keys::max_coc, "32", 0.5, 256,
       "largest CoC radius; nearer points are clamped to it", "pixels"),
      params::def(dof_keys::aperture, "disk", {"disk", "polygon"},
       "aperture (bokeh) shape: the gathers' spatial weight"),
      params::def(dof_keys::blades, "6", 3, 16, "blades of a polygon aperture"),
      params::def(dof_keys::rotation, "0", -360, 360, "rotation of a polygon aperture",
       "degrees"),
      params::def(dof_keys::tile_skip, "true",
       "16x16 tiles whose CoC range is under half a pixel take the cheap path (a plain aperture "
       "average)"),
  };
}

std::vector<params::Def> all_params() {
  std::vector<params::Def> all;
  for (const Effect* e : all_effects()) {
    auto t = e->params();
    all.insert(all.end(), t.begin(), t.end());
  }
  auto d = dof_params();
  all.insert(all.end(), d.begin(), d.end());
  auto t = output_params();
  all.insert(all.end(), t.begin(), t.end());
  return all;
}

params::Params default_params() { return params::Params(all_params()); }

}  // namespace isg::effects
