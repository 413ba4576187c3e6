#version 450
#extension GL_GOOGLE_include_directive : require
#include "composite_term_io.h"
#include "isg_texels.h"
layout(local_size_x = COMPOSITE_TERM_LOCAL, local_size_y = COMPOSITE_TERM_LOCAL) in;
layout(std430, binding = 0) buffer Composite { float C[]; };
layout(binding = 1) uniform samplerBuffer W;
layout(binding = 2) uniform samplerBuffer X_;
layout(binding = 3) uniform samplerBuffer Y_;
layout(binding = 4) uniform samplerBuffer fg;
layout(push_constant) uniform Push { CompositeTermPush pc; };

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint i = p.y * pc.width + p.x;
  if (texelFetch(fg, int(i)).r == 0.0) return;  // background is left untouched
  uint n = pc.width * pc.height;
  for (uint c = 0u; c < 3u; ++c) {
    uint xc = pc.x_planes == 1u ? 0u : c;
    C[c * n + i] += isg_at(W, c * n + i) * (isg_at(X_, xc * n + i) - isg_at(Y_, xc * n + i));
  }
}
