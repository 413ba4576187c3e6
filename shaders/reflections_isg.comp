#version 450
// Pass reflections.isg (paper §3.2): per pixel, the parameter search over refl.dist (eq. 4 with
// the range function of eq. 10-12) then the gather over refl (eq. 13, 14) with the screen-space
// projection of the GGX lobe as spatial weight. lib/effects/reflections/reflections.cpp mirrors
// every step in double.
#extension GL_GOOGLE_include_directive : require
#include "reflections_isg_io.h"
#include "isg_sampling.h"
layout(local_size_x = REFL_TILE, local_size_y = REFL_TILE) in;
layout(std430, binding = 0) readonly buffer Refl { float refl[]; };
layout(std430, binding = 1) readonly buffer Dist { float dist[]; };
layout(std430, binding = 2) readonly buffer Weight { float weight[]; };
layout(std430, binding = 3) readonly buffer Normal { float nrm[]; };
layout(std430, binding = 4) readonly buffer Geo { float geo[]; };  // P (3 planes) or Z
layout(std430, binding = 5) readonly buffer Rough { float rough[]; };
layout(std430, binding = 6) readonly buffer Fg { float fg[]; };
layout(std430, binding = 7) writeonly buffer Glossy { float glossy[]; };
layout(std430, binding = 8) writeonly buffer Tiles { float tiles[]; };
layout(push_constant) uniform Push { ReflIsgPush pc; };

const float PI = 3.14159265358979;
shared uint tile_glossy;

uint npix() { return pc.width * pc.height; }
vec3 rgb(uint base, uint i) {
  uint n = npix();
  if (base == 0u) return vec3(refl[i], refl[n + i], refl[2u * n + i]);
  return vec3(weight[i], weight[n + i], weight[2u * n + i]);
}
vec3 refl_at(uint i) { return rgb(0u, i); }

float roughness_at(uint i) { return (pc.flags & REFL_HAS_ROUGHNESS) != 0u ? rough[i] : pc.roughness; }

bool is_glossy(uint i) {
  vec3 w = rgb(1u, i);
  return fg[i] != 0.0 && max(w.r, max(w.g, w.b)) > 0.0 && roughness_at(i) > REFL_MIN_ROUGHNESS;
}
// A pixel holds reflection data to gather from: foreground with a non-zero weight.
bool has_refl(uint i) {
  vec3 w = rgb(1u, i);
  return fg[i] != 0.0 && max(w.r, max(w.g, w.b)) > 0.0;
}

mat3 rot() {  // world -> camera; GLSL matrices are column-major
  return mat3(pc.r00, pc.r10, pc.r20, pc.r01, pc.r11, pc.r21, pc.r02, pc.r12, pc.r22);
}
vec3 eye() { return vec3(pc.eye_x, pc.eye_y, pc.eye_z); }

vec3 position_at(uint i) {
  uint n = npix();
  if ((pc.flags & REFL_HAS_POSITION) != 0u) return vec3(geo[i], geo[n + i], geo[2u * n + i]);
  float z = geo[i];
  // Frame coordinates (a tile adds its origin), so a tile rounds as the whole frame does.
  float x = float(i % pc.width + (pc.origin & 0xffffu)) + 0.5, y = float(i / pc.width + (pc.origin >> 16)) + 0.5;
  vec3 c = vec3((x - pc.cx) / pc.f_px * z, -(y - pc.cy) / pc.f_px * z, -z);
  return transpose(rot()) * c + eye();
}
vec3 normal_at(uint i) {
  uint n = npix();
  vec3 v = vec3(nrm[i], nrm[n + i], nrm[2u * n + i]);
  float l = length(v);
  return l > 0.0 ? v / l : vec3(0.0, 0.0, 1.0);
}
vec2 project(vec3 w) {
  vec3 c = rot() * (w - eye());
  float z = max(-c.z, 1e-6);
  return vec2(pc.cx + pc.f_px * c.x / z, pc.cy - pc.f_px * c.y / z);
}


