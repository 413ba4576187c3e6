#version 450
// Pass shadows.isg (paper §3.1; method isg, step 5 of 6): a lane per pixel of the listed tiles
// that do not take the cheap path. The pixel takes its quad representative's mean occluder
// distance (shadows.isg.quads) unless it lies on another surface (eq. 6 weight under
// SHADOWS_ISG_QUAD_SAME), then its penumbra (eq. 8-9: R_s in the world, R_g in pixels at the
// receiver's depth): a wide one from the quads' gathers around it (reuse()), where they can lend
// it. A pixel that searches or gathers for itself joins the list shadows.isg.own finishes: on
// lavapipe every lane would run, masked, the loops of the few that need them. The hard shadow
// stands where no occluder is within reach of the quad's search, nor of those of
// SHADOWS_ISG_BORROW_MIN quads around it on its surface (borrowed_d).
// lib/effects/shadows/isg.cpp mirrors every step in double; shaders/shadows_isg.h holds what the
// dispatches share.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "shadows_isg.h"
layout(local_size_x = SHADOWS_ISG_TILE, local_size_y = SHADOWS_ISG_TILE) in;

void main() {
  uint tile, nt;
  uvec2 wg;
  if (!listed_tile(tile, wg, nt)) return;  // the whole workgroup
  if (tiles[2u * nt + tile] != 0u) return;  // the cheap path: L.softshadow keeps the hard shadow
  uvec2 l = gl_LocalInvocationID.xy, p = wg * SHADOWS_ISG_TILE + l;
  bool inside = p.x < pc.width && p.y < pc.height;
  uint i = inside ? p.y * pc.width + p.x : 0u;
  vec4 t0 = inside ? texelFetch(pack, int(i)) : vec4(SHADOWS_ISG_BACKGROUND);
  bool full = foreground(t0), clamped = false, listed = false, search_own = false, borrow = false;
  float out_ = 0.0;
  if (full) {
    Recv R = receiver(p, t0.xyz);
    float d_loc = uintBitsToFloat(tiles[SHADOWS_ISG_AT_DLOC(nt) + tile]);
    clamped = radius_px(R, d_loc) > pc.max_radius;
    uint at = quad_at(nt, tile, quad_of(l)), r = tiles[at];
    float d = uintBitsToFloat(tiles[at + 1u]);
    search_own = r != i && same_surface(r, R.P0) < SHADOWS_ISG_QUAD_SAME;
    if (search_own) {
      listed = true;
    } else if (d < 0.0) {
      // No occluder within the quad's reach: the hard shadow stands, unless the quads around
      // found one (shadows.isg.own: borrowed_d).
      out_ = texelFetch(shadow_in, int(i)).r;
      borrow = listed = may_borrow(l, nt, tile);
    } else {
      listed = !lent(l, nt, tile, R, d, clamped, out_);
    }
  }
  if (listed) {
    uint k = atomicAdd(tiles[SHADOWS_ISG_AT_OWN_COUNT(nt)], 1u);
    tiles[SHADOWS_ISG_AT_OWN(nt) + k] =
        i | (search_own ? SHADOWS_ISG_OWN_SEARCH : 0u) | (borrow ? SHADOWS_ISG_OWN_BORROW : 0u);
    // That dispatch is SHADOWS_ISG_OWN_ROW workgroups wide: a row per row's worth begun.
    if (k % (SHADOWS_ISG_OWN_ROW * SHADOWS_ISG_OWN_LOCAL) == 0u) atomicAdd(tiles[SHADOWS_ISG_AT_OWN_ARGS(nt) + 1u], 1u);
  } else if (full) {
    soft[i] = out_;
  }
  // Statistics (the pixels that search for themselves count theirs in shadows.isg.own).
  uint n_full = subgroupAdd(full ? 1u : 0u), n_clamped = subgroupAdd(clamped && !search_own ? 1u : 0u);
  if (subgroupElect()) {
    if (n_full != 0u) atomicAdd(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_FULL], n_full);
    if (n_clamped != 0u) atomicAdd(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_CLAMPED], n_clamped);
  }
}
