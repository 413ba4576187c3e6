#version 450
#extension GL_GOOGLE_include_directive : require
#include "sat_io.h"
// In-place inclusive prefix sums along rows (axis 0) or columns (axis 1), one workgroup a
// line: each invocation sums its chunk, the chunk sums are scanned in shared memory
// (Hillis-Steele), then each chunk is rewritten from its offset. 64-bit adds with carry.
// A stack of width x height tables, one after the other, is scanned by one dispatch: the
// workgroup's y index picks the table (0 for a single table).
layout(local_size_x = SAT_LOCAL, local_size_y = 1) in;
layout(std430, binding = 0) buffer Sat { uvec2 sat[]; };
layout(push_constant) uniform Push { SatPush pc; };
shared uvec2 part[SAT_LOCAL];

uvec2 add64(uvec2 a, uvec2 b) {
  uint c;
  uint lo = uaddCarry(a.x, b.x, c);
  return uvec2(lo, a.y + b.y + c);
}

void main() {
  uint line = gl_WorkGroupID.x, t = gl_LocalInvocationID.x;
  uint len = pc.axis == 0u ? pc.width : pc.height;
  uint lines = pc.axis == 0u ? pc.height : pc.width;
  bool live = line < lines;
  uint chunk = (len + SAT_LOCAL - 1u) / SAT_LOCAL;
  uint b = min(t * chunk, len), e = min(b + chunk, len);
  uint base = gl_WorkGroupID.y * pc.width * pc.height + (pc.axis == 0u ? line * pc.width : line);
  uint stride = pc.axis == 0u ? 1u : pc.width;
  uvec2 s = uvec2(0u);
  if (live)
    for (uint j = b; j < e; ++j) s = add64(s, sat[base + j * stride]);
  part[t] = s;
  barrier();
  for (uint off = 1u; off < SAT_LOCAL; off <<= 1u) {
    uvec2 v = t >= off ? part[t - off] : uvec2(0u);
    barrier();
    part[t] = add64(part[t], v);
    barrier();
  }
  if (!live) return;
  uvec2 run = t > 0u ? part[t - 1u] : uvec2(0u);
  for (uint j = b; j < e; ++j) {
    run = add64(run, sat[base + j * stride]);
    sat[base + j * stride] = run;
  }
}
