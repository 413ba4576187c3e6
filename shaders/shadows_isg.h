// GLSL only: what the four dispatches of shadows.isg share (shadows.isg.reach, .quads, the
// pixels' and .own; the layout of their records in the tiles buffer is shadows_isg_io.h's):
// their bindings, the receiver, the parameter search, the gather and the quads' reuse (paper
// §3.1; lib/effects/shadows/isg.cpp mirrors every step in double).
#ifndef SHADOWS_ISG_H
#define SHADOWS_ISG_H
#include "shadows_isg_io.h"
#include "isg_sampling.h"
// Inputs are texel views (lavapipe gathers texels as vectors; gpu.h's Slot::texels).
layout(binding = 0) uniform samplerBuffer pack;  // P − eye, L.shadow (shadows.isg.tiles)
layout(binding = 1) uniform samplerBuffer occluder;
layout(std430, binding = 2) buffer Tiles { uint tiles[]; };
layout(std430, binding = 3) buffer Soft { float soft[]; };
// The search lattice (grid_s² entries) then the gather lattice (grid_g²): concentric-disk
// points made on the host, (x, y) of each texel.
layout(binding = 4) uniform samplerBuffer samples;
layout(binding = 5) uniform samplerBuffer shadow_in;  // L.shadow, which stands where no occluder is within reach
layout(push_constant) uniform Push { ShadowsIsgPush pc; };
// SHADOWS_ISG_* settings: compiled in, not branched on (gpu::Kernel).
layout(constant_id = 0) const uint FLAGS = 0u;

mat3 rot() {  // world -> camera; GLSL matrices are column-major
  return mat3(pc.r00, pc.r10, pc.r20, pc.r01, pc.r11, pc.r21, pc.r02, pc.r12, pc.r22);
}
vec3 light() { return vec3(pc.light_x, pc.light_y, pc.light_z); }  // light − eye
bool foreground(vec4 t) { return t.w > 0.5 * SHADOWS_ISG_BACKGROUND; }

// P's screen derivative at pixel p along e (one-sided next to a silhouette): receiver() takes
// the receiver's normal from two of them.
vec3 axis_diff(uvec2 p, vec3 P0, uvec2 e) {
  uvec2 a = p - e, b = p + e;
  vec4 ta = p.x >= e.x && p.y >= e.y ? texelFetch(pack, int(a.y * pc.width + a.x)) : vec4(SHADOWS_ISG_BACKGROUND);
  vec4 tb = b.x < pc.width && b.y < pc.height ? texelFetch(pack, int(b.y * pc.width + b.x)) : vec4(SHADOWS_ISG_BACKGROUND);
  bool ha = foreground(ta), hb = foreground(tb);
  vec3 f = hb ? tb.xyz - P0 : vec3(0.0);
  vec3 g = ha ? P0 - ta.xyz : vec3(0.0);
  if (ha && hb) {
    float lf = length(f), lg = length(g);
    if (max(lf, lg) < 2.0 * min(lf, lg)) return f + g;
    return lf < lg ? f : g;
  }
  return ha ? g : f;
}

// The distance along the light's direction wl that across() takes off dP, the depth at which
// the penumbra's cross-section is measured: an occluder at distance d from a point dP away from
// p_0 lies d + along(dP, wl) from p_0 (sphere lights: along the ray; disk and rect lights: up to
// the plane through dP parallel to the light's, so that an occluder parallel to the light keeps
// its distance).
float along(vec3 dP, vec3 wl) {
  if ((FLAGS & SHADOWS_ISG_ORIENTED) == 0u) return dot(dP, wl);
  vec3 n = vec3(pc.light_nx, pc.light_ny, pc.light_nz);
  float c = dot(wl, n);
  c = c < 0.0 ? min(c, -SHADOWS_ISG_MIN_COS) : max(c, SHADOWS_ISG_MIN_COS);
  return dot(dP, n) / c;
}

// The distance from p_0 in the penumbra's cross-section: dP projected along the light direction
// wl onto the plane across the ray (sphere lights: the silhouette faces every receiver) or onto
// the light's own plane (disk and rect lights).
float across(vec3 dP, vec3 wl) {
  float a = along(dP, wl);
  if ((FLAGS & SHADOWS_ISG_ORIENTED) == 0u) return sqrt(max(dot(dP, dP) - a * a, 0.0));  // unit wl
  return length(dP - a * wl);
}

