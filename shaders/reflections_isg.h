// GLSL only: what the four dispatches of reflections.isg share (paper §3.2): the bindings, the
// pixel's lobe (eq. 13, 14), the parameter search (eq. 4 with the range function of eq. 10-12),
// the gather, and the tile's records. lib/effects/reflections/reflections.cpp mirrors every step
// in double.
// Speed (issue 18): every tap is one point sample of two packed texels (reflections.pack); the
// sample lattice comes from a table made on the host; the lobe warp is algebraic (no atan/tan/cos
// per tap). The search runs once per 2×2 quad (reflections_isg_search.comp), the wide gathers once
// per 4×4 block (reflections_isg_wide.comp), each a lane of its own dispatch, the pixels read
// their records (reflections_isg.comp), and the few that search or gather for themselves are
// finished from a list (reflections_isg_own.comp): no shader has a barrier or shared memory,
// which on lavapipe run a workgroup's lanes as coroutines (docs/design.md).
#ifndef REFLECTIONS_ISG_H
#define REFLECTIONS_ISG_H
#include "reflections_isg_io.h"
#include "isg_sampling.h"
#include "isg_view.h"
// Inputs are texel views (lavapipe gathers texels as vectors; gpu.h's Slot::texels).
layout(binding = 0) uniform usamplerBuffer pack_geo;   // P − eye, oct N
layout(binding = 1) uniform samplerBuffer pack_color;  // refl, dist
layout(binding = 2) uniform samplerBuffer rough;
// Search lattice (grid_s² entries) then gather lattice (grid_g²): (x, y, |c|, |c|²) on the disk.
layout(binding = 3) uniform samplerBuffer samples;
layout(std430, binding = 4) writeonly buffer Glossy { float glossy[]; };
layout(std430, binding = 5) buffer Tiles { uint tiles[]; };  // refl.tiles (reflections.list)
layout(binding = 6) uniform usamplerBuffer records;  // refl.tiles again, as 16-byte texels
layout(push_constant) uniform Push { ReflIsgPush pc; };
// Settings that choose code paths (reflections_isg_io.h): compiled in, not branched on.
layout(constant_id = 0) const uint REFL_FLAGS = 0u;
layout(constant_id = 1) const uint REFL_MODE = REFL_MODE_ISG;
#include "reflections_range.h"  // range_fn, eq. 10-12

float roughness_at(uint i) { return (REFL_FLAGS & REFL_HAS_ROUGHNESS) != 0u ? texelFetch(rough, int(i)).r : pc.roughness; }
// A pixel holds reflection data to gather from: foreground with a non-zero weight.
bool has_refl(vec4 c) { return c.w >= 0.0; }
bool is_glossy(uint i) { return has_refl(texelFetch(pack_color, int(i))) && roughness_at(i) > REFL_MIN_ROUGHNESS; }

mat3 rot() {  // world -> camera; GLSL matrices are column-major
  return mat3(pc.r00, pc.r10, pc.r20, pc.r01, pc.r11, pc.r21, pc.r02, pc.r12, pc.r22);
}
vec2 project(vec3 rel) {  // rel = P − eye
  vec3 c = rot() * rel;
  float z = max(-c.z, 1e-6);
  return vec2(pc.cx + pc.f_px * c.x / z, pc.cy - pc.f_px * c.y / z);
}

// The pixel holding frame position q (pixel centres at +0.5), clamped to the image.
ivec2 tap_xy(vec2 q) {
  ivec2 x = ivec2(floor(q)) - ivec2(pc.origin & 0xffffu, pc.origin >> 16);
  return clamp(x, ivec2(0), ivec2(pc.width, pc.height) - 1);
}
uint tap(vec2 q) {
  ivec2 x = tap_xy(q);
  return uint(x.y) * pc.width + uint(x.x);
}
// The texel of that pixel's REFL_COARSE² cell (after the image's in refl.pack.*).
uint tap_coarse(vec2 q) {
  uvec2 c = uvec2(tap_xy(q)) / REFL_COARSE;
  return REFL_COARSE_AT(pc.width, pc.height, c.x, c.y);
}

mat2 pixel_rotation(uvec2 p) {  // the same for the REFL_ROTATION_BLOCK² pixels of a block
  float ang = isg_pixel_angle((p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) / REFL_ROTATION_BLOCK);
  return mat2(cos(ang), sin(ang), -sin(ang), cos(ang));
}

// The pixel's lobe: the cone of eq. 13 and its screen footprint (eq. 14).
struct Lobe {
  vec2 p0;  // frame coordinates of the pixel centre
  vec3 P0, N0;
  float e, cos_i, alpha, tan_max, R_full, R_p;  // tan_max: tan θ_max
  mat2 F;  // footprint axes with the pixel's rotation folded in: offset = F · lattice point
};

