#version 450
// Pass shadows.isg.tiles (method isg, step 1): per 16×16 tile, whether its foreground holds lit
// and shadowed pixels, its largest occluder distance and the image's, d_max (which bounds every
// penumbra, eq. 8, so shadows.isg can size its search and skip tiles with no boundary within
// reach). It also packs each pixel's tap data, L.isg.pack = (P − eye, L.shadow or background),
// so a tap of shadows.isg is one 16-byte load (issue 18); positions are relative to the camera
// (shaders/isg_view.h). lib/effects/shadows/isg.cpp mirrors it in double.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "shadows_isg_io.h"
#include "isg_view.h"
#include "isg_texels.h"
layout(local_size_x = SHADOWS_ISG_TILE, local_size_y = SHADOWS_ISG_TILE) in;
layout(binding = 0) uniform samplerBuffer shadow_in;
layout(binding = 1) uniform samplerBuffer occluder;
layout(binding = 2) uniform samplerBuffer geo;  // P (3 planes) or Z
layout(binding = 3) uniform samplerBuffer fg;
layout(std430, binding = 4) buffer Tiles { uint tiles[]; };
layout(std430, binding = 5) writeonly buffer Pack { vec4 pack[]; };
layout(push_constant) uniform Push { ShadowsIsgTilesPush pc; };
// SHADOWS_ISG_HAS_POSITION or 0: compiled in, not branched on (gpu::Kernel).
layout(constant_id = 0) const uint FLAGS = 0u;

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  uint flags = 0u, dmax = 0u;  // this lane's: SHADOWS_ISG_FLAG_*, its occluder distance's bits
  if (p.x < pc.width && p.y < pc.height) {
    uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
    float s = texelFetch(shadow_in, int(i)).r;
    vec3 rel = vec3(0.0);
    if (texelFetch(fg, int(i)).r != 0.0) {
      flags = (s > 0.0 ? SHADOWS_ISG_FLAG_LIT : 0u) | (s < 1.0 ? SHADOWS_ISG_FLAG_SHADOW : 0u);
      // Positive floats order as their bits.
      float o = isg_at(occluder, i);
      if (s < 1.0 && o > 0.0) dmax = floatBitsToUint(o);
      if ((FLAGS & SHADOWS_ISG_HAS_POSITION) != 0u) {
        rel = isg_rel_from_world(isg_at3(geo, i, n), vec3(pc.eye_x, pc.eye_y, pc.eye_z),
                                 vec3(pc.eye_lo_x, pc.eye_lo_y, pc.eye_lo_z));
      } else {
        // Frame coordinates (a tile adds its origin), so a tile rounds as the whole frame does.
        vec2 xy = vec2(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) + 0.5;
        mat3 rot = mat3(pc.r00, pc.r10, pc.r20, pc.r01, pc.r11, pc.r21, pc.r02, pc.r12, pc.r22);
        rel = isg_rel_from_depth(xy, texelFetch(geo, int(i)).r, vec2(pc.cx, pc.cy), pc.f_px, rot);
      }
    }
    // Background pixels carry SHADOWS_ISG_BACKGROUND instead of L.shadow.
    pack[i] = vec4(rel, texelFetch(fg, int(i)).r != 0.0 ? s : SHADOWS_ISG_BACKGROUND);
  }
  // The tile's flags and largest occluder distance, and the image's: reduced over the subgroup,
  // then at most three atomics a subgroup into tiles (zero before the pass). No barrier: on
  // lavapipe a shader with one runs its lanes as coroutines, about 60 ns a lane (issue 18,
  // docs/design.md).
  flags = subgroupOr(flags);
  dmax = subgroupMax(dmax);
  if (subgroupElect()) {
    uint tiles_x = (pc.width + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
    uint tiles_y = (pc.height + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
    uint nt = tiles_x * tiles_y, t = gl_WorkGroupID.y * tiles_x + gl_WorkGroupID.x;
    if (flags != 0u) atomicOr(tiles[t], flags);
    if (dmax != 0u) {
      atomicMax(tiles[nt + t], dmax);
      atomicMax(tiles[3u * nt + SHADOWS_ISG_STAT_DMAX], dmax);
    }
  }
}
