#version 450
// Pass reflections.isg.own (method isg, step 4 of 4): a lane per pixel on the list reflections.isg
// made, those that search for themselves (on another surface than their quad's representative)
// or gather for themselves (no wide blocks' means to take): the whole of refl_isg
// (shaders/reflections_isg.h) for them.
#extension GL_GOOGLE_include_directive : require
#include "reflections_isg.h"
layout(local_size_x = REFL_OWN_LOCAL) in;

void main() {
  uint tiles_x = (pc.width + REFL_TILE - 1u) / REFL_TILE;
  uint nt = tiles_x * ((pc.height + REFL_TILE - 1u) / REFL_TILE);
  uint k = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * REFL_OWN_LOCAL + gl_LocalInvocationIndex;
  if (k >= tiles[REFL_AT_OWN_COUNT(nt)]) return;
  uint i = tiles[REFL_AT_OWN(nt) + k];
  uvec2 p = uvec2(i % pc.width, i / pc.width), wg = p / REFL_TILE, l = p % REFL_TILE;
  uint tile = wg.y * tiles_x + wg.x;
  uint q = (l.y / 2u) * REFL_QUADS + l.x / 2u, at = quad_at(nt, tile, q);
  uvec2 rp = quad_rep(wg, q, tiles[at]);
  uint searched = 0u, gathered = 0u;
  bool rest;
  vec3 c = refl_isg(p, i, rp.y * pc.width + rp.x, uintBitsToFloat(tiles[at + 1u]), nt, true, rest,
                    searched, gathered);
  // Statistics: few lanes, from tiles anywhere in the image.
  if (searched != 0u) atomicAdd(tiles[tile], REFL_STATS_SEARCHES);
  if (gathered != 0u) atomicAdd(tiles[nt + tile], 1u);
  uint n = pc.width * pc.height;
  glossy[i] = c.r; glossy[n + i] = c.g; glossy[2u * n + i] = c.b;
}
