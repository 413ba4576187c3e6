// GLSL helpers shared by the dof passes; lib/effects/dof/dof.cpp mirrors each one in double.
// Include after declaring `coc_buf` (signed CoC) and, for colour, `src_buf` (RGBA texels), both
// texel views (samplerBuffer: gpu.h's Slot::texels).
#ifndef DOF_COMMON_H
#define DOF_COMMON_H
#include "dof_io.h"
#include "isg_sampling.h"
#include "isg_texels.h"
const float DOF_PI = 3.14159265358979;
// The aperture's blades (0: a disk, else an n-blade polygon): a specialization constant
// (gpu::Kernel), so a disk's taps do not pay for the polygon's atan and cos.
layout(constant_id = 0) const uint DOF_BLADES = 0u;

// The sample lattice through the concentric map, evaluated once per workgroup rather than once
// per tap (issue 18). Call at the top of main, before any invocation returns.
shared vec2 dof_lattice[DOF_MAX_LATTICE];
void dof_fill_lattice_of(uint grid) {
  for (uint k = gl_LocalInvocationIndex; k < grid * grid; k += gl_WorkGroupSize.x * gl_WorkGroupSize.y)
    dof_lattice[k] = isg_concentric(k, grid);
  barrier();
}
void dof_fill_lattice() { dof_fill_lattice_of(pc.grid); }


// dof.anamorphic: the aperture stretched to s times as tall as wide at the same area (an
// anamorphic lens's oval bokeh). dof_stretch maps the unit disk's lattice onto it; dof_norm
// measures an offset in the unstretched aperture.
vec2 dof_stretch(vec2 u) { return vec2(u.x * pc.stretch_x, u.y * pc.stretch_y); }
float dof_reach_scale() { return max(pc.stretch_x, pc.stretch_y); }

// Aperture "norm": |v| for a disk, |v| / rho(angle) for an n-gon of circumradius 1, so a point
// lies inside the aperture of radius r when dof_norm(v) <= r (after undoing the stretch).
float dof_norm(vec2 v, uint blades, float rotation) {
  v = vec2(v.x / pc.stretch_x, v.y / pc.stretch_y);
  float len = length(v);
  if (blades < 3u || len == 0.0) return len;
  float seg = 2.0 * DOF_PI / float(blades);
  float phi = atan(v.y, v.x) - rotation;
  float t = phi - seg * floor(phi / seg) - 0.5 * seg;
  return len * cos(t) / cos(DOF_PI / float(blades));
}

// Antialiased inside test of offset v in an aperture of radius r (one-pixel ramp).
float dof_cover(vec2 v, float r, uint blades, float rotation) {
  return clamp(r - dof_norm(v, blades, rotation) + 0.5, 0.0, 1.0);
}

// Aperture area per unit radius squared.
float dof_area_factor(uint blades) {
  if (blades < 3u) return DOF_PI;
  return 0.5 * float(blades) * sin(2.0 * DOF_PI / float(blades));
}

// Bilinear weights and clamped texel indices for position q (pixel centres at +0.5).
void dof_taps(vec2 q, uint w, uint h, out uint i00, out uint i10, out uint i01, out uint i11,
              out vec2 f) {
  vec2 x = q - 0.5;
  vec2 x0 = floor(x);
  f = x - x0;
  int xa = clamp(int(x0.x), 0, int(w) - 1), xb = clamp(int(x0.x) + 1, 0, int(w) - 1);
  int ya = clamp(int(x0.y), 0, int(h) - 1), yb = clamp(int(x0.y) + 1, 0, int(h) - 1);
  i00 = uint(ya) * w + uint(xa); i10 = uint(ya) * w + uint(xb);
  i01 = uint(yb) * w + uint(xa); i11 = uint(yb) * w + uint(xb);
}

#ifdef DOF_HAS_COC
float dof_fetch_coc(vec2 q) {
  uint a, b, c, d; vec2 f;
  dof_taps(q, pc.width, pc.height, a, b, c, d, f);
  return mix(mix(isg_at(coc_buf, a), isg_at(coc_buf, b), f.x), mix(isg_at(coc_buf, c), isg_at(coc_buf, d), f.x),
             f.y);
}
#endif
#ifdef DOF_HAS_SRC
vec4 dof_fetch_src(vec2 q) {
  uint a, b, c, d; vec2 f;
  dof_taps(q, pc.width, pc.height, a, b, c, d, f);
  vec4 ta = texelFetch(src_buf, int(a)), tb = texelFetch(src_buf, int(b));
  vec4 tc = texelFetch(src_buf, int(c)), td = texelFetch(src_buf, int(d));
  return mix(mix(ta, tb, f.x), mix(tc, td, f.x), f.y);
}
vec4 dof_src(uint i) { return texelFetch(src_buf, int(i)); }
// The cheap path (tiles whose CoC range is under DOF_CHEAP_RANGE): a plain aperture average of
// radius |c0| over the workgroup's lattice of grid² samples, faded to the sharp pixel below half
// a pixel.
vec4 dof_cheap(uvec2 p, float c0, float rot_angle, uint grid) {
  vec2 p0 = vec2(p) + 0.5;
  vec4 c_0 = dof_src(p.y * pc.width + p.x);
  float r = abs(c0);
  if (r <= 0.25) return c_0;  // the fade below keeps the sharp pixel exactly: skip the gather
  mat2 rot = mat2(cos(rot_angle), sin(rot_angle), -sin(rot_angle), cos(rot_angle));
  vec4 s = c_0;
  float ws = 1.0;
  for (uint k = 0u; k < grid * grid; ++k) {
    vec2 d = r * dof_stretch(rot * dof_lattice[k]);
    float w = dof_cover(d, r, DOF_BLADES, pc.rotation);
    s += w * dof_fetch_src(p0 + d);
    ws += w;
  }
  return mix(c_0, s / ws, smoothstep(0.25, 0.75, r));
}
#endif
#endif
