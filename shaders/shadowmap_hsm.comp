#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_hsm_io.h"
// Min-max hierarchical shadow map (thesis §7.5.1, mipmap variant): level 0 is the map (z
// clamped to far_z, not stored); each level above holds the min and max of the up to 2x2
// texels below (from_map: level 1, from the map itself).
layout(local_size_x = HSM_LOCAL, local_size_y = HSM_LOCAL) in;
layout(std430, binding = 0) readonly buffer Smap { float smap[]; };
layout(std430, binding = 1) buffer Hsm { vec2 hsm[]; };
layout(push_constant) uniform Push { HsmPush pc; };

void main() {
  uvec2 d = gl_GlobalInvocationID.xy;
  if (d.x >= pc.dst_w || d.y >= pc.dst_h) return;
  vec2 r = vec2(1e30, -1e30);
  for (uint y = 2u * d.y; y < min(2u * d.y + 2u, pc.src_h); ++y)
    for (uint x = 2u * d.x; x < min(2u * d.x + 2u, pc.src_w); ++x) {
      vec2 c = pc.from_map != 0u ? vec2(min(smap[y * pc.src_w + x], pc.far_z))
                                 : hsm[pc.src_off + y * pc.src_w + x];
      r = vec2(min(r.x, c.x), max(r.y, c.y));
    }
  hsm[pc.dst_off + d.y * pc.dst_w + d.x] = r;
}