// Eq. 6-7 without inShadow: a gaussian of the world distance l (scene_radius units), from
// l² = |dP|² (no square root).
float range_l2(float l2) { return exp(-l2 * (pc.inv_scene_radius * pc.inv_scene_radius * pc.inv_sigma)); }
// Eq. 6-7's weight between pixel j's position and P0 (both P − eye).
float same_surface(uint j, vec3 P0) {
  vec3 d = texelFetch(pack, int(j)).xyz - P0;
  return range_l2(dot(d, d));
}
// Eq. 8: the penumbra radius R_s on the receiver for an occluder at d, the light at D.
float penumbra(float d, float D) { return pc.light_size * d / max(D - d, SHADOWS_ISG_MIN_GAP * D); }

// A foreground receiver: its position (P − eye), distance to the light, direction to it, the
// world size of a pixel there (Camera::pixel_size_at) shrunk by c = cos θ_i (the receiver's
// normal from P's screen derivatives, one-sided next to a silhouette; c at least
// 1 / SHADOWS_ISG_MAX_STRETCH), and the screen direction `dir` of the light's direction projected onto
// the receiver. The penumbra's footprint on the receiver (the disk of radius R_s across the ray,
// projected along it) is an ellipse: R_s / c along that direction, R_s across it (issue 19).
struct Recv {
  vec3 P0, wl, n;  // n: the receiver's normal on the light's side, 0 where P gives none
  float D, pix, inv_pix, c;
  vec2 dir;
};
Recv receiver(uvec2 p, vec3 P0) {
  Recv R;
  R.P0 = P0;
  vec3 cc = rot() * P0;
  float z = max(-cc.z, 1e-6);
  R.D = length(light() - P0);
  R.wl = (light() - P0) / max(R.D, 1e-20);
  R.c = 1.0;
  R.dir = vec2(1.0, 0.0);
  R.n = vec3(0.0);
  vec3 n = cross(axis_diff(p, P0, uvec2(1u, 0u)), axis_diff(p, P0, uvec2(0u, 1u)));
  float ln = length(n);
  if (ln > 0.0) {
    n /= ln;
    R.n = dot(n, R.wl) < 0.0 ? -n : n;
    R.c = max(abs(dot(n, R.wl)), 1.0 / SHADOWS_ISG_MAX_STRETCH);
    // The screen image of t = wl − (wl·n) n at P0 (the derivative of the projection).
    vec3 dc = rot() * (R.wl - dot(R.wl, n) * n);
    vec2 d = vec2(dc.z * cc.x - cc.z * dc.x, cc.z * dc.y - dc.z * cc.y);
    if (dot(d, d) > 1e-20) R.dir = normalize(d);
  }
  R.pix = z / pc.f_px * R.c;
  R.inv_pix = 1.0 / R.pix;
  return R;
}
// The sample lattice at p for a footprint of `raw` pixels along R.dir (R_s / R.pix, unclamped):
// the unit lattice turned by the pixel's hash angle, then stretched to the ellipse of radii
// min(raw, max_radius) along R.dir and min(raw·c, max_radius) across it, so that every sample
// lands where the penumbra can reach (a disk of the long radius would waste 1 − c of them).
mat2 lattice(uvec2 p, Recv R, float raw) {
  float ang = (FLAGS & SHADOWS_ISG_ROTATE) != 0u ? isg_pixel_angle(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) : 0.0;
  float ca = cos(ang), sa = sin(ang);
  float a = min(raw, pc.max_radius), b = min(raw * R.c, pc.max_radius), o = (a - b) * R.dir.x * R.dir.y;
  mat2 E = mat2(a * R.dir.x * R.dir.x + b * R.dir.y * R.dir.y, o, o, a * R.dir.y * R.dir.y + b * R.dir.x * R.dir.x);
  return E * mat2(ca, sa, -sa, ca);
}

