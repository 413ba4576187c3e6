// GLSL only: what every shadowmap_* pass shares. Before including, declare the buffers
//   prm (ShadowmapParams p: the buffer's, or a copy made at the top of main), and the texel views
//   (samplerBuffer, gpu.h's Slot::texels) geo, fg_in and smap — or, where the includer defines
//   SHADOWMAP_STORAGE_BUFFERS, storage buffers (float geo[], fg_in[], smap[]).
#ifndef SHADOWMAP_COMMON_H
#define SHADOWMAP_COMMON_H
#include "isg_sampling.h"

#ifdef SHADOWMAP_STORAGE_BUFFERS
float sm_geo(uint i) { return geo[i]; }
float sm_fg(uint i) { return fg_in[i]; }
float sm_map(uint i) { return smap[i]; }
#else
float sm_geo(uint i) { return texelFetch(geo, int(i)).r; }
float sm_fg(uint i) { return texelFetch(fg_in, int(i)).r; }
float sm_map(uint i) { return texelFetch(smap, int(i)).r; }
#endif

// Every position here is relative to the light (P − light, the light's centre rounded to float):
// a world position far from the origin is never formed in float (issue 19). From P, P − light is
// exact while the two are within a factor 2 (Sterbenz); from depth, the camera-space point is
// rotated into world axes and moved by eye − light, taken in double on the host.
vec3 sm_rel(uint i) {
  uint n = p.width * p.height;
  if (p.has_position != 0u) return vec3(sm_geo(i), sm_geo(n + i), sm_geo(2u * n + i)) - vec3(p.light_x, p.light_y, p.light_z);
  float z = sm_geo(i);
  // Frame coordinates (a tile adds its origin), so a tile rounds as the whole frame does.
  float x = float(i % p.width + (p.origin & 0xffffu)) + 0.5, y = float(i / p.width + (p.origin >> 16)) + 0.5;
  vec3 c = vec3((x - p.cx) / p.f_px * z, -(y - p.cy) / p.f_px * z, -z);
  mat3 rt = mat3(p.r0, p.r3, p.r6, p.r1, p.r4, p.r7, p.r2, p.r5, p.r8);  // R^T (columns)
  return transpose(rt) * c + vec3(p.eye_rel_x, p.eye_rel_y, p.eye_rel_z);
}

// Light space of d = P − light: (u, v) in map texels (texel centres at k + 0.5, row 0 at the
// top), planar depth; l03, l13, l23 are the translation left after the light's centre was
// rounded to float (in double on the host).
// The float32 spacing of pixel i's input: of P's largest component (P far from the world origin
// carries steps of it), else of Z. Exact (from the exponent bits).
float sm_input_step(uint i) {
  uint n = p.width * p.height;
  float m = p.has_position != 0u ? max(max(abs(sm_geo(i)), abs(sm_geo(n + i))), abs(sm_geo(2u * n + i))) : abs(sm_geo(i));
  uint e = (floatBitsToUint(m) >> 23) & 0xffu;
  return e > 23u ? uintBitsToFloat((e - 23u) << 23) : 0.0;
}

// Perspective and orthographic maps as one (issue 52): w(z) is the depth measure that is linear
// over (u, v) on a plane and in which the light's cone from a receiver at depth qz has, at depth
// z, the radius k·(w(z) − w(qz)) texels (k = sm_k()). Perspective: w = 1/z and k the texels per
// unit of 1/z at the light's radius (similar triangles through the light's centre). Orthographic
// (a sun): w = −z and k = tan(half angle) / texel, the cone widening by tan of the half angle
// per unit of depth (the contract's penumbra d · 2 · tan(angle / 2)).
float sm_w(float z) { return p.ortho != 0u ? -z : 1.0 / z; }
float sm_w_inv(float w) { return p.ortho != 0u ? -w : (w > 0.0 ? 1.0 / w : 1e30); }
// The light's cone from depth qz at depth z, in units of w (0 behind the receiver).
float sm_gap(float z, float qz) { return max(sm_w(z) - sm_w(qz), 0.0); }
float sm_k() { return p.light_radius * float(p.map_h) / (2.0 * p.tan_y); }
// A map texel's size in world units at depth z.
float sm_texel_world(float z) { return 2.0 * (p.ortho != 0u ? 1.0 : z) * p.tan_y / float(p.map_h); }
// The unit direction toward the light's centre from P (relative to the light); a sun's is its
// axis (the map camera's +Z).
vec3 sm_to_light(vec3 P) { return p.ortho != 0u ? vec3(p.l20, p.l21, p.l22) : -P; }
// The distance from the receiver P (map depth qz) to a blocker at map depth zb along the ray to
// the light's centre (L.occluder's measure).
float sm_occluder_distance(vec3 P, float qz, float zb) { return p.ortho != 0u ? qz - zb : length(P) * (qz - zb) / qz; }

