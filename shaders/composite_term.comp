#version 450
#extension GL_GOOGLE_include_directive : require
#include "composite_term_io.h"
layout(local_size_x = COMPOSITE_TERM_LOCAL, local_size_y = COMPOSITE_TERM_LOCAL) in;
layout(std430, binding = 0) buffer Composite { float C[]; };
layout(std430, binding = 1) readonly buffer Weight { float W[]; };
layout(std430, binding = 2) readonly buffer X { float X_[]; };
layout(std430, binding = 3) readonly buffer Y { float Y_[]; };
layout(std430, binding = 4) readonly buffer Fg { float fg[]; };
layout(push_constant) uniform Push { CompositeTermPush pc; };

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint i = p.y * pc.width + p.x;
  if (fg[i] == 0.0) return;  // background is left untouched
  uint n = pc.width * pc.height;
  for (uint c = 0u; c < 3u; ++c) {
    uint xc = pc.x_planes == 1u ? 0u : c;
    C[c * n + i] += W[c * n + i] * (X_[xc * n + i] - Y_[xc * n + i]);
  }
}
