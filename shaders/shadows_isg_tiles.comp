#version 450
// Pass shadows.isg.tiles (method isg, step 1): per 16×16 tile, whether its foreground holds lit
// and shadowed pixels, its largest occluder distance and the image's, d_max (which bounds every
// penumbra, eq. 8, so shadows.isg can size its search and skip tiles with no boundary within
// reach). lib/effects/shadows/isg.cpp mirrors it in double.
#extension GL_GOOGLE_include_directive : require
#include "shadows_isg_io.h"
layout(local_size_x = SHADOWS_ISG_TILE, local_size_y = SHADOWS_ISG_TILE) in;
layout(std430, binding = 0) readonly buffer Shadow { float shadow_in[]; };
layout(std430, binding = 1) readonly buffer Occluder { float occluder[]; };
layout(std430, binding = 2) readonly buffer Fg { float fg[]; };
layout(std430, binding = 3) buffer Tiles { uint tiles[]; };
layout(push_constant) uniform Push { ShadowsIsgPush pc; };

shared uint s_flags;
shared uint s_dmax;

void main() {
  if (gl_LocalInvocationIndex == 0u) {
    s_flags = 0u;
    s_dmax = 0u;
  }
  barrier();
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x < pc.width && p.y < pc.height) {
    uint i = p.y * pc.width + p.x;
    if (fg[i] != 0.0) {
      float s = shadow_in[i];
      uint f = (s > 0.0 ? SHADOWS_ISG_FLAG_LIT : 0u) | (s < 1.0 ? SHADOWS_ISG_FLAG_SHADOW : 0u);
      atomicOr(s_flags, f);
      // Positive floats order as their bits.
      if (s < 1.0 && occluder[i] > 0.0) atomicMax(s_dmax, floatBitsToUint(occluder[i]));
    }
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    uint tiles_x = (pc.width + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
    uint tiles_y = (pc.height + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
    uint nt = tiles_x * tiles_y, t = gl_WorkGroupID.y * tiles_x + gl_WorkGroupID.x;
    tiles[t] = s_flags;
    tiles[nt + t] = s_dmax;
    if (s_dmax != 0u) atomicMax(tiles[3u * nt + SHADOWS_ISG_STAT_DMAX], s_dmax);
  }
}
