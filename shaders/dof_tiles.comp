#version 450
#extension GL_GOOGLE_include_directive : require
// dof.tiles: per 16x16 tile, the min/max signed CoC and the largest |CoC| of every pixel whose
// aperture reaches the tile; tiles with a CoC range under half a pixel take the cheap path.
#include "dof_tiles_io.h"
layout(local_size_x = DOF_LOCAL, local_size_y = DOF_LOCAL) in;
layout(std430, binding = 0) readonly buffer Coc { float coc[]; };
layout(std430, binding = 1) writeonly buffer Tiles { float tiles[]; };
layout(push_constant) uniform Push { DofPush pc; };

void main() {
  uvec2 t = gl_GlobalInvocationID.xy;
  if (t.x >= pc.tiles_x || t.y >= pc.tiles_y) return;
  int x0 = int(t.x) * DOF_TILE, y0 = int(t.y) * DOF_TILE;
  int x1 = min(x0 + DOF_TILE, int(pc.width)) - 1, y1 = min(y0 + DOF_TILE, int(pc.height)) - 1;
  int m = int(pc.margin);
  float cmin = 1e30, cmax = -1e30, rmax = 0.0;
  for (int y = max(y0 - m, 0); y <= min(y1 + m, int(pc.height) - 1); ++y) {
    for (int x = max(x0 - m, 0); x <= min(x1 + m, int(pc.width) - 1); ++x) {
      float c = coc[uint(y) * pc.width + uint(x)];
      int dx = max(max(x0 - x, x - x1), 0), dy = max(max(y0 - y, y - y1), 0);
      float reach = abs(c) + 1.0;
      if (float(dx * dx + dy * dy) > reach * reach) continue;
      cmin = min(cmin, c);
      cmax = max(cmax, c);
      rmax = max(rmax, abs(c));
    }
  }
  uint o = 4u * (t.y * pc.tiles_x + t.x);
  tiles[o] = cmin;
  tiles[o + 1u] = cmax;
  tiles[o + 2u] = rmax;
  tiles[o + 3u] = (pc.tile_skip != 0u && cmax - cmin < DOF_CHEAP_RANGE) ? 1.0 : 0.0;
}
