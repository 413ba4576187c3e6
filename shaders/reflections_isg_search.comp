#version 450
// Pass reflections.isg.search (method isg, step 1 of 4): a lane per 2×2 quad of the tiles
// reflections.list kept. The quad's glossy pixels, and the parameter search (eq. 4, 10-12) of its
// first glossy pixel (the representative) over its whole lattice; both into the quad's record in
// refl.tiles for reflections.isg.wide and reflections.isg.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "reflections_isg.h"
layout(local_size_x = REFL_QUADS, local_size_y = REFL_QUADS) in;

void main() {
  uint tile, nt;
  uvec2 wg;
  if (!listed_tile(tile, wg, nt)) return;  // the whole workgroup
  uint q = gl_LocalInvocationIndex;
  uvec2 base = quad_base(wg, q);
  uint mask = 0u;
  for (uint k = 0u; k < 4u; ++k) {
    uvec2 pp = base + uvec2(k & 1u, k >> 1u);
    if (pp.x < pc.width && pp.y < pc.height && is_glossy(pp.y * pc.width + pp.x)) mask |= 1u << k;
  }
  float t = 1.0;
  if (mask != 0u) {
    uvec2 rp = quad_rep(wg, q, mask);
    uint r = rp.y * pc.width + rp.x;
    t = search(lobe_at(rp, r), r);
  }
  uint at = quad_at(nt, tile, q);
  tiles[at] = mask;
  tiles[at + 1u] = floatBitsToUint(t);
  // The tile's searches (statistics): reduced over the subgroup, one atomic a subgroup.
  uint searches = subgroupAdd(mask != 0u ? 1u : 0u);
  if (subgroupElect() && searches != 0u) atomicAdd(tiles[tile], REFL_STATS_SEARCHES * searches);
}
