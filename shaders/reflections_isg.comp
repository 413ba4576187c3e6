#version 450
// Pass reflections.isg (paper §3.2; method isg step 3 of 4, method blur alone): a lane per pixel
// of the tiles reflections.list kept. Method isg: the pixel's t̄ from its quad's record
// (reflections.isg.search); for a wide lobe the blocks' means around it (reflections.isg.wide),
// for a footprint under a quarter pixel the mirror; a pixel on another surface than its quad's
// representative (its own search) or with a footprint between (its own gather, eq. 4, 13, 14)
// joins the list reflections.isg.own finishes: on lavapipe every lane would run, masked, the
// loops of the few that need them. Method blur: a constant-width disk blur of refl.
// shaders/reflections_isg.h holds what the four dispatches share.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "reflections_isg.h"
layout(local_size_x = REFL_TILE, local_size_y = REFL_TILE) in;

vec3 refl_blur(uvec2 p, uint i) {
  vec2 p0 = vec2(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) + 0.5;  // frame coordinates
  mat2 R = pixel_rotation(p);
  vec3 s = texelFetch(pack_color, int(i)).rgb;
  float ws = 1.0;
  uint gs = pc.grids & 0xffffu, gg = pc.grids >> 16;
  for (uint k = 0u; k < gg * gg; ++k) {
    vec4 c = texelFetch(pack_color, int(tap(p0 + pc.blur_radius * (R * texelFetch(samples, int(gs * gs + k)).xy))));
    float w = has_refl(c) ? 1.0 : 0.0;
    s += w * c.rgb;
    ws += w;
  }
  return s / ws;
}

void main() {
  uint tile, nt;
  uvec2 wg;
  if (!listed_tile(tile, wg, nt)) return;  // the whole workgroup
  uvec2 l = gl_LocalInvocationID.xy, p = wg * REFL_TILE + l;
  bool inside = p.x < pc.width && p.y < pc.height;
  uint i = inside ? p.y * pc.width + p.x : 0u;
  uint searched = 0u, gathered = 0u;
  bool g, rest = false;
  vec3 c = vec3(0.0);
  if (REFL_MODE == REFL_MODE_BLUR) {
    g = inside && is_glossy(i);
    if (g) c = refl_blur(p, i);
  } else {
    // The quad's record: its glossy pixels and its representative's t̄.
    uint q = (l.y / 2u) * REFL_QUADS + l.x / 2u, at = quad_at(nt, tile, q);
    uint mask = tiles[at];
    g = inside && (mask & (1u << ((l.x & 1u) + 2u * (l.y & 1u)))) != 0u;
    if (g) {
      uvec2 rp = quad_rep(wg, q, mask);
      c = refl_isg(p, i, rp.y * pc.width + rp.x, uintBitsToFloat(tiles[at + 1u]), nt, false, rest,
                   searched, gathered);
    }
    // A pixel that searches or gathers for itself joins reflections.isg.own's list.
    if (rest) {
      uint k = atomicAdd(tiles[REFL_AT_OWN_COUNT(nt)], 1u);
      tiles[REFL_AT_OWN(nt) + k] = i;
      // The dispatch is REFL_OWN_ROW workgroups wide: a row per REFL_OWN_ROW · REFL_OWN_LOCAL begun.
      if (k % (REFL_OWN_ROW * REFL_OWN_LOCAL) == 0u) atomicAdd(tiles[REFL_AT_OWN_ARGS(nt) + 1u], 1u);
    }
  }
  // The tile's glossy pixels (statistics behind --timings): reduced over the subgroup, one
  // atomic a subgroup. Pixels not glossy keep refl, copied into refl.glossy before.
  uint st = subgroupAdd(g ? 1u : 0u);
  if (subgroupElect() && st != 0u) atomicAdd(tiles[tile], st);
  if (!g || rest) return;
  uint n = pc.width * pc.height;
  glossy[i] = c.r; glossy[n + i] = c.g; glossy[2u * n + i] = c.b;
}
