#version 450
#extension GL_GOOGLE_include_directive : require
#include "sat_io.h"
layout(local_size_x = SAT_LOCAL, local_size_y = 1) in;
layout(std430, binding = 0) readonly buffer Src { float src[]; };
layout(std430, binding = 1) writeonly buffer Sat { uvec2 sat[]; };
layout(push_constant) uniform Push { SatPush pc; };

void main() {
  uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
  if (x >= pc.width || y >= pc.height) return;
  uint i = y * pc.width + x;
  precise float v = min(src[i], pc.far_z) - pc.shift;
  precise float w = pc.power == 2u ? v * v : v;
  precise float d = (w - pc.offset) * pc.scale;
  int q = int(floor(d + 0.5));
  sat[i] = uvec2(uint(q), q < 0 ? 0xffffffffu : 0u);
}
