#version 450
// Pass shadows.isg.reach (method isg, step 3 of 6): one workgroup a listed tile. The reach of the
// widest penumbra its receivers can take (eq. 5's R_p from the image's largest occluder distance)
// bounds the tiles to look at: the tile takes the cheap path (keeps the hard shadow) where none
// of them holds both light and shadow, and its search radius comes from the largest occluder
// distance among them (into the tiles buffer for shadows.isg.quads, shadows.isg and .own).
#extension GL_GOOGLE_include_directive : require
#include "shadows_isg.h"
layout(local_size_x = SHADOWS_ISG_TILE, local_size_y = SHADOWS_ISG_TILE) in;
shared uint s_rp;     // the tile's largest search radius (float bits)
shared uint s_reach;  // OR of the flags of the tiles within reach
shared uint s_dloc;   // the largest occluder distance of the tiles within reach (float bits)

void main() {
  uint tile, nt;
  uvec2 wg;
  if (!listed_tile(tile, wg, nt)) return;  // the whole workgroup
  uint tiles_x = (pc.width + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
  uint tiles_y = (pc.height + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
  uvec2 p = wg * SHADOWS_ISG_TILE + gl_LocalInvocationID.xy;
  bool inside = p.x < pc.width && p.y < pc.height;
  uint i = inside ? p.y * pc.width + p.x : 0u;
  float d_max = uintBitsToFloat(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_DMAX]);
  if (gl_LocalInvocationIndex == 0u) {
    s_rp = 0u;
    s_reach = 0u;
    s_dloc = 0u;
  }
  barrier();
  vec4 t0 = inside ? texelFetch(pack, int(i)) : vec4(SHADOWS_ISG_BACKGROUND);
  if (foreground(t0)) {
    Recv R = receiver(p, t0.xyz);
    atomicMax(s_rp, floatBitsToUint(min(radius_px(R, d_max), pc.max_radius)));
  }
  barrier();
  // The tiles the search and the gather can reach (radius + 1 for the bilinear taps).
  int reach = int(ceil(uintBitsToFloat(s_rp))) + 1;
  ivec2 t0_ = ivec2(wg) * SHADOWS_ISG_TILE;
  ivec2 lo = max((t0_ - reach) / SHADOWS_ISG_TILE, ivec2(0));
  ivec2 hi = min((t0_ + SHADOWS_ISG_TILE - 1 + reach) / SHADOWS_ISG_TILE, ivec2(tiles_x - 1u, tiles_y - 1u));
  int span = hi.x - lo.x + 1, count = span * (hi.y - lo.y + 1);
  for (int k = int(gl_LocalInvocationIndex); k < count; k += SHADOWS_ISG_TILE * SHADOWS_ISG_TILE) {
    uint t = uint(lo.y + k / span) * tiles_x + uint(lo.x + k % span);
    atomicOr(s_reach, tiles[t]);
    atomicMax(s_dloc, tiles[nt + t]);
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    bool cheap = (FLAGS & SHADOWS_ISG_TILE_SKIP) != 0u &&
                 s_reach != (SHADOWS_ISG_FLAG_LIT | SHADOWS_ISG_FLAG_SHADOW);
    tiles[2u * nt + tile] = cheap ? 1u : 0u;
    // Eq. 5: the search radius R_p covers the widest penumbra the occluders around can cast.
    tiles[SHADOWS_ISG_AT_DLOC(nt) + tile] = s_dloc;
  }
}