// Parameter search (eq. 4, 6, 7) at p over the footprint of Rp pixels (unclamped, along R.dir):
// occluder distances weighted by r = gaussian · inShadow, the centre tap included, each measured
// from p_0 (the tap's L.occluder plus the tap's offset along the light's direction). The mean
// occluder distance, or -1 where no occluder is within reach (the hard shadow stands).
// The sums of lattice samples part, part + parts, ... (the centre tap in part 0): a quad's
// search is split over its four lanes.
vec2 search_sums(Recv R, uvec2 p, uint i, float Rp, uint part, uint parts) {
  float s0 = texelFetch(shadow_in, int(i)).r, o0 = texelFetch(occluder, int(i)).r;
  float sw = 0.0, swd = 0.0;
  if (part == 0u && s0 < 1.0 && o0 > 0.0) {
    sw = 1.0 - s0;
    swd = sw * o0;
  }
  vec2 p0 = vec2(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) + 0.5;  // frame coordinates
  ivec2 org = ivec2(pc.origin & 0xffffu, pc.origin >> 16);
  uint grid_search = pc.grids & 0xffffu;
  mat2 Rot = lattice(p, R, Rp);
  for (uint k = part; k < grid_search * grid_search; k += parts) {
    vec2 x = p0 + Rot * texelFetch(samples, int(k)).xy - 0.5;
    vec2 x0 = floor(x), f = x - x0;
    ivec2 xa = ivec2(x0) - org;
    for (int j = 0; j < 4; ++j) {
      ivec2 xx = xa + ivec2(j & 1, j >> 1);
      if (xx.x < 0 || xx.y < 0 || xx.x >= int(pc.width) || xx.y >= int(pc.height)) continue;
      int t = xx.y * int(pc.width) + xx.x;
      vec4 Tt = texelFetch(pack, int(t));
      if (!foreground(Tt) || !(Tt.w < 1.0)) continue;
      vec3 dP = Tt.xyz - R.P0;
      float ot = texelFetch(occluder, int(t)).r;
      if (!(ot > 0.0)) continue;
      // The tap's occluder seen from p_0: its distance from p_0, not from the tap (they differ
      // by along(dP), large along a receiver under a grazing sphere light).
      ot += along(dP, R.wl);
      if (!(ot > 0.0)) continue;  // behind p_0
      float bw = ((j & 1) != 0 ? f.x : 1.0 - f.x) * ((j >> 1) != 0 ? f.y : 1.0 - f.y);
      float r = range_l2(dot(dP, dP)) * (1.0 - Tt.w) * bw;
      float l = across(dP, R.wl);
      if ((FLAGS & SHADOWS_ISG_SEARCH_REACH) != 0u) {
        // PCSS's blocker test in image space: the occluder lies in p_0's cone to the light.
        float Rt = penumbra(ot, R.D);
        r *= clamp((SHADOWS_ISG_REACH * Rt + R.pix - l) * R.inv_pix, 0.0, 1.0);
      }
      sw += r;
      swd += r * ot;
    }
  }
  return vec2(sw, swd);
}
float search_mean(vec2 s) { return s.x > 0.0 ? s.y / s.x : -1.0; }

