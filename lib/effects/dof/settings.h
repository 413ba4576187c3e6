// Depth-of-field settings the planner resolves from the camera and the preset (no GPU here).
#pragma once

#include <cstdint>
#include <string>

#include "effects/view.h"
#include "io/scene.h"
#include "params/params.h"

namespace isg::effects {

// Eq. 15 in pixels: c(z) = c_inf · (z − z_f) / z, signed (near negative, far positive).
// Thin lens: an aperture of diameter f/N focused at z_f images a point at depth z to a disc of
// diameter (f/N) · f/(z_f − f) · |z − z_f|/z on the sensor; as a radius in pixels that is
//   c_inf = f² / (2 N (z_f − f)) · width_px / sensor_width   (f, z_f, sensor width in mm).
struct DofLens {
  double z_f = 5.0;      // focus distance, scene units (planar depth)
  double c_inf = 0.0;    // CoC radius at infinity, pixels
  double max_coc = 32;   // |CoC| clamp, pixels
};

struct DofSettings {
  std::string method = "none";  // "isg" or "layered"
  DofLens lens;
  int grid = 8;            // samples per pass = grid², a regular grid through the concentric map
  int blades = 0;          // 0: disk; n >= 3: n-blade polygon
  double rotation_deg = 0;  // polygon rotation
  double anamorphic = 1;    // dof.anamorphic: the aperture's height over its width
  bool tile_skip = true;   // cheap path for tiles whose CoC range is under half a pixel
  // dof.coc_source: 0 eq. 15 from depth (camera or depth), 1 a CoC channel (times lens.c_inf,
  // which is then dof.coc_scale).
  int coc_source = 0;
  // dof.depth_form: 0 planar, 1 normalized (depth_near + z (depth_far − depth_near)), 2 inverse.
  int depth_form = 0;
  double depth_near = 0.1, depth_far = 100.0;
  Window window;  // a tile of a larger frame (the pixel hash's origin)
};

// Millimetres per scene unit ("m", "cm", "mm"; anything else is taken as metres).
double mm_per_unit(const std::string& units);

// The lens of eq. 15 from the camera, with the preset's overrides (dof.focus_distance,
// dof.fstop, dof.coc_infinity, dof.coc_scale, dof.max_coc).
DofLens dof_lens(const io::Camera& cam, const std::string& units, const params::Params& p);

DofSettings dof_settings(const io::Camera& cam, const std::string& units, const params::Params& p);

// 16x16 tiles (DOF_TILE) across and down: dof.tiles holds 4 floats a tile.
uint32_t dof_tiles_x(uint32_t w);
uint32_t dof_tiles_y(uint32_t h);

}  // namespace isg::effects
