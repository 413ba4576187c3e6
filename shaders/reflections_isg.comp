#version 450
// Pass reflections.isg (paper §3.2): per pixel, the parameter search over refl.dist (eq. 4 with
// the range function of eq. 10-12) then the gather over refl (eq. 13, 14) with the screen-space
// projection of the GGX lobe as spatial weight. lib/effects/reflections/reflections.cpp mirrors
// every step in double.
// Speed (issue 18): every tap is one point sample of two packed texels (reflections.pack); the
// sample lattice comes from a table made on the host; the lobe warp is algebraic (no atan/tan/cos
// per tap); the search runs once per 2×2 quad, from the coarse cells where its radius is wide.
#extension GL_GOOGLE_include_directive : require
#include "reflections_isg_io.h"
#include "isg_sampling.h"
#include "isg_view.h"
layout(local_size_x = REFL_TILE, local_size_y = REFL_TILE) in;
// Inputs are texel views (lavapipe gathers texels as vectors; gpu.h's Slot::texels).
layout(binding = 0) uniform usamplerBuffer pack_geo;   // P − eye, oct N
layout(binding = 1) uniform samplerBuffer pack_color;  // refl, dist
layout(binding = 2) uniform samplerBuffer rough;
// Search lattice (grid_s² entries) then gather lattice (grid_g²): (x, y, |c|, |c|²) on the disk.
layout(binding = 3) uniform samplerBuffer samples;
layout(std430, binding = 4) writeonly buffer Glossy { float glossy[]; };
layout(std430, binding = 5) buffer Tiles { uint tiles[]; };  // refl.tiles (reflections.list)
layout(push_constant) uniform Push { ReflIsgPush pc; };
// Settings that choose code paths (reflections_isg_io.h): compiled in, not branched on.
layout(constant_id = 0) const uint REFL_FLAGS = 0u;
layout(constant_id = 1) const uint REFL_MODE = REFL_MODE_ISG;

shared uint tile_glossy;  // glossy pixels in the tile
shared uint glossy_bits[REFL_TILE * REFL_TILE / 32u];  // bit per pixel of the tile: glossy

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

// Eq. 10-12: r = exp(-(a·l² + b·n²)/σ), l = |w(p_i) − w(p_0)| / scene_radius, n = 1 − N_i·N_0.
float range_fn(uvec4 g, vec3 P0, vec3 N0) {
  vec3 d = uintBitsToFloat(g.xyz) - P0;
  float l2 = dot(d, d) * (pc.inv_scene_radius * pc.inv_scene_radius);
  float nn = 1.0 - dot(isg_oct_decode(g.w), N0);
  return exp(-(pc.a * l2 + pc.b * nn * nn) * pc.inv_sigma);
}

mat2 pixel_rotation(uvec2 p) {  // the same for the REFL_ROTATION_BLOCK² pixels of a block
  float ang = isg_pixel_angle((p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) / REFL_ROTATION_BLOCK);
  return mat2(cos(ang), sin(ang), -sin(ang), cos(ang));
}

vec3 refl_blur(uvec2 p, uint i) {
  vec2 p0 = vec2(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) + 0.5;  // frame coordinates
  mat2 R = pixel_rotation(p);
  vec3 s = texelFetch(pack_color, int(i)).rgb;
  float ws = 1.0;
  uint gs = pc.grids & 0xffffu, gg = pc.grids >> 16;
  for (uint k = 0u; k < gg * gg; ++k) {
    vec4 c = texelFetch(pack_color, int(tap(p0 + pc.blur_radius * (R * texelFetch(samples, int(gs * gs + k)).xy))));
    float w = has_refl(c) ? 1.0 : 0.0;
    s += w * c.rgb;
    ws += w;
  }
  return s / ws;
}

