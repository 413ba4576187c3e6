#version 450
// Pass reflections.list: the tiles reflections.isg runs on, those with a glossy pixel (issue 18:
// on lavapipe a workgroup of reflections.isg costs about as much to start and classify itself as
// a cheap tile's work). One lane per tile; a tile left out is marked cheap (REFL_TILE_CHEAP) and
// keeps refl, copied into refl.glossy before, and (method isg) block records that hold no wide
// gather, which the pixels of the tiles around it read (reflections_isg.h's reuse). No output
// depends on the list's order.
#extension GL_GOOGLE_include_directive : require
#include "reflections_isg_io.h"
layout(local_size_x = REFL_LIST_LOCAL) in;
layout(binding = 0) uniform samplerBuffer pack_color;  // refl, dist (reflections.pack)
layout(binding = 1) uniform samplerBuffer rough;
layout(std430, binding = 2) buffer Tiles { uint tiles[]; };
layout(push_constant) uniform Push { ReflIsgPush pc; };
// Settings that choose code paths (REFL_HAS_*): compiled in, not branched on.
layout(constant_id = 0) const uint REFL_FLAGS = 0u;
layout(constant_id = 1) const uint REFL_MODE = REFL_MODE_ISG;

void main() {
  uint tiles_x = (pc.width + REFL_TILE - 1u) / REFL_TILE;
  uint nt = tiles_x * ((pc.height + REFL_TILE - 1u) / REFL_TILE), t = gl_GlobalInvocationID.x;
  if (t >= nt) return;
  ivec2 t0 = ivec2(t % tiles_x, t / tiles_x) * REFL_TILE;
  ivec2 end = min(t0 + REFL_TILE, ivec2(pc.width, pc.height));
  bool glossy = false;
  // As reflections.isg's is_glossy: something to gather, rougher than a mirror.
  for (int y = t0.y; y < end.y && !glossy; ++y)
    for (int x = t0.x; x < end.x; ++x) {
      int i = y * int(pc.width) + x;
      float r = (REFL_FLAGS & REFL_HAS_ROUGHNESS) != 0u ? texelFetch(rough, i).r : pc.roughness;
      if (texelFetch(pack_color, i).w >= 0.0 && r > REFL_MIN_ROUGHNESS) glossy = true;
    }
  if (glossy) {
    uint k = atomicAdd(tiles[REFL_AT_COUNT(nt)], 1u);
    tiles[REFL_AT_LIST(nt) + k] = t;
    // The dispatch is tiles_x wide: a row of workgroups per tiles_x entries begun.
    if (k % tiles_x == 0u) atomicAdd(tiles[REFL_AT_ARGS(nt) + 1u], 1u);
  } else {
    tiles[t] = REFL_TILE_CHEAP;
    tiles[nt + t] = 0u;
    // Its blocks' records (mean, R_s; geometry): R_s < 0, no wide gather to blend.
    if (REFL_MODE == REFL_MODE_ISG)
      for (uint b = 0u; b < REFL_BLOCKS * REFL_BLOCKS; ++b)
        tiles[REFL_AT_BLOCKS(nt) + 8u * (t * REFL_BLOCKS * REFL_BLOCKS + b) + 3u] = floatBitsToUint(-1.0);
  }
}