Lobe lobe_at(uvec2 p, uint i) {
  Lobe L;
  L.p0 = vec2(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) + 0.5;
  uvec4 g0 = texelFetch(pack_geo, int(i));
  L.P0 = uintBitsToFloat(g0.xyz);
  L.N0 = isg_oct_decode(g0.w);
  L.e = max(length(L.P0), 1e-6);
  vec3 V = -L.P0 / L.e;
  L.cos_i = clamp(dot(L.N0, V), REFL_MIN_COS, 1.0);
  L.alpha = roughness_at(i) * roughness_at(i);
  // The cone holding the fraction E of the lobe: tan θ_h = α·sqrt(E/(1−E)), θ_max = 2·θ_h up
  // to REFL_MAX_THETA, kept as its tangent: tan 2θ_h = 2·tan θ_h / (1 − tan² θ_h), θ_h clamped to
  // REFL_MAX_THETA / 2 first (the tangent is monotonic there; no atan/tan per pixel).
  float th = min(L.alpha * pc.tan_h_factor, REFL_TAN_HALF_MAX_THETA);
  L.tan_max = 2.0 * th / (1.0 - th * th);
  L.R_full = pc.f_px * L.tan_max;  // eq. 13 as E → ∞, in pixels
  L.R_p = min(L.R_full, pc.max_radius);
  // Footprint axes: along the screen image of the plane of incidence the lobe keeps its width;
  // across it the reflected lobe narrows by cos θ_incident (eq. 14 on that axis only).
  vec2 d_maj = vec2(1.0, 0.0);
  if ((REFL_FLAGS & REFL_ANISOTROPIC) != 0u) {
    vec2 d = project(L.P0 + L.N0 * (0.01 * L.e)) - project(L.P0);
    if (length(d) > 1e-6) d_maj = normalize(d);
  }
  vec2 d_min = vec2(-d_maj.y, d_maj.x);
  float maj = (REFL_FLAGS & REFL_ANISOTROPIC) != 0u ? 1.0 : L.cos_i;
  L.F = mat2(maj * d_maj, L.cos_i * d_min) * pixel_rotation(p);
  return L;
}

// Parameter search (eq. 4, constant spatial weight, eq. 10 range) over t = E/(e+E), the ratio
// of eq. 13: bounded, and 1 for misses (infinitely far).
float search(Lobe L, uint i) {
  float d0 = texelFetch(pack_color, int(i)).w;
  float st = d0 > 0.0 ? d0 / (L.e + d0) : 1.0;
  float sw = 1.0;
  if (d0 <= 0.0 && (REFL_FLAGS & REFL_SEARCH_MISSES) == 0u) { st = 0.0; sw = 0.0; }
  uint gs = pc.grids & 0xffffu;
  mat2 FR = L.R_p * L.F;
  bool coarse = L.R_p >= REFL_COARSE_RADIUS;
  for (uint k = 0u; k < gs * gs; ++k) {
    vec4 u = texelFetch(samples, int(k));
    vec2 q = L.p0 + FR * u.xy;
    uint t = coarse ? tap_coarse(q) : tap(q);
    vec4 c = texelFetch(pack_color, int(t));
    if (!has_refl(c)) continue;
    float dj = c.w;
    if (dj <= 0.0 && (REFL_FLAGS & REFL_SEARCH_MISSES) == 0u) continue;
    float tj = dj > 0.0 ? dj / (L.e + dj) : 1.0;
    float w = range_fn(texelFetch(pack_geo, int(t)), L.P0, L.N0);
    // Reach: only reflections whose own footprint (radius t_j·R_full) covers p_0.
    if ((REFL_FLAGS & REFL_SEARCH_REACH) != 0u) w *= clamp(tj * L.R_full - u.z * L.R_p + 0.5, 0.0, 1.0);
    st += w * tj;
    sw += w;
  }
  return sw > 1e-6 ? st / sw : 1.0;
}

// The gather's footprint (eq. 13: tan α = E·tan θ / (e + E), a reflected deviation θ lands
// k·tan θ pixels away): k = t̄·f in pixels, the tangent of the cone's half-angle th_max and its
// radius R_s. A footprint over max_radius truncates the cone rather than squeezing the lobe:
// 2·th_max = min(θ_max, atan(max_radius / k)), so tan 2·th_max = min(tan θ_max, max_radius / k),
// and tan th_max is the half-angle tangent T / (1 + sqrt(1 + T²)) (no atan/tan per pixel).
struct Foot {
  float k_px, tan_th, R_s;
};
Foot footprint(Lobe L, float t_bar) {
  Foot F;
  F.k_px = t_bar * pc.f_px;
  float T = min(L.tan_max, pc.max_radius / max(F.k_px, 1e-6));
  F.tan_th = T / (1.0 + sqrt(1.0 + T * T));
  F.R_s = F.k_px * T;
  return F;
}