vec3 sm_project(vec3 d) {
  float x = p.l00 * d.x + p.l01 * d.y + p.l02 * d.z + p.l03;
  float y = p.l10 * d.x + p.l11 * d.y + p.l12 * d.z + p.l13;
  float z = -(p.l20 * d.x + p.l21 * d.y + p.l22 * d.z + p.l23);
  if (z <= 1e-6) return vec3(-1.0, -1.0, -1.0);
  float sx = p.ortho != 0u ? p.tan_x : z * p.tan_x, sy = p.ortho != 0u ? p.tan_y : z * p.tan_y;
  return vec3((x / sx * 0.5 + 0.5) * float(p.map_w), (0.5 - y / sy * 0.5) * float(p.map_h), z);
}

bool sm_inside(vec3 q) {
  return q.z > 0.0 && q.z <= p.far_clip && q.x >= 0.0 && q.y >= 0.0 && q.x < float(p.map_w) && q.y < float(p.map_h);
}

// Receiver plane: the gradient of w(z) (1/z; a sun's map: −z) over (u, v), from the screen neighbours on the same
// surface (the one of each pair nearer in light depth); zero where there is none. z: the
// smallest light-depth step to a neighbour, the receiver's own depth uncertainty (large where
// P blends two surfaces at a silhouette), added to the bias. w: the slope bound (texel
// footprints per texel of lateral offset): SHADOWMAP_TRUSTED_SLOPE where the neighbours left
// out of the fit lie on the plane (a planar receiver, however grazing the light), else
// shadows.slope_max.
// back: the plane through the neighbours faces away from the light (seen from the camera's
// side), where the contract keeps L.shadow (1 where key.direct vanishes).
vec3 sm_n = vec3(0.0);  // the receiver's normal on the light's side (sm_receiver_plane), 0: none
vec4 sm_receiver_plane(uvec2 px, vec3 q, vec3 P, out bool back) {
  vec3 d[2];
  vec3 t[2];
  vec3 other[2];  // the neighbour of each pair left out of the fit
  bool has_other[2];
  back = false;
  int found = 0;
  float spread = 1e30;
  for (int axis = 0; axis < 2; ++axis) {
    float best = 1e30;
    vec3 bd = vec3(0.0), bt = vec3(0.0);
    has_other[axis] = false;
    other[axis] = vec3(0.0);
    for (int s = -1; s <= 1; s += 2) {
      ivec2 nb = ivec2(px) + (axis == 0 ? ivec2(s, 0) : ivec2(0, s));
      if (nb.x < 0 || nb.y < 0 || nb.x >= int(p.width) || nb.y >= int(p.height)) continue;
      uint j = uint(nb.y) * p.width + uint(nb.x);
      if (sm_fg(j) == 0.0) continue;
      vec3 Pn = sm_rel(j);
      vec3 qn = sm_project(Pn);
      if (qn.z <= 0.0) continue;
      float dz = abs(qn.z - q.z);
      vec3 dn = vec3(qn.xy - q.xy, sm_w(qn.z) - sm_w(q.z));
      if (dz < best) {
        if (best < 1e30) { other[axis] = bd; has_other[axis] = true; }
        best = dz; bd = dn; bt = Pn - P;
      } else {
        other[axis] = dn;
        has_other[axis] = true;
      }
    }
    if (best < 1e30) { t[found] = bt; d[found++] = bd; }
    spread = min(spread, best);
  }
  spread = (spread >= 1e30 ? 0.0 : spread) + p.depth_eps + p.input_ulps * sm_input_step(px.y * p.width + px.x);
  if (found < 2) return vec4(0.0, 0.0, spread, p.slope_max);
  {
    vec3 nrm = cross(t[0], t[1]);
    float ln = length(nrm);
    if (ln > 0.0) sm_n = (dot(nrm, sm_to_light(P)) < 0.0 ? -nrm : nrm) / ln;
  }
  if (p.has_camera != 0u) {
    vec3 nrm = cross(t[0], t[1]);
    if (dot(nrm, vec3(p.eye_rel_x, p.eye_rel_y, p.eye_rel_z) - P) < 0.0) nrm = -nrm;
    back = dot(nrm, sm_to_light(P)) < 0.0;
  }
  float det = d[0].x * d[1].y - d[0].y * d[1].x;
  if (abs(det) < 1e-8) return vec4(0.0, 0.0, spread, p.slope_max);
  vec2 g = vec2(d[0].z * d[1].y - d[1].z * d[0].y, d[0].x * d[1].z - d[1].x * d[0].z) / det;
  // Planarity: each left-out neighbour's 1/z against the plane's, relative to its step.
  bool planar = false;
  for (int axis = 0; axis < 2; ++axis) {
    if (!has_other[axis]) continue;
    vec3 o = other[axis];
    float pred = dot(g, o.xy);
    planar = abs(o.z - pred) <= SHADOWMAP_PLANE_TOL * max(abs(o.z), abs(pred));
    if (!planar) break;
  }
  return vec4(g, spread, planar ? max(p.slope_max, SHADOWMAP_TRUSTED_SLOPE) : p.slope_max);
}

