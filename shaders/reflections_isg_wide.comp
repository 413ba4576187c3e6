#version 450
// Pass reflections.isg.wide (method isg, step 2 of 4): a lane per 4×4 block of the tiles
// reflections.list kept. Where the footprint (eq. 13) of the block's top-left quad's
// representative is wide (R_s ≥ REFL_REUSE_RADIUS), its gather over the whole lattice (eq. 4,
// 13, 14): the mean that the pixels with wide lobes around the block, in its tile and the tiles
// beside it, take bilinearly in reflections.isg and reflections.isg.own.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "reflections_isg.h"
layout(local_size_x = REFL_BLOCKS, local_size_y = REFL_BLOCKS) in;

void main() {
  uint tile, nt;
  uvec2 wg;
  if (!listed_tile(tile, wg, nt)) return;  // the whole workgroup
  uint b = gl_LocalInvocationIndex, q = block_quad(b), at = quad_at(nt, tile, q);
  uint mask = tiles[at];
  vec4 m = vec4(0.0, 0.0, 0.0, -1.0);
  uvec4 geo = uvec4(0u);
  if (mask != 0u) {
    uvec2 rp = quad_rep(wg, q, mask);
    uint r = rp.y * pc.width + rp.x;
    Lobe L = lobe_at(rp, r);
    Foot F = footprint(L, uintBitsToFloat(tiles[at + 1u]));
    if (F.R_s >= REFL_REUSE_RADIUS) m = vec4(gather_mean(L, r, F), F.R_s);
    geo = texelFetch(pack_geo, int(r));
  }
  uint bt = 4u * block_at(nt, tile, b);
  for (uint k = 0u; k < 4u; ++k) {
    tiles[bt + k] = floatBitsToUint(m[k]);
    tiles[bt + 4u + k] = geo[k];
  }
  uint gathers = subgroupAdd(m.w >= 0.0 ? 1u : 0u);
  if (subgroupElect() && gathers != 0u) atomicAdd(tiles[nt + tile], gathers);
}
