#version 450
#extension GL_GOOGLE_include_directive : require
// dof.coc: eq. 15, the signed circle of confusion in pixels (near negative, far positive), and a
// copy of the composite for the gathers to read while they write the composite, as one RGBA
// texel a pixel (a bilinear tap is four 16-byte loads, not sixteen scattered floats; issue 18).
#include "dof_coc_io.h"
#include "isg_texels.h"
layout(local_size_x = DOF_LOCAL, local_size_y = DOF_LOCAL) in;
layout(binding = 0) uniform samplerBuffer C;
layout(binding = 1) uniform samplerBuffer depth;
layout(std430, binding = 2) writeonly buffer Coc { float coc[]; };
layout(std430, binding = 3) writeonly buffer Src { vec4 src[]; };
layout(push_constant) uniform Push { DofPush pc; };

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint n = pc.width * pc.height;
  uint i = p.y * pc.width + p.x;
  float z = texelFetch(depth, int(i)).r;
  bool bg = z <= 0.0 || z >= ISG_BACKGROUND_DEPTH || (pc.has_alpha != 0u && isg_at(C, 3u * n + i) == 0.0);
  // Background blurs like a point at infinity: c -> c_inf.
  float c = bg ? pc.c_inf : pc.c_inf * (z - pc.z_f) / z;
  coc[i] = clamp(c, -pc.max_coc, pc.max_coc);
  src[i] = isg_at4(C, i, n);
}