// A filter tap's share of the receiver's irradiance, relative to the light's centre (issue 19;
// shadows.isg's irradiance()): the PCF tap at unit offset u in the filter's disk (texel axes,
// v down), at the penumbra's radius, stands for the light point w = L·(u.x, −u.y) in the light's
// frame (the ray from the receiver through the blocker it samples ends there), and that point,
// at r = w − P from the receiver, gives it max(n·r, 0)·|n_l·r| / |r|⁴ (n_l: the disk facing the
// receiver for a sphere light, the map's axis for a disk or rect light). A renderer's soft shadow
// weighs the light's points so: under a low light its top lights a floor several times as much
// as its bottom. A sun's point u is the direction ω = axis + tan(half angle)·(u.x, −u.y) in the
// map's frame, every one at the same radiance: it gives max(n·ω̂, 0), relative to n·axis. 1 where
// the receiver's normal is unknown.
float sm_irradiance(vec3 P, vec2 u) {
  if (sm_n == vec3(0.0)) return 1.0;
  if (p.ortho != 0u) {
    vec3 a = vec3(p.l20, p.l21, p.l22);
    vec3 w = normalize(a + p.light_radius * (u.x * vec3(p.l00, p.l01, p.l02) - u.y * vec3(p.l10, p.l11, p.l12)));
    return max(dot(sm_n, w), 0.0) / max(dot(sm_n, a), SHADOWMAP_MIN_CN);
  }
  vec3 w = p.light_radius * (u.x * vec3(p.l00, p.l01, p.l02) - u.y * vec3(p.l10, p.l11, p.l12));
  vec3 r = w - P, nl = p.facing != 0u ? P : vec3(p.l20, p.l21, p.l22);
  float D2 = dot(P, P), q = D2 / dot(r, r);
  return max(dot(sm_n, r), 0.0) * abs(dot(nl, r)) /
         (max(dot(sm_n, -P), SHADOWMAP_MIN_CN * sqrt(D2)) * max(abs(dot(nl, -P)), 1e-30)) * q * q;
}

// The receiver's depth at texel centre c (receiver plane, slope clamped to g.w) minus the bias:
// map depths below it are blockers.
float sm_threshold(vec3 q, vec4 g, vec2 c, float texel_world) {
  vec2 o = c - q.xy;
  float zc = sm_w_inv(sm_w(q.z) + dot(g.xy, o));
  float lim = g.w * texel_world * length(o);
  zc = clamp(zc, q.z - lim, q.z + lim);
  return zc - p.bias * texel_world - p.spread_bias * g.z;
}