// Energy the rough lobe loses to masking-shadowing (Smith, height-correlated, the lobe narrow
// enough that the incident angle is the mirror's): albedo 1 / (1 + 2·Λ(θ_i)).
float albedo_of(Lobe L) {
  float tan2 = (1.0 - L.cos_i * L.cos_i) / (L.cos_i * L.cos_i);
  return (REFL_FLAGS & REFL_MASKING) != 0u ? 1.0 / sqrt(1.0 + L.alpha * L.alpha * tan2) : 1.0;
}

// Gather (eq. 4): the weighted mean of refl over the lobe, the centre pixel included. The samples
// are reflected directions placed by the lobe (the grid's radius warped through the NDF's CDF in
// θ_h, ξ = tan²θ_h / (α² + tan²θ_h) up to the cone's ξ_max), each landing k·tan 2θ_h pixels away
// along its azimuth (eq. 14 narrows the minor axis); what is left of the GGX weight per solid
// angle is 1 / cos θ_h. With τ = tan θ_h = α·sqrt(ξ/(1−ξ)): tan 2θ_h = 2τ/(1−τ²) and
// 1/cos θ_h = sqrt(1+τ²) (θ_h ≤ 0.65, so τ < 1).
vec3 gather_mean(Lobe L, uint i, Foot F) {
  float alpha = L.alpha;
  float tm = F.tan_th;
  float xi_max = tm * tm / (alpha * alpha + tm * tm);
  vec3 s = texelFetch(pack_color, int(i)).rgb;
  float ws = 1.0;
  uint gs = pc.grids & 0xffffu, gg = pc.grids >> 16;
  mat2 FK = F.k_px * L.F;
  for (uint k = 0u; k < gg * gg; ++k) {
    vec4 u = texelFetch(samples, int(gs * gs + k));
    float xi = xi_max * u.w;
    float tau2 = alpha * alpha * xi / (1.0 - xi);
    float tau = sqrt(tau2);
    // Lattice point scaled from radius |c| to k·tan 2θ_h (|c| = 0: the centre stays put).
    float f = u.z > 0.0 ? 2.0 * tau / ((1.0 - tau2) * u.z) : 0.0;
    vec2 q = L.p0 + FK * (f * u.xy);
    // A tap at least REFL_COARSE_GATHER pixels out (k·tan 2θ_h) reads its coarse cell.
    uint t = F.k_px * f * u.z >= REFL_COARSE_GATHER ? tap_coarse(q) : tap(q);
    vec4 c = texelFetch(pack_color, int(t));
    if (!has_refl(c)) continue;
    float w = sqrt(1.0 + tau2) * range_fn(texelFetch(pack_geo, int(t)), L.P0, L.N0);
    s += w * c.rgb;
    ws += w;
  }
  return s / ws;
}

vec3 gather(Lobe L, uint i, Foot F) {
  vec3 c0 = texelFetch(pack_color, int(i)).rgb;
  if (F.R_s < 0.25) return albedo_of(L) * c0;
  return albedo_of(L) * mix(c0, gather_mean(L, i, F), smoothstep(0.25, 0.75, F.R_s));
}


// The tile workgroup (x, y) of a dispatch over reflections.list runs: workgroup k (row-major in a
// grid tiles_x wide) is tile tiles[list + k]; false past the list's end (the last row's end).
bool listed_tile(out uint tile, out uvec2 wg, out uint nt) {
  uint tiles_x = (pc.width + REFL_TILE - 1u) / REFL_TILE;
  nt = tiles_x * ((pc.height + REFL_TILE - 1u) / REFL_TILE);
  uint k_list = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  tile = 0u;
  wg = uvec2(0u);
  if (k_list >= tiles[REFL_AT_COUNT(nt)]) return false;
  tile = tiles[REFL_AT_LIST(nt) + k_list];
  wg = uvec2(tile % tiles_x, tile / tiles_x);
  return true;
}
// Quad q (row-major, REFL_QUADS a row) of tile wg: its record's first word in refl.tiles, its
// top-left pixel, and its representative (the first glossy pixel of mask, bit k at (k & 1, k >> 1)).
uint quad_at(uint nt, uint tile, uint q) { return REFL_AT_QUADS(nt) + 2u * (tile * REFL_QUADS * REFL_QUADS + q); }
uvec2 quad_base(uvec2 wg, uint q) { return wg * REFL_TILE + 2u * uvec2(q % REFL_QUADS, q / REFL_QUADS); }
uvec2 quad_rep(uvec2 wg, uint q, uint mask) {
  uint k = uint(findLSB(mask));
  return quad_base(wg, q) + uvec2(k & 1u, k >> 1u);
}
// Block b's record's first 16-byte texel in refl.tiles.
uint block_at(uint nt, uint tile, uint b) { return REFL_AT_BLOCKS(nt) / 4u + 2u * (tile * REFL_BLOCKS * REFL_BLOCKS + b); }
// Block b's top-left quad.
uint block_quad(uint b) { return 2u * (b / REFL_BLOCKS) * REFL_QUADS + 2u * (b % REFL_BLOCKS); }