// Bilinear taps of position q (frame coordinates, pixel centres at +0.5), clamped to the image.
void taps(vec2 q, out uint t[4], out float bw[4]) {
  vec2 x = q - 0.5;
  vec2 x0 = floor(x);
  vec2 f = x - x0;
  int ix = int(x0.x) - int(pc.origin & 0xffffu), iy = int(x0.y) - int(pc.origin >> 16);
  int xa = clamp(ix, 0, int(pc.width) - 1), xb = clamp(ix + 1, 0, int(pc.width) - 1);
  int ya = clamp(iy, 0, int(pc.height) - 1), yb = clamp(iy + 1, 0, int(pc.height) - 1);
  t[0] = uint(ya) * pc.width + uint(xa); t[1] = uint(ya) * pc.width + uint(xb);
  t[2] = uint(yb) * pc.width + uint(xa); t[3] = uint(yb) * pc.width + uint(xb);
  bw[0] = (1.0 - f.x) * (1.0 - f.y); bw[1] = f.x * (1.0 - f.y);
  bw[2] = (1.0 - f.x) * f.y; bw[3] = f.x * f.y;
}

// Eq. 10-12: r = exp(-(a·l² + b·n²)/σ), l = |w(p_i) − w(p_0)| / scene_radius, n = 1 − N_i·N_0.
float range_fn(uint j, vec3 P0, vec3 N0) {
  float l = length(position_at(j) - P0) * pc.inv_scene_radius;
  float nn = 1.0 - dot(normal_at(j), N0);
  return exp(-(pc.a * l * l + pc.b * nn * nn) * pc.inv_sigma);
}

vec3 refl_blur(uvec2 p, uint i) {
  vec2 p0 = vec2(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) + 0.5;  // frame coordinates
  float ang = isg_pixel_angle(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16));
  mat2 R = mat2(cos(ang), sin(ang), -sin(ang), cos(ang));
  vec3 s = refl_at(i);
  float ws = 1.0;
  for (uint k = 0u; k < (pc.grids >> 16) * (pc.grids >> 16); ++k) {
    vec2 q = p0 + pc.blur_radius * (R * isg_concentric(k, pc.grids >> 16));
    uint t[4]; float bw[4];
    taps(q, t, bw);
    for (int j = 0; j < 4; ++j) {
      float w = has_refl(t[j]) ? bw[j] : 0.0;
      s += w * refl_at(t[j]);
      ws += w;
    }
  }
  return s / ws;
}

