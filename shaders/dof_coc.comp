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
  float v = texelFetch(depth, int(i)).r;  // depth, or the CoC channel (coc_source 1)
  // Depth as the file holds it, to planar depth: normalized (0 near, 1 far and beyond:
  // background) or inverse (0: infinity).
  float z = v;
  if (pc.depth_form == 1u) z = v >= 1.0 ? ISG_BACKGROUND_DEPTH : pc.depth_near + v * (pc.depth_far - pc.depth_near);
  if (pc.depth_form == 2u) z = v > 0.0 ? 1.0 / v : ISG_BACKGROUND_DEPTH;
  bool bg = z <= 0.0 || z >= ISG_BACKGROUND_DEPTH || (pc.has_alpha != 0u && isg_at(C, 3u * n + i) == 0.0);
  // Background blurs like a point at infinity: c -> c_inf.
  float c = bg ? pc.c_inf : pc.c_inf * (z - pc.z_f) / z;
  if (pc.coc_source == 1u) c = pc.c_inf * v;  // the renderer's CoC, as it is
  coc[i] = clamp(c, -pc.max_coc, pc.max_coc);
  src[i] = isg_at4(C, i, n);
}