// Bounds of the receiver's threshold (sm_threshold) over [lo, hi): the receiver plane's depth is
// monotone along lines (w(z) is linear), so its extremes are at the corners; the clamp to
// q.z ± g.w·tw·|o| (the plane's slope bound) is bounded by the farthest corner.
vec2 sm_threshold_range(vec3 q, vec4 g, vec2 lo, vec2 hi, float tw) {
  float zmin = 1e30, zmax = -1e30, far = 0.0;
  for (int k = 0; k < 4; ++k) {
    vec2 o = vec2((k & 1) != 0 ? hi.x : lo.x, (k & 2) != 0 ? hi.y : lo.y) - q.xy;
    float zc = sm_w_inv(sm_w(q.z) + dot(g.xy, o));
    zmin = min(zmin, zc);
    zmax = max(zmax, zc);
    far = max(far, length(o));
  }
  float lim = g.w * tw * far, b = p.bias * tw + p.spread_bias * g.z;
  return vec2(max(q.z - lim, min(zmin, q.z)), min(q.z + lim, max(q.z, zmax))) - b;
}
// Whether the light's cone from the receiver reaches texel centre c at map depth zm (issue 19):
// kr is shadows.reach times k (sm_k); 0: always.
bool sm_reaches(vec3 q, vec2 c, float zm, float kr) {
  if (kr <= 0.0) return true;
  float r = kr * sm_gap(zm, q.z) + SHADOWMAP_REACH_MARGIN;
  vec2 o = c - q.xy;
  return dot(o, o) <= r * r;
}
// The radius, in texels, of the light's cone from the receiver (depth qz) at map depth z, widened
// `margin` times, within shadows.smap_max_radius; k as sm_reaches's. The first blocker search's
// region is the cone at the map's nearest depth (PCSS), a narrowed one's at the mean blocker
// depth (issue 19).
float sm_cone_radius(float k, float z, float qz, float margin) {
  return min(margin * k * sm_gap(z, qz), p.max_radius);
}
// The narrowed blocker search's box (vssm's and cssm's): the half-width of the square of the
// cone's area, at least a texel wide.
float sm_cone_box(float k, float z, float qz, float margin) {
  return max(SM_BOX_OF_DISK * sm_cone_radius(k, z, qz, margin), 0.5);
}
// One to statistics word `w` (--timings): reduced over the subgroup's active lanes, one atomic
// a subgroup (an atomic a pixel, every lane on one word, cost lavapipe 0.28 s at 1080p).
// Includers that count define SHADOWMAP_COUNTS, enable GL_KHR_shader_subgroup_arithmetic and
// declare buffer `stats`.
#ifdef SHADOWMAP_COUNTS
void sm_count(uint w) {
  uint n = subgroupAdd(1u);
  if (subgroupElect()) atomicAdd(stats[w], n);
}
#endif
// Two dispatches of one shader (vssm, cssm), told apart by specialization constant 0, SM_OWN
// (docs/design.md: llvmpipe runs every lane through all the code there is, masked, so a pixel
// the cheap test settles must not sit in a SIMD group with one that filters): the first, a lane
// per pixel, settles what its cheap test can and lists the rest (sm_own_append); the second, a
// lane per listed pixel, runs the whole method for them. Includers define SHADOWMAP_OWN and
// declare buffer `own` (SHADOWMAP_OWN_HEAD in shadowmap_io.h).
#ifdef SHADOWMAP_OWN
layout(constant_id = 0) const bool SM_OWN = false;
void sm_own_append(uint i) {
  uint k = atomicAdd(own[0], 1u);
  own[SHADOWMAP_OWN_HEAD + k] = i;
  uint lanes = SHADOWMAP_LOCAL * SHADOWMAP_LOCAL;
  if (k % (SHADOWMAP_OWN_ROW * lanes) == 0u) atomicAdd(own[2], 1u);
}
// The pixel this lane shades (false: none): its own in the first dispatch, the listed one in
// the second.
bool sm_pixel_of(out uvec2 px) {
  if (!SM_OWN) {
    px = gl_GlobalInvocationID.xy;
    return px.x < pc.width && px.y < pc.height;
  }
  uint k = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * (SHADOWMAP_LOCAL * SHADOWMAP_LOCAL) +
           gl_LocalInvocationIndex;
  if (k >= own[0]) return false;
  uint i = own[SHADOWMAP_OWN_HEAD + k];
  px = uvec2(i % pc.width, i / pc.width);
  return true;
}
#endif
float sm_fetch(vec2 c) {
  return sm_map(uint(c.y) * p.map_w + uint(c.x));
}

// Every method's last step (shadows.input_edges, issue 19): a map texel places a shadow's edge
// only to within itself (8 cm on a floor lit at 8 degrees by a 1024² map), and a narrow penumbra
// filtered from it inherits that and the receiver plane's bias near contact; the renderer's
// ray-traced L.shadow places the edge exactly. Where the penumbra's radius rf (texels) is within
// r0 = shadows.input_edges texels the input's hard shadow stands; beyond, it weighs (r0/rf)², the
// filtered visibility the rest. rf = 0 where the map's verdict stood alone (a lit or umbra region,
// no blocker found): there too the input's L.shadow stands. r_min: the method's own floor on r0,
// the narrowest penumbra it can place (cssm's, shadowmap_cssm.comp; 0 for the others).
float sm_input_edges_at(float s, float hard_in, float rf, float r_min) {
  float r0 = p.input_edges;
  if (r0 <= 0.0) return s;
  r0 = max(r0, r_min);
  float w = rf <= r0 ? 1.0 : (r0 / rf) * (r0 / rf);
  return clamp(mix(s, hard_in, w), 0.0, 1.0);
}
float sm_input_edges(float s, float hard_in, float rf) { return sm_input_edges_at(s, hard_in, rf, 0.0); }

#endif