vec3 refl_isg(uvec2 p, uint i) {
  vec2 p0 = vec2(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) + 0.5;  // frame coordinates
  vec3 P0 = position_at(i), N0 = normal_at(i);
  vec3 V = eye() - P0;
  float e = max(length(V), 1e-6);
  V /= e;
  float cos_i = clamp(dot(N0, V), REFL_MIN_COS, 1.0);
  float alpha = roughness_at(i) * roughness_at(i);
  // The cone holding the fraction E of the lobe: tan θ_h = α·sqrt(E/(1−E)), θ_max = 2·θ_h.
  float theta_max = min(2.0 * atan(alpha * pc.tan_h_factor), REFL_MAX_THETA);
  float R_full = pc.f_px * tan(theta_max);  // eq. 13 as E → ∞, in pixels
  float R_p = min(R_full, pc.max_radius);
  // Footprint axes: along the screen image of the plane of incidence the lobe keeps its width;
  // across it the reflected lobe narrows by cos θ_incident (eq. 14 on that axis only).
  vec2 d_maj = vec2(1.0, 0.0);
  float minor = cos_i;
  if ((pc.flags & 4u) != 0u) {
    vec2 d = project(P0 + N0 * (0.01 * e)) - project(P0);
    if (length(d) > 1e-6) d_maj = normalize(d);
  }
  vec2 d_min = vec2(-d_maj.y, d_maj.x);
  float maj = (pc.flags & 4u) != 0u ? 1.0 : cos_i;
  float ang = isg_pixel_angle(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16));
  mat2 Rot = mat2(cos(ang), sin(ang), -sin(ang), cos(ang));

  // Parameter search (eq. 4, constant spatial weight, eq. 10 range) over t = E/(e+E), the
  // ratio of eq. 13: bounded, and 1 for misses (infinitely far).
  float d0 = dist[i];
  float st = d0 > 0.0 ? d0 / (e + d0) : 1.0;
  float sw = 1.0;
  if (d0 <= 0.0 && (pc.flags & 8u) == 0u) { st = 0.0; sw = 0.0; }
  for (uint k = 0u; k < (pc.grids & 0xffffu) * (pc.grids & 0xffffu); ++k) {
    vec2 u = Rot * isg_concentric(k, pc.grids & 0xffffu);
    vec2 q = p0 + R_p * (u.x * maj * d_maj + u.y * minor * d_min);
    uint t[4]; float bw[4];
    taps(q, t, bw);
    for (int j = 0; j < 4; ++j) {
      if (!has_refl(t[j])) continue;
      float dj = dist[t[j]];
      if (dj <= 0.0 && (pc.flags & 8u) == 0u) continue;
      float tj = dj > 0.0 ? dj / (e + dj) : 1.0;
      float w = bw[j] * range_fn(t[j], P0, N0);
      // Reach: only reflections whose own footprint (radius t_j·R_full) covers p_0.
      if ((pc.flags & 1u) != 0u) w *= clamp(tj * R_full - length(u) * R_p + 0.5, 0.0, 1.0);
      st += w * tj;
      sw += w;
    }
  }
  float t_bar = sw > 1e-6 ? st / sw : 1.0;
  // Eq. 13: tan α = E·tan θ / (e + E): a reflected deviation θ lands k·tan θ pixels away.
  // A footprint over max_radius truncates the cone rather than squeezing the lobe.
  float k_px = t_bar * pc.f_px;
  float th_max = 0.5 * min(theta_max, atan(pc.max_radius / max(k_px, 1e-6)));
  float R_s = k_px * tan(2.0 * th_max);
  // Energy the rough lobe loses to masking-shadowing (Smith, height-correlated, the lobe
  // narrow enough that the incident angle is the mirror's): albedo 1 / (1 + 2·Λ(θ_i)).
  float tan2 = (1.0 - cos_i * cos_i) / (cos_i * cos_i);
  float albedo = (pc.flags & 16u) != 0u ? 1.0 / sqrt(1.0 + alpha * alpha * tan2) : 1.0;
  vec3 c0 = refl_at(i);
  if (R_s < 0.25) return albedo * c0;

  // Gather (eq. 4): the samples are reflected directions placed by the lobe (the grid's radius
  // warped through the NDF's CDF in θ_h, ξ = tan²θ_h / (α² + tan²θ_h) up to the cone's ξ_max),
  // each landing k·tan 2θ_h pixels away along its azimuth (eq. 14 narrows the minor axis);
  // what is left of the GGX weight per solid angle is 1 / cos θ_h.
  float tm2 = tan(th_max) * tan(th_max);
  float xi_max = tm2 / (alpha * alpha + tm2);
  vec3 s = c0;
  float ws = 1.0;
  for (uint k = 0u; k < (pc.grids >> 16) * (pc.grids >> 16); ++k) {
    vec2 c = isg_concentric(k, pc.grids >> 16);
    float rho_u = length(c);
    float xi = xi_max * rho_u * rho_u;
    float th = atan(alpha * sqrt(xi / (1.0 - xi)));
    vec2 u = rho_u > 0.0 ? Rot * (c * (k_px * tan(2.0 * th) / rho_u)) : vec2(0.0);
    vec2 q = p0 + (u.x * maj * d_maj + u.y * minor * d_min);
    float wd = 1.0 / cos(th);
    uint t[4]; float bw[4];
    taps(q, t, bw);
    for (int j = 0; j < 4; ++j) {
      if (!has_refl(t[j])) continue;
      float w = wd * bw[j] * range_fn(t[j], P0, N0);
      s += w * refl_at(t[j]);
      ws += w;
    }
  }
  return albedo * mix(c0, s / ws, smoothstep(0.25, 0.75, R_s));
}

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  bool inside = p.x < pc.width && p.y < pc.height;
  uint i = inside ? p.y * pc.width + p.x : 0u;
  if (gl_LocalInvocationIndex == 0u) tile_glossy = 0u;
  barrier();
  bool g = inside && is_glossy(i);
  if (g) atomicOr(tile_glossy, 1u);
  barrier();
  // Tiles with nothing glossy take the cheap path: refl.glossy = refl.
  if (gl_LocalInvocationIndex == 0u)
    tiles[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = tile_glossy == 0u ? 1.0 : 0.0;
  if (!inside) return;
  vec3 c = refl_at(i);
  if (tile_glossy != 0u && g) c = pc.mode == REFL_MODE_BLUR ? refl_blur(p, i) : refl_isg(p, i);
  uint n = npix();
  glossy[i] = c.r; glossy[n + i] = c.g; glossy[2u * n + i] = c.b;
}