// A tap's share of p_0's irradiance (issue 19), relative to the light's centre. Through an
// occluder at distance d, the tap at offset cs across the light direction (its cross-section
// offset, |cs| = across()) casts the shadow of the light point w = cs · L / R_s from the light's
// centre (eq. 8's similar triangles: the ray from p_0 through the occluder point that blocks the
// tap's own ray to the centre), so the gather's uniform weight over the cross-section is uniform
// over the light's disk. The renderer's soft shadow weighs each point of the light by the
// irradiance it gives p_0: at r = D·wl + w, max(n·r, 0) · |n_l·r| / |r|⁴ (the receiver's cosine,
// the emitter's, the inverse square; n_l = wl for a sphere light, whose disk faces p_0). Under a
// low light its top lights a floor several times as much as its bottom, and the part below the
// receiver's horizon not at all. 1 where the receiver's normal is unknown.
// In the gather's loop (issue 18) the weight is taken apart: n·r = D·(n·wl) + k·(n·dP − a·(n·wl))
// with k = L / R_s and a = along(dP, wl), and |r|² / D² = 1 + 2k·(wl·cs) / D + k²·|cs|² / D²
// (wl·cs = 0 for a sphere light), so that a tap costs a dot product and a division; Irr holds
// what is the same for every tap of one gather. lib/effects/shadows/isg.cpp keeps the formula.
struct Irr {
  vec3 nk;               // k·n (0 where n is unknown)
  float A, kcn, inv, kk, k2D, k, nlw;
  bool hn;               // n is known (else every weight is 1)
};
Irr irradiance_setup(Recv R, float Rs) {
  Irr I;
  I.k = pc.light_size / max(Rs, 1e-30);
  bool hn = R.n != vec3(0.0);
  I.hn = hn;
  float cn = dot(R.n, R.wl);
  I.nk = I.k * R.n;
  I.A = hn ? R.D * cn : 1.0;
  I.kcn = I.k * cn;
  I.inv = hn ? 1.0 / (R.D * max(cn, SHADOWS_ISG_MIN_CN)) : 1.0;
  I.kk = hn ? I.k * I.k / (R.D * R.D) : 0.0;
  I.k2D = hn ? 2.0 * I.k / R.D : 0.0;
  I.nlw = dot(vec3(pc.light_nx, pc.light_ny, pc.light_nz), R.wl);
  return I;
}
// The weight of the tap at dP (a = along(dP, wl), cs = dP − a·wl, l2 = |cs|²).
float irradiance(Irr I, Recv R, vec3 dP, float a, vec3 cs, float l2) {
  float num = max(I.A + dot(I.nk, dP) - a * I.kcn, 0.0);
  float rr = 1.0 + I.kk * l2;
  float e = 1.0;
  if ((FLAGS & SHADOWS_ISG_ORIENTED) != 0u && I.hn) {
    vec3 nl = vec3(pc.light_nx, pc.light_ny, pc.light_nz);
    rr += I.k2D * dot(R.wl, cs);
    e = abs(R.D * I.nlw + I.k * dot(nl, cs)) / (R.D * max(abs(I.nlw), SHADOWS_ISG_MIN_COS));
  }
  return num * I.inv * e / (rr * rr);
}

// Gather (eq. 4) over the shadow bits: over the points within R_s of p_0 across the light
// direction (a one-pixel ramp at the rim), each weighed by its light point's irradiance
// (irradiance()): on the receiver, the penumbra's footprint, stretched by 1 / cos θ_i; on
// grazing receivers the screen disk, which reaches far along the surface, is cut back to it.
// The gaussian of eq. 6 as range function. Bilinear taps, here and in the search: the shadow
// bits are a binary signal, and point taps of them alias (issue 18: isg-synth contact's error
// rose 40 % with point taps in the gather, shared contact's 7 % at 9 search samples with point
// taps in the search).
vec2 gather_sums(Recv R, uvec2 p, uint i, float Rs, uint part, uint parts) {
  float sum = part == 0u ? texelFetch(shadow_in, int(i)).r : 0.0, ws = part == 0u ? 1.0 : 0.0;
  vec2 p0 = vec2(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) + 0.5;
  ivec2 org = ivec2(pc.origin & 0xffffu, pc.origin >> 16);
  uint grid_search = pc.grids & 0xffffu, grid_gather = pc.grids >> 16;
  mat2 Rog = lattice(p, R, Rs * R.inv_pix);
  Irr I = irradiance_setup(R, Rs);
  for (uint k = part; k < grid_gather * grid_gather; k += parts) {
    vec2 x = p0 + Rog * texelFetch(samples, int(grid_search * grid_search + k)).xy - 0.5;
    vec2 x0 = floor(x), f = x - x0;
    ivec2 xa = ivec2(x0) - org;
    for (int j = 0; j < 4; ++j) {
      ivec2 xx = xa + ivec2(j & 1, j >> 1);
      if (xx.x < 0 || xx.y < 0 || xx.x >= int(pc.width) || xx.y >= int(pc.height)) continue;
      vec4 Tt = texelFetch(pack, int(xx.y * int(pc.width) + xx.x));
      if (!foreground(Tt)) continue;
      vec3 dP = Tt.xyz - R.P0;
      float a = along(dP, R.wl), dd = dot(dP, dP);
      vec3 cs = dP - a * R.wl;
      float l2 = (FLAGS & SHADOWS_ISG_ORIENTED) == 0u ? max(dd - a * a, 0.0) : dot(cs, cs);
      float l = sqrt(l2);
      float bw = ((j & 1) != 0 ? f.x : 1.0 - f.x) * ((j >> 1) != 0 ? f.y : 1.0 - f.y);
      float r = range_l2(dd) * clamp((Rs + 0.5 * R.pix - l) * R.inv_pix, 0.0, 1.0) * bw *
                irradiance(I, R, dP, a, cs, l2);
      sum += r * Tt.w;
      ws += r;
    }
  }
  return vec2(sum, ws);
}

