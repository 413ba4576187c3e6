#version 450
#extension GL_GOOGLE_include_directive : require
// dof.gather (method isg): eq. 4 over radius R_g with the aperture as the spatial weight and the
// range function of eq. 17, softened: a sample in front of this pixel and sharper (an in-focus
// object before a blurry background) only counts inside its own CoC.
#include "dof_gather_io.h"
layout(local_size_x = DOF_LOCAL, local_size_y = DOF_LOCAL) in;
layout(binding = 0) uniform samplerBuffer src_buf;  // dof.input, RGBA texels (texel views)
layout(binding = 1) uniform samplerBuffer coc_buf;
layout(binding = 2) uniform samplerBuffer tiles;
layout(binding = 3) uniform samplerBuffer radius;
layout(std430, binding = 4) writeonly buffer Composite { float C[]; };
layout(push_constant) uniform Push { DofPush pc; };
#define DOF_HAS_COC
#define DOF_HAS_SRC
#include "dof_common.h"

void main() {
  dof_fill_lattice();
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint n = pc.width * pc.height;
  uint i = p.y * pc.width + p.x;
  float c0 = texelFetch(coc_buf, int(i)).r;
  uint t = 4u * ((p.y / DOF_TILE) * pc.tiles_x + p.x / DOF_TILE);
  float a = isg_pixel_angle(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16));
  vec4 out_c;
  if (texelFetch(tiles, int(t + 3u)).r != 0.0) {
    out_c = dof_cheap(p, c0, a, pc.grid);
  } else {
    float R_g = texelFetch(radius, int(i)).r;
    mat2 rot = mat2(cos(a), sin(a), -sin(a), cos(a));
    vec2 p0 = vec2(p) + 0.5;
    vec4 c_0 = dof_src(i);
    vec4 s = c_0;
    float ws = 1.0;
    for (uint k = 0u; k < pc.grid * pc.grid; ++k) {
      vec2 d = R_g * dof_stretch(rot * dof_lattice[k]);
      float ci = dof_fetch_coc(p0 + d);
      float own = dof_cover(ci >= 0.0 ? -d : d, abs(ci), DOF_BLADES, pc.rotation);
      float front_sharper = smoothstep(0.0, 1.0, c0 - ci) * smoothstep(0.0, 1.0, abs(c0) - abs(ci));
      float w = dof_cover(d, R_g, DOF_BLADES, pc.rotation) * mix(1.0, own, front_sharper);
      s += w * dof_fetch_src(p0 + d);
      ws += w;
    }
    out_c = mix(c_0, s / ws, smoothstep(0.25, 0.75, R_g));
  }
  for (uint k = 0u; k < 4u; ++k) C[k * n + i] = out_c[k];
}
