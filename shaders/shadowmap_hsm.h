// GLSL only: the min-max HSM lookup (lib/effects/shadowmaps/hsm.h). Before including, define
// SM_HSM (an HsmLevelsGpu), sm_hsm_texel(i) (level ≥ 1 texel i: vec2 min, max) and include
// shadowmap_common.h (sm_map).
#ifndef SHADOWMAP_HSM_H
#define SHADOWMAP_HSM_H
// Min and max depth over the texels a rectangle [lo, hi) touches: the HSM level whose texels
// are at least as large as it, where it spans at most 2x2 of them (a fixed 2 x 2, the second
// column or row repeating the first where the span has one, so the loop unrolls).
vec2 sm_hsm_range(vec2 flo, vec2 fhi) {
  ivec2 lo = ivec2(floor(flo)), hi = max(ivec2(ceil(fhi)), lo + 1);
  int size = max(hi.x - lo.x, hi.y - lo.y);
  // The least L with 2^L >= size, within the levels there are (no loop: lavapipe runs a loop
  // as often as its slowest lane needs).
  uint L = size <= 1 ? 0u : min(uint(findMSB(size - 1)) + 1u, SM_HSM.levels - 1u);
  ivec2 a = lo >> L, b = (hi - 1) >> L;
  vec2 r = vec2(1e30, -1e30);
  [[unroll]] for (int k = 0; k < 4; ++k) {
    int x = (k & 1) != 0 ? b.x : a.x, y = (k & 2) != 0 ? b.y : a.y;
    vec2 c = L == 0u ? vec2(min(sm_map(uint(y) * p.map_w + uint(x)), SM_HSM.far_z))
                     : sm_hsm_texel(SM_HSM.off[L] + uint(y) * SM_HSM.w[L] + uint(x));
    r = vec2(min(r.x, c.x), max(r.y, c.y));
  }
  return r;
}
#endif
