#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#include "shadowmap_io.h"
// PCSS (thesis §2.4.2): blocker search over the region a blocker as near as the map's nearest
// depth could shadow the receiver from, then PCF over the penumbra width
// w = (d_receiver − d_blocker)·w_light/d_blocker, in map texels at the receiver's depth; the
// filter's blockers only those the light's cone from the receiver reaches (sm_reaches); the
// input's L.shadow where the penumbra is a few texels or narrower (sm_input_edges).
// The blocker search narrowed (issue 19, shadows.pcss_narrow passes; 0: the thesis's single
// search): the first search covers the cone of the nearest depth anywhere in the map, and its
// taps' mean depth takes in blockers no cone from the receiver reaches. Each pass searches again,
// with the same taps, over the disk of the cone at the mean found so far (PCSS_NARROW_MARGIN times
// wider), while it shrinks: where it finds no blocker the receiver is lit, else its mean is the
// new one. Ratio to doing nothing's RMSE (32 taps), 0 -> 1 pass: own Cycles cases grazing 0.43 ->
// 0.35, lowlight 0.35 -> 0.27, overlap 0.31 -> 0.23, grazing-sm4096 0.36 -> 0.24; shared contact
// 0.23 -> 0.21, rowdepth 0.24 -> 0.19. Margin 1.25 and 1.75: lowlight 0.26, 0.27; overlap 0.22,
// 0.24; rowdepth 0.18, 0.20; 2 passes at 1.5: lowlight 0.25, overlap 0.22, but isg-synth contact
// (whose L.shadow is not antialiased: a narrower penumbra hands its edge to the input) 6 % worse
// at 16 taps, against 2 % with 1.
layout(local_size_x = SHADOWMAP_LOCAL, local_size_y = SHADOWMAP_LOCAL) in;
layout(std430, binding = 0) readonly buffer Prm { ShadowmapParams p_in; };
ShadowmapParams p;  // p_in, copied once at the top of main
layout(binding = 1) uniform samplerBuffer geo;
layout(binding = 2) uniform samplerBuffer fg_in;
layout(binding = 3) uniform samplerBuffer hard;
layout(binding = 4) uniform samplerBuffer smap;
layout(binding = 5) uniform samplerBuffer taps;
layout(std430, binding = 6) writeonly buffer Soft { float soft[]; };
layout(std430, binding = 7) buffer Stats { uint stats[]; };
layout(push_constant) uniform Push { ShadowmapPush pc; };
#define SHADOWMAP_COUNTS
#include "shadowmap_common.h"

// The blocker search over the disk of radius rs (the taps turned by rot): whether it finds
// blockers, their mean depth in db.
bool pcss_search(vec3 q, vec4 g, float texel_world, mat2 rot, float rs, out float db) {
  float sum = 0.0;
  uint cnt = 0u;
  for (uint t = 0u; t < p.taps; ++t) {
    vec2 c = floor(q.xy + rot * texelFetch(taps, int(t)).xy * rs) + 0.5;
    if (c.x < 0.0 || c.y < 0.0 || c.x >= float(p.map_w) || c.y >= float(p.map_h)) continue;
    float zm = sm_fetch(c);
    if (zm < sm_threshold(q, g, c, texel_world)) { sum += zm; ++cnt; }
  }
  db = cnt > 0u ? sum / float(cnt) : 0.0;
  return cnt > 0u;
}

void main() {
  p = p_in;
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= pc.width || px.y >= pc.height) return;
  uint i = px.y * pc.width + px.x;
  if (texelFetch(fg_in, int(i)).r == 0.0) { soft[i] = texelFetch(hard, int(i)).r; return; }
  vec3 P = sm_rel(i);  // P − light
  vec3 q = sm_project(P);
  if (!sm_inside(q)) { soft[i] = texelFetch(hard, int(i)).r; return; }
  sm_count(SHADOWMAP_STAT_PIXELS);
  bool back;
  vec4 g = sm_receiver_plane(px, q, P, back);
  if (back) { sm_count(SHADOWMAP_STAT_SKIPPED); soft[i] = texelFetch(hard, int(i)).r; return; }
  float texel_world = sm_texel_world(q.z);
  float k = sm_k();  // texels per unit of w(d) − w(z) (1/d − 1/z; a sun: z − d)
  float a = 0.0;
  if (p.rotate != 0u) a = isg_pixel_angle(px + uvec2(p.origin & 0xffffu, p.origin >> 16));
  mat2 rot = mat2(cos(a), sin(a), -sin(a), cos(a));
  float rs = sm_cone_radius(k, p.min_depth, q.z, 1.0);
  float db;
  bool found = pcss_search(q, g, texel_world, rot, rs, db);
  // Narrowed to the blockers' cone, while it shrinks (the top of the file).
  for (uint pass = 0u; found && pass < p.pcss_narrow; ++pass) {
    float rn = sm_cone_radius(k, db, q.z, PCSS_NARROW_MARGIN);
    if (rn >= rs) break;
    found = pcss_search(q, g, texel_world, rot, rn, db);
    rs = rn;
  }
  if (!found) {
    sm_count(SHADOWMAP_STAT_SKIPPED);
    soft[i] = sm_input_edges(1.0, texelFetch(hard, int(i)).r, 0.0);
    return;
  }
  float rf = k * sm_gap(db, q.z);
  if (rf > p.max_radius) { rf = p.max_radius; sm_count(SHADOWMAP_STAT_CLAMPED); }
  float lit = 0.0, all = 0.0;
  for (uint t = 0u; t < p.taps; ++t) {
    vec2 u = rot * texelFetch(taps, int(t)).xy;
    float wt = sm_irradiance(P, u);
    all += wt;
    vec2 c = floor(q.xy + u * rf) + 0.5;
    if (c.x < 0.0 || c.y < 0.0 || c.x >= float(p.map_w) || c.y >= float(p.map_h)) { lit += wt; continue; }
    float zm = sm_fetch(c);
    if (zm >= sm_threshold(q, g, c, texel_world) || !sm_reaches(q, c, zm, p.reach * k)) lit += wt;
  }
  soft[i] = sm_input_edges(all > 0.0 ? lit / all : 1.0, texelFetch(hard, int(i)).r, rf);
}
