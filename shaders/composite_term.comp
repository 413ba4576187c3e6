#version 450
#extension GL_GOOGLE_include_directive : require
#include "composite_term_io.h"
layout(local_size_x = COMPOSITE_TERM_LOCAL, local_size_y = COMPOSITE_TERM_LOCAL) in;
layout(std430, binding = 0) buffer Composite { float C[]; };
// Texel views of planar images (gpu.h's Slot::texels), COMPOSITE_LANE_PIXELS pixels a texel.
layout(binding = 1) uniform samplerBuffer W;
layout(binding = 2) uniform samplerBuffer X_;
layout(binding = 3) uniform samplerBuffer Y_;
layout(binding = 4) uniform samplerBuffer fg;
layout(push_constant) uniform Push { CompositeTermPush pc; };
// Specialization constants (gpu::Kernel): the planes of X and Y (1: one for every channel, or
// 3), and the pixels a lane takes, 4 where the image's pixel count is a multiple of 4 (the views
// then hold four consecutive pixels a texel; on lavapipe a lane's fixed cost is then paid once for
// four), else 1.
layout(constant_id = 0) const uint X_PLANES = 3u;
layout(constant_id = 1) const uint LANE_PIXELS = 1u;

void main() {
  uint n = pc.width * pc.height, m = n / LANE_PIXELS;  // pixels, texels a plane
  uint j = gl_GlobalInvocationID.y * COMPOSITE_TERM_ROW + gl_GlobalInvocationID.x;
  if (j >= m) return;
  vec4 f = texelFetch(fg, int(j));
  vec4 d1 = X_PLANES == 1u ? texelFetch(X_, int(j)) - texelFetch(Y_, int(j)) : vec4(0.0);
  for (uint c = 0u; c < 3u; ++c) {
    vec4 d = X_PLANES == 1u ? d1 : texelFetch(X_, int(c * m + j)) - texelFetch(Y_, int(c * m + j));
    vec4 t = texelFetch(W, int(c * m + j)) * d;
    for (uint k = 0u; k < LANE_PIXELS; ++k)  // background is left untouched
      if (f[k] != 0.0) C[c * n + j * LANE_PIXELS + k] += t[k];
  }
}
