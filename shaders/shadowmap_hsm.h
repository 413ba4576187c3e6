// GLSL only: the min-max HSM's range query (shadowmap_hsm_io.h), for the passes that read it.
// Before including, define HSM_LV (an HsmLevels lvalue), HSM_MAP(i) (float: map texel i, not
// yet clamped), HSM_TEXEL(i) (vec2: stored texel i of levels 1...) and HSM_MAP_W (the map's
// width). lib/effects/shadows/hsm.cpp's HsmRef::range mirrors it.
#ifndef SHADOWMAP_HSM_H
#define SHADOWMAP_HSM_H

// Min and max depth over the texels a rectangle [lo, hi) touches: the HSM level whose texels
// are at least as large as it, where it spans at most 2x2 of them.
vec2 hsm_range(vec2 flo, vec2 fhi) {
  ivec2 lo = ivec2(floor(flo)), hi = max(ivec2(ceil(fhi)), lo + 1);
  int size = max(hi.x - lo.x, hi.y - lo.y);
  uint L = 0u;
  while ((1 << L) < size && L + 1u < HSM_LV.levels) ++L;
  ivec2 a = lo >> L, b = (hi - 1) >> L;
  vec2 r = vec2(1e30, -1e30);
  for (int y = a.y; y <= b.y; ++y)
    for (int x = a.x; x <= b.x; ++x) {
      vec2 c = L == 0u ? vec2(min(HSM_MAP(uint(y) * HSM_MAP_W + uint(x)), HSM_LV.far_z))
                       : HSM_TEXEL(HSM_LV.off[L] + uint(y) * HSM_LV.w[L] + uint(x));
      r = vec2(min(r.x, c.x), max(r.y, c.y));
    }
  return r;
}

#endif
