#version 450
// Pass shadows.isg.list (method isg, step 2): the tiles shadows.isg runs on, so that it is
// dispatched over them only (issue 18: on lavapipe a workgroup of shadows.isg cost about as much
// to start and classify itself as a listed tile's work). One lane per tile: the tile is listed
// unless no foreground pixel with light and none with shadow lie within a reach that bounds
// shadows.isg's own (shadows_isg_io.h, ShadowsIsgListPush); a tile left out is marked cheap, as
// shadows.isg would mark it, and keeps the hard shadow copied into L.softshadow. No output
// depends on the order of the list.
#extension GL_GOOGLE_include_directive : require
#include "shadows_isg_io.h"
layout(local_size_x = SHADOWS_ISG_LIST_LOCAL) in;
layout(binding = 0) uniform samplerBuffer pack;  // P − eye, L.shadow (shadows.isg.tiles)
layout(std430, binding = 1) buffer Tiles { uint tiles[]; };
layout(push_constant) uniform Push { ShadowsIsgListPush pc; };

void main() {
  uint tiles_x = (pc.width + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
  uint tiles_y = (pc.height + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
  uint nt = tiles_x * tiles_y, t = gl_GlobalInvocationID.x;
  if (t >= nt) return;
  ivec2 t0 = ivec2(t % tiles_x, t / tiles_x) * SHADOWS_ISG_TILE;
  bool listed = true;
  float d_max = uintBitsToFloat(tiles[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_DMAX]);
  if ((pc.flags & SHADOWS_ISG_TILE_SKIP) != 0u) {
    // The foreground's smallest distance to the light and camera depth, as shadows.isg's
    // receiver() forms them.
    vec3 light = vec3(pc.light_x, pc.light_y, pc.light_z), depth = vec3(pc.r20, pc.r21, pc.r22);
    float D = 1e30, z = 1e30;
    ivec2 end = min(t0 + SHADOWS_ISG_TILE, ivec2(pc.width, pc.height));
    for (int y = t0.y; y < end.y; ++y)
      for (int x = t0.x; x < end.x; ++x) {
        vec4 T = texelFetch(pack, y * int(pc.width) + x);
        if (!(T.w > 0.5 * SHADOWS_ISG_BACKGROUND)) continue;
        D = min(D, length(light - T.xyz));
        z = min(z, max(-dot(depth, T.xyz), 1e-6));
      }
    // Eq. 8 grows with d and falls with D; the footprint is at least z / f_px / the stretch.
    float bound = 0.0;
    if (d_max > 0.0 && z < 1e30) {
      float Rs = pc.light_size * d_max / max(D - d_max, SHADOWS_ISG_MIN_GAP * D);
      bound = min(1.01 * Rs * pc.f_px * SHADOWS_ISG_MAX_STRETCH / z, pc.max_radius);
    }
    int reach = int(ceil(bound)) + 2;  // shadows.isg's is ceil(R_p) + 1
    ivec2 lo = max((t0 - reach) / SHADOWS_ISG_TILE, ivec2(0));
    ivec2 hi = min((t0 + SHADOWS_ISG_TILE - 1 + reach) / SHADOWS_ISG_TILE,
                   ivec2(tiles_x - 1u, tiles_y - 1u));
    uint flags = 0u;
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) flags |= tiles[uint(y) * tiles_x + uint(x)];
    listed = flags == (SHADOWS_ISG_FLAG_LIT | SHADOWS_ISG_FLAG_SHADOW);
  }
  if (listed) {
    uint k = atomicAdd(tiles[SHADOWS_ISG_AT_COUNT(nt)], 1u);
    tiles[SHADOWS_ISG_AT_LIST(nt) + k] = t;
    // The dispatch is tiles_x wide: a row of workgroups per tiles_x entries begun.
    if (k % tiles_x == 0u) atomicAdd(tiles[SHADOWS_ISG_AT_ARGS(nt) + 1u], 1u);
  } else {
    tiles[2u * nt + t] = 1u;
  }
}
