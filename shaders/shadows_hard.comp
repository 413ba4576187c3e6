#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadows_hard_io.h"
layout(local_size_x = SHADOWS_HARD_LOCAL, local_size_y = SHADOWS_HARD_LOCAL) in;
layout(std430, binding = 0) readonly buffer Shadow { float shadow_in[]; };
layout(std430, binding = 1) writeonly buffer Soft { float soft[]; };
layout(push_constant) uniform Push { ShadowsHardPush pc; };

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint i = p.y * pc.width + p.x;
  soft[i] = shadow_in[i];
}
