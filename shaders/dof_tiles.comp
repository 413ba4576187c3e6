#version 450
#extension GL_GOOGLE_include_directive : require
// dof.tiles: per 16x16 tile, the min/max signed CoC and the largest |CoC| of every pixel whose
// aperture reaches the tile; tiles with a CoC range under half a pixel take the cheap path.
// One workgroup per tile: its DOF_LOCAL^2 lanes stride over the tile's window (adjacent lanes
// read adjacent pixels) and reduce in shared memory; min and max do not depend on the order,
// so the result is the reference's (dof_tiles_reference) bit for bit.
#include "dof_tiles_io.h"
layout(local_size_x = DOF_LOCAL, local_size_y = DOF_LOCAL) in;
layout(binding = 0) uniform samplerBuffer coc;  // a texel view (gpu.h's Slot::texels)
layout(std430, binding = 1) writeonly buffer Tiles { float tiles[]; };
layout(push_constant) uniform Push { DofPush pc; };

const uint N = DOF_LOCAL * DOF_LOCAL;
shared float s_min[N], s_max[N], s_r[N];

void main() {
  uvec2 t = gl_WorkGroupID.xy;
  uint lane = gl_LocalInvocationIndex;
  int x0 = int(t.x) * DOF_TILE, y0 = int(t.y) * DOF_TILE;
  int x1 = min(x0 + DOF_TILE, int(pc.width)) - 1, y1 = min(y0 + DOF_TILE, int(pc.height)) - 1;
  int m = int(pc.margin);
  float cmin = 1e30, cmax = -1e30, rmax = 0.0;
  if (t.x < pc.tiles_x && t.y < pc.tiles_y) {
    int ya = max(y0 - m, 0), yb = min(y1 + m, int(pc.height) - 1);
    int xa = max(x0 - m, 0), xb = min(x1 + m, int(pc.width) - 1);
    for (int y = ya + int(gl_LocalInvocationID.y); y <= yb; y += DOF_LOCAL) {
      int dy = max(max(y0 - y, y - y1), 0);
      for (int x = xa + int(gl_LocalInvocationID.x); x <= xb; x += DOF_LOCAL) {
        float c = texelFetch(coc, y * int(pc.width) + x).r;
        int dx = max(max(x0 - x, x - x1), 0);
        float reach = (abs(c) + 1.0) * max(pc.stretch_x, pc.stretch_y);  // a stretched aperture's bound
        if (float(dx * dx + dy * dy) > reach * reach) continue;
        cmin = min(cmin, c);
        cmax = max(cmax, c);
        rmax = max(rmax, abs(c));
      }
    }
  }
  s_min[lane] = cmin;
  s_max[lane] = cmax;
  s_r[lane] = rmax;
  barrier();
  for (uint s = N / 2u; s > 0u; s >>= 1u) {
    if (lane < s) {
      s_min[lane] = min(s_min[lane], s_min[lane + s]);
      s_max[lane] = max(s_max[lane], s_max[lane + s]);
      s_r[lane] = max(s_r[lane], s_r[lane + s]);
    }
    barrier();
  }
  if (lane != 0u || t.x >= pc.tiles_x || t.y >= pc.tiles_y) return;
  uint o = 4u * (t.y * pc.tiles_x + t.x);
  tiles[o] = s_min[0];
  tiles[o + 1u] = s_max[0];
  tiles[o + 2u] = s_r[0];
  tiles[o + 3u] = (pc.tile_skip != 0u && s_max[0] - s_min[0] < DOF_CHEAP_RANGE) ? 1.0 : 0.0;
}
