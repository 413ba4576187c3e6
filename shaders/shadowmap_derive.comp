#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_derive_io.h"
// L.shadow and L.occluder from the light's shadow map, for method isg when the renderer wrote
// neither (or no occluder distances): the hard test at the receiver's texel, with the same
// receiver-plane bias as the filtering passes, and the occluder distance along the ray to the
// light's centre. Planar light depth grows linearly along that ray, so a blocker at depth z_b
// over a receiver at depth d lies |P − light|·(d − z_b)/d from P (paper §3.1: d_occluder).
// The blocker taken is the nearest to the receiver among the 3×3 texels around it, so pixels
// the renderer shadows at a texel's edge still find their occluder.
layout(local_size_x = SHADOWMAP_LOCAL, local_size_y = SHADOWMAP_LOCAL) in;
layout(std430, binding = 0) readonly buffer Prm { ShadowmapParams p_in; };
ShadowmapParams p;  // p_in, copied once at the top of main
layout(binding = 1) uniform samplerBuffer geo;
layout(binding = 2) uniform samplerBuffer fg_in;
layout(binding = 3) uniform samplerBuffer smap;
layout(std430, binding = 4) buffer Shadow { float shadow[]; };
layout(std430, binding = 5) writeonly buffer Occ { float occ[]; };
layout(push_constant) uniform Push { ShadowmapDerivePush pc; };
#include "shadowmap_common.h"

void main() {
  p = p_in;
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= pc.width || px.y >= pc.height) return;
  uint i = px.y * pc.width + px.x;
  float lit = 1.0, d_occ = 0.0;
  if (texelFetch(fg_in, int(i)).r != 0.0) {
    vec3 P = sm_rel(i);  // P − light
    vec3 q = sm_project(P);
    bool back = false;
    vec4 g = vec4(0.0, 0.0, 0.0, p.slope_max);
    if (sm_inside(q)) g = sm_receiver_plane(px, q, P, back);
    if (sm_inside(q) && !back) {
      float texel_world = sm_texel_world(q.z);
      vec2 c0 = floor(q.xy) + 0.5;
      lit = sm_fetch(c0) >= sm_threshold(q, g, c0, texel_world) ? 1.0 : 0.0;
      float zb = -1.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          vec2 c = c0 + vec2(dx, dy);
          if (c.x < 0.0 || c.y < 0.0 || c.x >= float(p.map_w) || c.y >= float(p.map_h)) continue;
          float zm = sm_fetch(c);
          if (zm < sm_threshold(q, g, c, texel_world)) zb = max(zb, zm);
        }
      if (zb > 0.0) d_occ = sm_occluder_distance(P, q.z, zb);
    }
  }
  if (pc.write_shadow != 0u) shadow[i] = lit;
  occ[i] = d_occ;
}
