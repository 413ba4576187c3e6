// Depth-of-field settings from the camera and the preset (no GPU here: the planner's side).
#include "effects/dof/settings.h"

#include <algorithm>
#include <cmath>

#include "dof_io.h"
#include "effects/dof/params.h"

namespace isg::effects {

// ---- lens (eq. 15) ----

double mm_per_unit(const std::string& units) {
  if (units == "mm") return 1.0;
  if (units == "cm") return 10.0;
  return 1000.0;
}

DofLens dof_lens(const io::Camera& cam, const std::string& units, const params::Params& p) {
  DofLens L;
  L.z_f = p.get(dof_keys::focus_distance) > 0 ? p.get(dof_keys::focus_distance) : cam.focus_distance;
  const double N = p.get(dof_keys::fstop) > 0 ? p.get(dof_keys::fstop) : cam.fstop;
  const double f = cam.focal_length_mm, zf_mm = L.z_f * mm_per_unit(units);
  const int width = cam.width > 0 ? cam.width : 1;
  // Thin lens, as a radius in pixels (settings.h); a focus inside the focal length has no image.
  L.c_inf = zf_mm > f ? f * f / (2.0 * N * (zf_mm - f)) * width / cam.sensor_width_mm : 0.0;
  if (p.get(dof_keys::coc_infinity) > 0) L.c_inf = p.get(dof_keys::coc_infinity);
  L.c_inf *= p.get(dof_keys::coc_scale);
  L.max_coc = p.get(dof_keys::max_coc);
  return L;
}

DofSettings dof_settings(const io::Camera& cam, const std::string& units, const params::Params& p) {
  DofSettings s;
  s.method = p.get(dof_keys::method);
  s.lens = dof_lens(cam, units, p);
  s.grid = std::max(1, int(std::lround(std::sqrt(double(p.get(dof_keys::samples))))));
  s.blades = p.get(dof_keys::aperture) == "polygon" ? int(p.get(dof_keys::blades)) : 0;
  s.rotation_deg = p.get(dof_keys::rotation);
  s.anamorphic = p.get(dof_keys::anamorphic);
  s.tile_skip = p.get(dof_keys::tile_skip);
  const std::string& source = p.get(dof_keys::coc_source);
  const std::string& form = p.get(dof_keys::depth_form);
  s.coc_source = source == "channel" ? 1 : 0;
  if (s.coc_source == 1) s.lens.c_inf = p.get(dof_keys::coc_scale);  // the channel's gain
  s.depth_form = form == "normalized" ? 1 : form == "inverse" ? 2 : 0;
  s.depth_near = p.get(dof_keys::depth_near);
  s.depth_far = p.get(dof_keys::depth_far);
  return s;
}

uint32_t dof_tiles_x(uint32_t w) { return (w + DOF_TILE - 1) / DOF_TILE; }
uint32_t dof_tiles_y(uint32_t h) { return (h + DOF_TILE - 1) / DOF_TILE; }

}  // namespace isg::effects
