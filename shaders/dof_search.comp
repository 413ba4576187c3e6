#version 450
#extension GL_GOOGLE_include_directive : require
// dof.search (method isg): the parameter search of §3.3 with the range function of eq. 16,
// softened with smoothstep: the gather radius R_g is the average CoC of the samples whose
// aperture reaches this pixel; a sample behind it and blurrier (eq. 16's first case) is hidden
// by this pixel, so it counts with this pixel's own CoC.
#include "dof_search_io.h"
layout(local_size_x = DOF_LOCAL, local_size_y = DOF_LOCAL) in;
layout(binding = 0) uniform samplerBuffer coc_buf;
layout(binding = 1) uniform samplerBuffer tiles;
layout(std430, binding = 2) writeonly buffer Radius { float radius[]; };
layout(push_constant) uniform Push { DofPush pc; };
#define DOF_HAS_COC
#include "dof_common.h"

void main() {
  dof_fill_lattice();
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint i = p.y * pc.width + p.x;
  float c0 = texelFetch(coc_buf, int(i)).r;
  uint t = 4u * ((p.y / DOF_TILE) * pc.tiles_x + p.x / DOF_TILE);
  if (texelFetch(tiles, int(t + 3u)).r != 0.0) { radius[i] = abs(c0); return; }
  float R_s = max(texelFetch(tiles, int(t + 2u)).r, 0.5);  // the farthest any CoC reaching this tile spreads
  float a = isg_pixel_angle(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16));
  mat2 rot = mat2(cos(a), sin(a), -sin(a), cos(a));
  vec2 p0 = vec2(p) + 0.5;
  float sw = 1.0, sv = abs(c0);
  for (uint k = 0u; k < pc.grid * pc.grid; ++k) {
    vec2 d = R_s * dof_stretch(rot * dof_lattice[k]);
    float ci = dof_fetch_coc(p0 + d);
    // The aperture image is upright behind the focal plane and inverted in front of it.
    float reach = dof_cover(ci >= 0.0 ? -d : d, abs(ci), DOF_BLADES, pc.rotation);
    float w = dof_cover(d, R_s, DOF_BLADES, pc.rotation) * reach;
    float hidden = smoothstep(0.0, 1.0, ci - c0) * smoothstep(0.0, 1.0, abs(ci) - abs(c0));
    sv += w * mix(abs(ci), abs(c0), hidden);
    sw += w;
  }
  radius[i] = sv / sw;
}