// The pixel's lobe: the cone of eq. 13 and its screen footprint (eq. 14).
struct Lobe {
  vec2 p0;  // frame coordinates of the pixel centre
  vec3 P0, N0;
  float e, cos_i, alpha, theta_max, R_full, R_p;
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
  // The cone holding the fraction E of the lobe: tan θ_h = α·sqrt(E/(1−E)), θ_max = 2·θ_h.
  L.theta_max = min(2.0 * atan(L.alpha * pc.tan_h_factor), REFL_MAX_THETA);
  L.R_full = pc.f_px * tan(L.theta_max);  // eq. 13 as E → ∞, in pixels
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
// The sums over lattice samples part, part + parts, ... (the centre in part 0): a quad's search
// is split over its four lanes.
vec2 search_sums(Lobe L, uint i, uint part, uint parts) {
  float d0 = texelFetch(pack_color, int(i)).w;
  float st = d0 > 0.0 ? d0 / (L.e + d0) : 1.0;
  float sw = 1.0;
  if ((d0 <= 0.0 && (REFL_FLAGS & REFL_SEARCH_MISSES) == 0u) || part != 0u) { st = 0.0; sw = 0.0; }
  uint gs = pc.grids & 0xffffu;
  mat2 FR = L.R_p * L.F;
  bool coarse = L.R_p >= REFL_COARSE_RADIUS;
  for (uint k = part; k < gs * gs; k += parts) {
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
  return vec2(st, sw);
}
float search_mean(vec2 s) { return s.y > 1e-6 ? s.x / s.y : 1.0; }
float search(Lobe L, uint i) { return search_mean(search_sums(L, i, 0u, 1u)); }

// The gather's footprint (eq. 13: tan α = E·tan θ / (e + E), a reflected deviation θ lands
// k·tan θ pixels away): k = t̄·f in pixels, the cone's half-angle th_max and its radius R_s. A
// footprint over max_radius truncates the cone rather than squeezing the lobe.
struct Foot {
  float k_px, th_max, R_s;
};
Foot footprint(Lobe L, float t_bar) {
  Foot F;
  F.k_px = t_bar * pc.f_px;
  F.th_max = 0.5 * min(L.theta_max, atan(pc.max_radius / max(F.k_px, 1e-6)));
  F.R_s = F.k_px * tan(2.0 * F.th_max);
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
vec4 gather_sums(Lobe L, uint i, Foot F, uint part, uint parts) {
  float alpha = L.alpha;
  float tm = tan(F.th_max);
  float xi_max = tm * tm / (alpha * alpha + tm * tm);
  vec3 s = part == 0u ? texelFetch(pack_color, int(i)).rgb : vec3(0.0);
  float ws = part == 0u ? 1.0 : 0.0;
  uint gs = pc.grids & 0xffffu, gg = pc.grids >> 16;
  mat2 FK = F.k_px * L.F;
  for (uint k = part; k < gg * gg; k += parts) {
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
  return vec4(s, ws);
}
vec3 gather_mean(Lobe L, uint i, Foot F) {
  vec4 s = gather_sums(L, i, F, 0u, 1u);
  return s.rgb / s.w;
}

vec3 gather(Lobe L, uint i, Foot F) {
  vec3 c0 = texelFetch(pack_color, int(i)).rgb;
  if (F.R_s < 0.25) return albedo_of(L) * c0;
  return albedo_of(L) * mix(c0, gather_mean(L, i, F), smoothstep(0.25, 0.75, F.R_s));
}

// The search at half resolution and the wide gathers at quarter resolution (issue 18): one
// search per 2×2 quad of the tile, from its first glossy pixel (the quad's representative), and
// one gather per 4×4 block, the representative's of its top-left quad, where its footprint is
// wide (R_s ≥ REFL_REUSE_RADIUS = 64 pixels: sixteen block spacings).
#define REFL_QUADS (REFL_TILE / 2u)
#define REFL_BLOCKS (REFL_TILE / 4u)
#define REFL_NO_REP 0xffffffffu
shared uint quad_rep[REFL_QUADS * REFL_QUADS];    // the representative's index, or REFL_NO_REP
shared float quad_t[REFL_QUADS * REFL_QUADS];     // its t̄ (eq. 4 over t = E/(e+E))
shared vec4 block_mean[REFL_BLOCKS * REFL_BLOCKS];  // the block's gather_mean and R_s (w < 0: none)
#define REFL_QUAD_PARTS 4u    // lanes per quad in the search (REFL_TILE² / REFL_QUADS²)
#define REFL_BLOCK_PARTS 16u  // lanes per block in the wide gather (REFL_TILE² / REFL_BLOCKS²)
shared vec4 part_sums[REFL_TILE * REFL_TILE];  // the lanes' partial sums, added in a fixed order
shared uint tile_searches, tile_gathers;

// A wide lobe's mean (R_s ≥ REFL_REUSE_RADIUS) moves little from one pixel to the next: the
// pixel takes it bilinearly from the blocks' gathers around it in the tile's block grid, from
// those on its surface (eq. 10 range weight ≥ REFL_QUAD_SAME) whose footprint is within a
// factor REFL_REUSE_RATIO of its own. False where they hold under REFL_REUSE_COVER of the
// bilinear weight: the pixel gathers for itself.
bool reuse(Lobe L, float R_s, out vec3 m) {
  uvec2 q0;  // the lower corner of the blocks around the pixel (at their top-left pixels)
  vec2 a;
  isg_cell_bilinear(gl_LocalInvocationID.xy, REFL_BLOCKS, 4.0, q0, a);
  vec3 s = vec3(0.0);
  float ws = 0.0;
  for (uint k = 0u; k < 4u; ++k) {
    uint b = (q0.y + (k >> 1u)) * REFL_BLOCKS + q0.x + (k & 1u);
    float w = isg_quad_weight(a, k);
    vec4 c = block_mean[b];
    if (w <= 0.0 || c.w < 0.0 || c.w * REFL_REUSE_RATIO < R_s || R_s * REFL_REUSE_RATIO < c.w) continue;
    if (range_fn(texelFetch(pack_geo, int(quad_rep[2u * (b / REFL_BLOCKS) * REFL_QUADS + 2u * (b % REFL_BLOCKS)])), L.P0, L.N0) < REFL_QUAD_SAME) continue;
    s += w * c.rgb;
    ws += w;
  }
  m = ws > 0.0 ? s / ws : vec3(0.0);
  return ws >= REFL_REUSE_COVER;
}

vec3 refl_isg(uvec2 p, uint i) {
  Lobe L = lobe_at(p, i);
  uvec2 l = gl_LocalInvocationID.xy / 2u;
  uint q = l.y * REFL_QUADS + l.x, r = quad_rep[q];
  float t_bar = quad_t[q];
  // A pixel on another surface than its quad's representative searches for itself.
  if (r != i && range_fn(texelFetch(pack_geo, int(r)), L.P0, L.N0) < REFL_QUAD_SAME) {
    t_bar = search(L, i);
    atomicAdd(tile_searches, 1u);
  }
  Foot F = footprint(L, t_bar);
  vec3 m;
  if (F.R_s >= REFL_REUSE_RADIUS && reuse(L, F.R_s, m)) return albedo_of(L) * m;
  if (F.R_s >= 0.25) atomicAdd(tile_gathers, 1u);
  return gather(L, i, F);
}

void main() {
  uint tiles_x = (pc.width + REFL_TILE - 1u) / REFL_TILE;
  uint nt = tiles_x * ((pc.height + REFL_TILE - 1u) / REFL_TILE);
  // Dispatched over the tiles reflections.list kept: workgroup k (row-major in a grid tiles_x
  // wide) is tile tiles[list + k]; the last row's end is past the list.
  uint k_list = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (k_list >= tiles[REFL_AT_COUNT(nt)]) return;  // the whole workgroup
  uint tile = tiles[REFL_AT_LIST(nt) + k_list];
  uvec2 wg = uvec2(tile % tiles_x, tile / tiles_x);
  uvec2 p = wg * REFL_TILE + gl_LocalInvocationID.xy;
  bool inside = p.x < pc.width && p.y < pc.height;
  uint i = inside ? p.y * pc.width + p.x : 0u;
  if (gl_LocalInvocationIndex == 0u) { tile_glossy = 0u; tile_searches = 0u; tile_gathers = 0u; }
  if (gl_LocalInvocationIndex < REFL_TILE * REFL_TILE / 32u) glossy_bits[gl_LocalInvocationIndex] = 0u;
  barrier();
  bool g = inside && is_glossy(i);
  if (g) {
    atomicAdd(tile_glossy, 1u);
    atomicOr(glossy_bits[gl_LocalInvocationIndex >> 5u], 1u << (gl_LocalInvocationIndex & 31u));
  }
  barrier();
  // The quads' searches, each split over four lanes: lane q + part·QUADS² takes samples part,
  // part + 4, ... of quad q's lattice (whole SIMD rows of llvmpipe and whole warps on one part);
  // the partial sums are added in a fixed order. Then the blocks' wide gathers, over sixteen
  // lanes each. The condition is uniform. (Every tile here holds a glossy pixel: reflections.list.)
  if (REFL_MODE == REFL_MODE_ISG) {
    uint q = gl_LocalInvocationIndex % (REFL_QUADS * REFL_QUADS);
    uint part = gl_LocalInvocationIndex / (REFL_QUADS * REFL_QUADS);
    uvec2 base = wg * REFL_TILE + 2u * uvec2(q % REFL_QUADS, q / REFL_QUADS);
    uint r = REFL_NO_REP;
    uvec2 rp = base;
    for (uint k = 0u; k < 4u; ++k) {
      uvec2 pp = base + uvec2(k & 1u, k >> 1u);
      uint lp = (pp.y % REFL_TILE) * REFL_TILE + pp.x % REFL_TILE;  // its local index
      if (r == REFL_NO_REP && (glossy_bits[lp >> 5u] & (1u << (lp & 31u))) != 0u) {
        r = pp.y * pc.width + pp.x;
        rp = pp;
      }
    }
    if (r != REFL_NO_REP) {
      Lobe L = lobe_at(rp, r);
      part_sums[part * REFL_QUADS * REFL_QUADS + q] = vec4(search_sums(L, r, part, REFL_QUAD_PARTS), 0.0, 0.0);
    }
    barrier();
    if (part == 0u) {
      float t = 1.0;
      if (r != REFL_NO_REP) {
        vec4 st = vec4(0.0);
        for (uint k = 0u; k < REFL_QUAD_PARTS; ++k) st += part_sums[k * REFL_QUADS * REFL_QUADS + q];
        t = search_mean(st.xy);
        atomicAdd(tile_searches, 1u);
      }
      quad_rep[q] = r;
      quad_t[q] = t;
    }
    barrier();
    // The blocks' wide gathers, each split over sixteen lanes: lane b + part·BLOCKS² takes
    // samples part, part + 16, ... of block b's (its top-left quad's representative's).
    uint b = gl_LocalInvocationIndex % (REFL_BLOCKS * REFL_BLOCKS);
    uint bpart = gl_LocalInvocationIndex / (REFL_BLOCKS * REFL_BLOCKS);
    uint qb = 2u * (b / REFL_BLOCKS) * REFL_QUADS + 2u * (b % REFL_BLOCKS);
    uint rb = quad_rep[qb];
    bool wide = false;
    Foot F;
    if (rb != REFL_NO_REP) {
      uvec2 rbp = uvec2(rb % pc.width, rb / pc.width);
      Lobe L = lobe_at(rbp, rb);
      F = footprint(L, quad_t[qb]);
      wide = F.R_s >= REFL_REUSE_RADIUS;
      if (wide) part_sums[bpart * REFL_BLOCKS * REFL_BLOCKS + b] = gather_sums(L, rb, F, bpart, REFL_BLOCK_PARTS);
    }
    barrier();
    if (bpart == 0u) {
      vec4 g = vec4(0.0);
      if (wide)
        for (uint k = 0u; k < REFL_BLOCK_PARTS; ++k) g += part_sums[k * REFL_BLOCKS * REFL_BLOCKS + b];
      block_mean[b] = wide ? vec4(g.rgb / g.w, F.R_s) : vec4(0.0, 0.0, 0.0, -1.0);
      if (wide) atomicAdd(tile_gathers, 1u);
    }
  }
  barrier();
  vec3 c = inside ? texelFetch(pack_color, int(i)).rgb : vec3(0.0);
  if (g) c = REFL_MODE == REFL_MODE_BLUR ? refl_blur(p, i) : refl_isg(p, i);
  barrier();
  // The tile records how many pixels were glossy, how many searches and how many gathers ran
  // (the statistics behind --timings; the gathers in the second half of refl.tiles); the tiles
  // with nothing glossy were marked cheap by reflections.list.
  if (gl_LocalInvocationIndex == 0u) {
    tiles[tile] = floatBitsToUint(-float(tile_glossy + REFL_STATS_SEARCHES * tile_searches));
    tiles[nt + tile] = floatBitsToUint(float(tile_gathers));
  }
  if (!inside) return;
  uint n = pc.width * pc.height;
  glossy[i] = c.r; glossy[n + i] = c.g; glossy[2u * n + i] = c.b;
}