// A wide lobe's mean (R_s ≥ REFL_REUSE_RADIUS) moves little from one pixel to the next: the
// pixel p takes it bilinearly from the blocks' gathers around it in the image's grid of 4×4
// blocks, across tile borders (a blend within each tile alone steps at every tile border, 16
// pixels apart: shared gloss composite RMSE +8 % at 25×49 samples, +9 % at 49×49), from those on
// its surface (eq. 10 range weight ≥ REFL_QUAD_SAME to the block's representative) whose
// footprint is within a factor REFL_REUSE_RATIO of its own (a tile reflections.list left out has
// records without a gather). False where they hold under REFL_REUSE_COVER of the bilinear weight:
// the pixel gathers for itself.
bool reuse(Lobe L, float R_s, uint nt, uvec2 p, out vec3 m) {
  uint tiles_x = (pc.width + REFL_TILE - 1u) / REFL_TILE;
  uvec2 cells = (uvec2(pc.width, pc.height) + 3u) / 4u;
  uvec2 q0;  // the lower corner of the blocks around the pixel (at their top-left pixels)
  vec2 a;
  isg_cell_bilinear(p, cells, 4.0, q0, a);
  vec3 s = vec3(0.0);
  float ws = 0.0;
  for (uint k = 0u; k < 4u; ++k) {
    uvec2 c = q0 + uvec2(k & 1u, k >> 1u);
    float w = isg_quad_weight(a, k);
    if (w <= 0.0 || c.x >= cells.x || c.y >= cells.y) continue;
    uint tile = (c.y / REFL_BLOCKS) * tiles_x + c.x / REFL_BLOCKS;
    int bt = int(block_at(nt, tile, (c.y % REFL_BLOCKS) * REFL_BLOCKS + c.x % REFL_BLOCKS));
    vec4 r = uintBitsToFloat(texelFetch(records, bt));
    if (r.w < 0.0 || r.w * REFL_REUSE_RATIO < R_s || R_s * REFL_REUSE_RATIO < r.w) continue;
    if (range_fn(texelFetch(records, bt + 1), L.P0, L.N0) < REFL_QUAD_SAME) continue;  // its representative
    s += w * r.rgb;
    ws += w;
  }
  m = ws > 0.0 ? s / ws : vec3(0.0);
  return ws >= REFL_REUSE_COVER;
}

// The pixel p with its quad's representative r and t̄. own: compiled as a
// constant; false in reflections.isg, where a pixel that would search or gather for itself
// returns with rest set (reflections.isg.own finishes it), true there. searched, gathered:
// statistics.
vec3 refl_isg(uvec2 p, uint i, uint r, float t_rep, uint nt, bool own, out bool rest,
              inout uint searched, inout uint gathered) {
  rest = false;
  Lobe L = lobe_at(p, i);
  float t_bar = t_rep;
  // A pixel on another surface than its quad's representative searches for itself.
  if (r != i && range_fn(texelFetch(pack_geo, int(r)), L.P0, L.N0) < REFL_QUAD_SAME) {
    if (!own) { rest = true; return vec3(0.0); }
    t_bar = search(L, i);
    searched = 1u;
  }
  Foot F = footprint(L, t_bar);
  vec3 m;
  if (F.R_s >= REFL_REUSE_RADIUS && reuse(L, F.R_s, nt, p, m)) return albedo_of(L) * m;
  if (F.R_s >= 0.25) {
    if (!own) { rest = true; return vec3(0.0); }
    gathered = 1u;
  }
  if (!own) return albedo_of(L) * texelFetch(pack_color, int(i)).rgb;  // gather()'s mirror
  return gather(L, i, F);
}

#endif
