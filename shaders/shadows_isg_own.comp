#version 450
// Pass shadows.isg.own (method isg, step 6 of 6): a sum a pixel on the list shadows.isg made
// (PART_LANES lanes a sum, shadows_isg.h). A pixel on another surface than its quad's
// representative searches for itself (eq. 4, 6, 7), then takes its penumbra as shadows.isg would
// (the quads' gathers around it where they can lend it); every listed pixel else gathers for
// itself (eq. 4, radius R_g of eq. 8-9) from its quad's mean occluder distance. A pixel whose
// quad's search found none (SHADOWS_ISG_OWN_BORROW) takes the quads' around (borrowed_d), then
// its penumbra as a searching pixel does.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_shuffle : require
#define SHADOWS_ISG_PARTED SHADOWS_ISG_OWN_LOCAL
#include "shadows_isg.h"

void main() {
  uint tiles_x = (pc.width + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
  uint nt = tiles_x * ((pc.height + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE);
  uint k = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * SHADOWS_ISG_OWN_LOCAL + sum_slot();
  if (k >= tiles[SHADOWS_ISG_AT_OWN_COUNT(nt)]) return;
  uint e = tiles[SHADOWS_ISG_AT_OWN(nt) + k], i = e & ~(SHADOWS_ISG_OWN_SEARCH | SHADOWS_ISG_OWN_BORROW);
  bool search_own = (e & SHADOWS_ISG_OWN_SEARCH) != 0u, borrow = (e & SHADOWS_ISG_OWN_BORROW) != 0u;
  uvec2 p = uvec2(i % pc.width, i / pc.width), wg = p / SHADOWS_ISG_TILE, l = p % SHADOWS_ISG_TILE;
  uint tile = wg.y * tiles_x + wg.x;
  Recv R = receiver(p, texelFetch(pack, int(i)).xyz);
  uint at = quad_at(nt, tile, quad_of(l));
  float d = uintBitsToFloat(tiles[at + 1u]), out_ = texelFetch(shadow_in, int(i)).r;
  bool gathers = !search_own && !borrow, clamped = false;
  if (search_own || borrow) {
    float d_loc = uintBitsToFloat(tiles[SHADOWS_ISG_AT_DLOC(nt) + tile]);
    float Rp_raw = radius_px(R, d_loc);
    // shadows.isg counted a borrowing pixel's search radius over max_radius; here what lent()
    // adds to it.
    bool counted = borrow && Rp_raw > pc.max_radius;
    clamped = search_own && Rp_raw > pc.max_radius;
    // Its own search, or the quads' around where its quad's found no occluder.
    d = search_own ? search_mean(search_total(R, p, i, Rp_raw)) : borrowed_d(l, nt, tile, R.P0);
    float m;
    bool lends = d >= 0.0 && lent(l, nt, tile, R, d, clamped, m);
    if (lends) out_ = m;
    gathers = d >= 0.0 && !lends;  // d < 0: no occluder within reach, the hard shadow stands
    clamped = clamped && !counted;
  }
  if (gathers) {
    vec2 g = gather_total(R, p, i, penumbra(d, R.D));
    out_ = g.x / g.y;
  }
  if (sum_part() != 0u) return;  // the sum's first lane writes and counts
  soft[i] = out_;
  // Statistics: few lanes, from tiles anywhere in the image.
  if (search_own) atomicAdd(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_SEARCHES], 1u);
  if (gathers) atomicAdd(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_GATHERS], 1u);
  if (clamped) atomicAdd(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_CLAMPED], 1u);
  if (borrow && d >= 0.0) atomicAdd(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_BORROWED], 1u);
}
