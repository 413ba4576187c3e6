#version 450
// Pass shadows.isg.quads (method isg, step 4 of 6): a sum a 2×2 quad of the listed tiles that do
// not take the cheap path (PART_LANES lanes a sum, shadows_isg.h). The search and the wide
// gathers at half resolution (issue 18): the quad's first foreground pixel (the representative)
// searches (eq. 4, 6, 7) over the whole lattice, and gathers (eq. 4) where its radius R_g is at
// least SHADOWS_ISG_REUSE_RADIUS; both into the quad's record for shadows.isg and .own.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#define SHADOWS_ISG_PARTED (SHADOWS_ISG_TILE * SHADOWS_ISG_TILE / 4u)  // the tile's quads
#include "shadows_isg.h"

void main() {
  uint tile, nt;
  uvec2 wg;
  if (!listed_tile(tile, wg, nt)) return;  // the whole workgroup
  if (tiles[2u * nt + tile] != 0u) return;  // the cheap path: no record is read
  uint q = sum_slot(), at = quad_at(nt, tile, q);
  bool first = sum_part() == 0u;  // the lane that writes the record
  float d_loc = uintBitsToFloat(tiles[SHADOWS_ISG_AT_DLOC(nt) + tile]);
  uvec2 base = wg * SHADOWS_ISG_TILE + 2u * uvec2(q % QUADS, q / QUADS);
  uint r = SHADOWS_ISG_NO_REP;
  uvec2 rp = base;
  for (uint k = 0u; k < 4u; ++k) {
    uvec2 pp = base + uvec2(k & 1u, k >> 1u);
    if (r == SHADOWS_ISG_NO_REP && pp.x < pc.width && pp.y < pc.height && foreground(texelFetch(pack, int(pp.y * pc.width + pp.x)))) {
      r = pp.y * pc.width + pp.x;
      rp = pp;
    }
  }
  float d = -1.0, Rg = -1.0, m = 0.0;
  bool wide = false;
  if (r != SHADOWS_ISG_NO_REP) {
    Recv Rr = receiver(rp, texelFetch(pack, int(r)).xyz);
    float Rp = radius_px(Rr, d_loc);
    d = search_mean(search_total(Rr, rp, r, Rp));
    float Rs = 0.0;
    if (d >= 0.0) {
      Rs = penumbra(d, Rr.D);
      Rg = min(Rs / Rr.pix, pc.max_radius);
    }
    wide = d >= 0.0 && Rg >= SHADOWS_ISG_REUSE_RADIUS;
    if (wide) {
      vec2 g = gather_total(Rr, rp, r, Rs);
      m = g.x / g.y;
    }
  }
  if (first) {
    tiles[at] = r;
    tiles[at + 1u] = floatBitsToUint(d);
    tiles[at + 2u] = floatBitsToUint(wide ? m : 0.0);
    tiles[at + 3u] = floatBitsToUint(wide ? Rg : -1.0);
  }
  // Statistics: reduced over the subgroup, one atomic a subgroup.
  uint searches = subgroupAdd(first && r != SHADOWS_ISG_NO_REP ? 1u : 0u);
  uint gathers = subgroupAdd(first && wide ? 1u : 0u);
  if (subgroupElect()) {
    if (searches != 0u) atomicAdd(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_SEARCHES], searches);
    if (gathers != 0u) atomicAdd(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_GATHERS], gathers);
  }
}
