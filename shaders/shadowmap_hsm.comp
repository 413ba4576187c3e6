#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_vssm_io.h"
// Min-max hierarchical shadow map (thesis §7.5.1, mipmap variant): level 0 holds (z, z) of the
// map clamped to far_z; each level above the min and max of the up to 2x2 texels below.
layout(local_size_x = HSM_LOCAL, local_size_y = HSM_LOCAL) in;
layout(std430, binding = 0) readonly buffer Smap { float smap[]; };
layout(std430, binding = 1) buffer Hsm { vec2 hsm[]; };
layout(push_constant) uniform Push { HsmPush pc; };

void main() {
  uvec2 d = gl_GlobalInvocationID.xy;
  if (d.x >= pc.dst_w || d.y >= pc.dst_h) return;
  if (pc.from_map != 0u) {
    float z = min(smap[d.y * pc.dst_w + d.x], pc.far_z);
    hsm[pc.dst_off + d.y * pc.dst_w + d.x] = vec2(z);
    return;
  }
  vec2 r = vec2(1e30, -1e30);
  for (uint y = 2u * d.y; y < min(2u * d.y + 2u, pc.src_h); ++y)
    for (uint x = 2u * d.x; x < min(2u * d.x + 2u, pc.src_w); ++x) {
      vec2 c = hsm[pc.src_off + y * pc.src_w + x];
      r = vec2(min(r.x, c.x), max(r.y, c.y));
    }
  hsm[pc.dst_off + d.y * pc.dst_w + d.x] = r;
}
