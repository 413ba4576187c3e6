// Glossy-reflection settings from the camera and the preset (no GPU here: the planner's side).
#include "effects/reflections/settings.h"

#include "effects/reflections/params.h"
#include "effects/sampling.h"
#include "reflections_isg_io.h"

namespace isg::effects {

ReflSettings refl_settings(const io::Camera& cam, double scene_radius, const params::Params& p,
                           int height) {
  ReflSettings s;
  s.method = p.get(refl_keys::method);
  s.grid_search = grid_of(p.get(refl_keys::search_samples));
  s.grid_gather = grid_of(p.get(refl_keys::gather_samples));
  s.roughness = p.get(refl_keys::roughness);
  s.roughness_override = p.get(refl_keys::roughness_override);
  s.energy = p.get(refl_keys::energy);
  s.a = p.get(refl_keys::a);
  s.b = p.get(refl_keys::b);
  s.sigma = p.get(refl_keys::sigma);
  s.scene_radius = scene_radius > 0 ? scene_radius : 1.0;
  s.max_radius = p.get(refl_keys::max_radius);
  s.blur_radius = p.get(refl_keys::blur_radius);
  s.search_reach = p.get(refl_keys::search_reach);
  s.search_misses = p.get(refl_keys::search_misses);
  s.anisotropic = p.get(refl_keys::anisotropic);
  s.masking = p.get(refl_keys::masking);
  const auto v = PinholeView::of(cam, height);
  s.f_px = v.f_px;
  s.eye = v.eye;
  s.rot = v.rot;
  return s;
}

uint32_t refl_tiles(uint32_t w, uint32_t h) {
  return ((w + REFL_TILE - 1) / REFL_TILE) * ((h + REFL_TILE - 1) / REFL_TILE);
}

uint32_t refl_tiles_words(uint32_t w, uint32_t h, bool records) {
  const uint32_t nt = refl_tiles(w, h);
  return records ? REFL_TILES_WORDS_ISG(nt) : REFL_TILES_WORDS(nt);
}

uint64_t refl_pack_texels(uint32_t w, uint32_t h) {
  // The texel after the last cell's (the cell rows' count is REFL_COARSE_CELLS(h)).
  return REFL_COARSE_AT(uint64_t(w), uint64_t(h), 0u, uint64_t(REFL_COARSE_CELLS(h)));
}

}  // namespace isg::effects
