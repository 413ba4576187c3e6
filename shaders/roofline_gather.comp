#version 450
// The roofline (issue 18): a plain cross-bilateral gather, the least a gather pass can do per
// tap (one 16-byte texel read through a texel view, one exp range weight, four multiply-adds),
// so its taps/s is the yardstick for the isg gathers on the same device.
// lib/roofline/roofline.cpp mirrors it in double.
#extension GL_GOOGLE_include_directive : require
#include "roofline_gather_io.h"
#include "isg_sampling.h"
layout(local_size_x = ROOFLINE_LOCAL_X, local_size_y = ROOFLINE_LOCAL_Y) in;
// Integer offsets (a concentric-disk lattice already scaled by the radius and rounded on the
// host): the reference then reads exactly the texels this shader reads, whatever the device's
// float rounding. Both inputs are texel views (gpu.h's Slot::texels): (x, y) as two uints, and
// rgb + depth.
layout(binding = 0) uniform usamplerBuffer offsets;
layout(binding = 1) uniform samplerBuffer src;
layout(std430, binding = 2) writeonly restrict buffer Dst { vec4 dst[]; };
layout(push_constant) uniform Push { RooflinePush pc; };

void main() {
  uvec2 u = gl_GlobalInvocationID.xy;
  if (u.x >= pc.width || u.y >= pc.height) return;
  ivec2 p = ivec2(u);
  int w = int(pc.width);
  ivec2 hi = ivec2(w - 1, int(pc.height) - 1);
  // Per-pixel rotation as one of the lattice's 8 symmetries (swap, flip x, flip y): it spreads
  // neighbouring pixels' reads as the isg gathers' rotations do, with integer arithmetic only.
  uint h = isg_pixel_hash(u.x, u.y) >> 29;
  bool swap = (h & 1u) != 0u;
  ivec2 s = ivec2((h & 2u) != 0u ? -1 : 1, (h & 4u) != 0u ? -1 : 1);
  float z0 = texelFetch(src, p.y * w + p.x).w;
  vec4 acc = vec4(0.0);
  for (uint k = 0u; k < pc.taps; ++k) {
    ivec2 o = ivec2(texelFetch(offsets, int(k)).xy);
    o = (swap ? o.yx : o) * s;
    ivec2 q = clamp(p + o, ivec2(0), hi);
    vec4 t = texelFetch(src, q.y * w + q.x);
    float d = t.w - z0;
    float wt = exp(-d * d * pc.falloff);
    acc += vec4(t.rgb * wt, wt);
  }
  // The lattice holds the centre (odd grid), so acc.w >= 1.
  dst[p.y * w + p.x] = vec4(acc.rgb / acc.w, acc.w);
}