// The tile's listing (shadows.isg.list): workgroup k of a dispatch over the listed tiles (a grid
// tiles_x wide) is tile tiles[list + k]; false past the list's end (the last row's rest).
bool listed_tile(out uint tile, out uvec2 wg, out uint nt) {
  uint tiles_x = (pc.width + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE;
  nt = tiles_x * ((pc.height + SHADOWS_ISG_TILE - 1u) / SHADOWS_ISG_TILE);
  uint k = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (k >= tiles[SHADOWS_ISG_AT_COUNT(nt)]) return false;
  tile = tiles[SHADOWS_ISG_AT_LIST(nt) + k];
  wg = uvec2(tile % tiles_x, tile / tiles_x);
  return true;
}
// Quad q of a tile (QUADS x QUADS of them, row-major; a quad is 2x2 pixels): its record.
#define QUADS (SHADOWS_ISG_TILE / 2u)
// The searches and gathers of shadows.isg.quads and .own: a lane a sum (one pixel's or quad's)
// on a CPU device (lavapipe: a lane's fixed cost paid once, a vector of 8 lanes running every
// lane's loop masked); on a GPU PART_LANES lanes a sum, each a strided part of it, the parts added
// in order across the sum's lanes (PART_LANES times the lanes, each a 1/PART_LANES of the loop;
// with a lane a sum .quads and .own took 0.119 + 0.102 of the H200's 0.254 ms at 1080p). The
// orders of the additions agree within float rounding (tests/gpu/test_shadows_isg.cpp runs them).
#ifdef SHADOWS_ISG_PARTED
// The lanes of a sum (1, or a power of two up to the subgroup size): gpu::Kernel's
// specialization constant 1, the workgroup SHADOWS_ISG_PARTED sums wide.
layout(constant_id = 1) const uint PART_LANES = 1u;
layout(local_size_x = SHADOWS_ISG_PARTED, local_size_y_id = 1) in;
// The lane's sum within the workgroup and its part of it. A sum's lanes are consecutive
// invocations of one subgroup (subgroups are whole, the workgroup being a multiple of the
// subgroup size on the devices isg runs on).
uint sum_slot() {
  return PART_LANES == 1u ? gl_LocalInvocationIndex
                          : (gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID) / PART_LANES;
}
uint sum_part() { return PART_LANES == 1u ? 0u : gl_SubgroupInvocationID % PART_LANES; }
// The sum from the lane's part: the parts added in order.
vec2 parts_added(vec2 mine) {
  if (PART_LANES == 1u) return mine;
  uint first = gl_SubgroupInvocationID - sum_part();
  vec2 s = subgroupShuffle(mine, first);
  for (uint k = 1u; k < PART_LANES; ++k) s += subgroupShuffle(mine, first + k);
  return s;
}
vec2 search_total(Recv R, uvec2 p, uint i, float Rp) {
  return parts_added(search_sums(R, p, i, Rp, sum_part(), PART_LANES));
}
vec2 gather_total(Recv R, uvec2 p, uint i, float Rs) {
  return parts_added(gather_sums(R, p, i, Rs, sum_part(), PART_LANES));
}
#endif
uint quad_at(uint nt, uint tile, uint q) { return SHADOWS_ISG_AT_QUADS(nt) + 4u * (tile * QUADS * QUADS + q); }
uint quad_of(uvec2 l) { return (l.y / 2u) * QUADS + l.x / 2u; }  // l: the pixel within its tile

// A wide penumbra's gather (R_g ≥ SHADOWS_ISG_REUSE_RADIUS) moves little from one pixel to the
// next: bilinear from the representatives' gathers around the pixel in the tile's quad grid, from
// those on its surface (eq. 6 weight ≥ SHADOWS_ISG_QUAD_SAME) whose R_g is within a factor
// SHADOWS_ISG_REUSE_RATIO of its own. False where they hold under SHADOWS_ISG_REUSE_COVER of the
// bilinear weight: the pixel gathers for itself.
bool reuse(uvec2 l, uint nt, uint tile, vec3 P0, float Rg, out float m) {
  uvec2 q0;  // the lower corner of the quads around the pixel (at their top-left pixels)
  vec2 a;
  isg_quad_bilinear(l, QUADS, q0, a);
  float s = 0.0, ws = 0.0;
  for (uint k = 0u; k < 4u; ++k) {
    uint q = (q0.y + (k >> 1u)) * QUADS + q0.x + (k & 1u);
    float w = isg_quad_weight(a, k);
    uint at = quad_at(nt, tile, q);
    vec2 g = vec2(uintBitsToFloat(tiles[at + 2u]), uintBitsToFloat(tiles[at + 3u]));
    if (w <= 0.0 || g.y < 0.0 || g.y * SHADOWS_ISG_REUSE_RATIO < Rg || Rg * SHADOWS_ISG_REUSE_RATIO < g.y) continue;
    if (same_surface(tiles[at], P0) < SHADOWS_ISG_QUAD_SAME) continue;
    s += w * g.x;
    ws += w;
  }
  m = ws > 0.0 ? s / ws : 0.0;
  return ws >= SHADOWS_ISG_REUSE_COVER;
}

// The quads around the pixel's own in its tile (the 3x3 about it, l its place in the tile) whose
// search found an occluder, their representatives on the pixel's surface (eq. 6 weight ≥
// SHADOWS_ISG_QUAD_SAME) where `surfaces` holds: how many, and the sum of their distances.
uint found_around(uvec2 l, uint nt, uint tile, vec3 P0, bool surfaces, out float sd) {
  ivec2 qc = ivec2(l / 2u);
  uint n = 0u;
  sd = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 qn = qc + ivec2(dx, dy);
      if (qn.x < 0 || qn.y < 0 || qn.x >= int(QUADS) || qn.y >= int(QUADS)) continue;
      uint at = quad_at(nt, tile, uint(qn.y) * QUADS + uint(qn.x));
      float d = uintBitsToFloat(tiles[at + 1u]);
      if (!(d >= 0.0) || (surfaces && same_surface(tiles[at], P0) < SHADOWS_ISG_QUAD_SAME)) continue;
      sd += d;
      ++n;
    }
  return n;
}
// For a pixel whose quad's search found no occluder (issue 19: lit specks in wide penumbrae): the
// mean distance of the quads around on its surface where at least SHADOWS_ISG_BORROW_MIN found
// one, -1 else (shadows.isg.own).
float borrowed_d(uvec2 l, uint nt, uint tile, vec3 P0) {
  float sd;
  uint n = found_around(l, nt, tile, P0, true, sd);
  return n >= uint(SHADOWS_ISG_BORROW_MIN) ? sd / float(n) : -1.0;
}
// Whether borrowed_d can find enough quads, their surfaces not yet looked at: the records'
// distances alone, so that shadows.isg, where every lane of a group runs what one needs on
// lavapipe, pays no more than their loads (the pixel pass 9.4 -> 13 ms at 1080p isg-synth
// contact; 17.7 with borrowed_d there). shadows.isg lists the pixels for which it holds.
bool may_borrow(uvec2 l, uint nt, uint tile) {
  float sd;
  return found_around(l, nt, tile, vec3(0.0), false, sd) >= uint(SHADOWS_ISG_BORROW_MIN);
}

// Eq. 5 and 8 in pixels at the receiver: the penumbra radius an occluder at distance d casts,
// unclamped (0 where d is not positive: no occluder).
float radius_px(Recv R, float d) { return d > 0.0 ? penumbra(d, R.D) / R.pix : 0.0; }
// The pixel's penumbra from its mean occluder distance d ≥ 0 (eq. 8-9): true where the quads
// around lend their gathers (reuse(), into m), false where the pixel gathers for itself;
// `clamped` also records a radius R_g over max_radius. shadows.isg and shadows.isg.own.
bool lent(uvec2 l, uint nt, uint tile, Recv R, float d, inout bool clamped, out float m) {
  float Rg_raw = radius_px(R, d);
  clamped = clamped || Rg_raw > pc.max_radius;
  float Rg = min(Rg_raw, pc.max_radius);
  m = 0.0;
  return Rg >= SHADOWS_ISG_REUSE_RADIUS && reuse(l, nt, tile, R.P0, Rg, m);
}

#endif
