#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_io.h"
#include "shadowmap_cssm_io.h"
// CSSM shading (thesis §5.2-5.3, Fig. 5.4): a box blocker search as wide as PCSS's, the
// average blocker depth from the prefiltered CSM and CSM-Z images (eq. 5.8, 5.11), the
// penumbra width from it, one prefiltered CSM lookup over that width (eq. 5.3, 5.10), ringing
// suppression (§5.2.3) and sharpening (eq. 5.9); each lookup split into sub-kernels with the
// receiver's depth at their centres where the receiver plane's depth changes across it (see
// cssm.cpp). Mirrors cssm_reference (cssm.cpp).
layout(local_size_x = SHADOWMAP_LOCAL, local_size_y = SHADOWMAP_LOCAL) in;
layout(std430, binding = 0) readonly buffer Prm { ShadowmapParams p; };
layout(std430, binding = 1) readonly buffer Cprm { CssmParams c; };
layout(std430, binding = 2) readonly buffer Geo { float geo[]; };
layout(std430, binding = 3) readonly buffer Fg { float fg_in[]; };
layout(std430, binding = 4) readonly buffer Hard { float hard[]; };
layout(std430, binding = 5) readonly buffer Smap { float smap[]; };
layout(std430, binding = 6) writeonly buffer Soft { float soft[]; };
layout(std430, binding = 7) buffer Stats { uint stats[]; };
layout(push_constant) uniform Push { ShadowmapPush pc; };
// Storage buffers, not texel views: on lavapipe (Mesa 22.3) this kernel ran 4x slower with its four
// planes read through texel views (52 -> 220 s at 1080p; reason not found), where every other
// gather got faster.
#define SHADOWMAP_STORAGE_BUFFERS
#include "shadowmap_common.h"
#define CSSM_TABLES_BINDING 8
#define CSSM_TABLES_READ
#include "shadowmap_cssm_common.h"

// A box kernel of half-width h texels about q, as SAT corners or as mip taps.
struct Kern {
  ivec4 X, Y;     // SAT: corner columns / rows X0, X0 + 1, X1, X1 + 1 (clamped to the map)
  vec3 wx, wy;    // SAT: weights of the span [X0, X1), the cell X0, the cell X1
  float inv;      // SAT: 1 / (fixed-point scale · clipped area)
  float area;     // the clipped area, block units²
  uint b0, b1;    // mip: first element of the two levels within a layer
  uvec4 i0, i1;   // mip: bilinear texels within each level's layer
  vec4 w0, w1;    // mip: their weights (the level blend included)
};

// Block units (the basis's texels): `bound` the map's extent, `n` the basis size.
void kern_axis(float qc, float h, float bound, uint size, out ivec4 X, out vec3 w, out float len) {
  float lo = max(qc - h, 0.0), hi = min(qc + h, bound);
  float X0 = floor(lo), X1 = floor(hi);
  int n = int(size);
  X = ivec4(int(X0), min(int(X0) + 1, n), int(X1), min(int(X1) + 1, n));
  w = vec3(1.0, -(lo - X0), hi - X1);
  len = hi - lo;
}

void kern_level(vec2 q, uint l, float wl, out uint b, out uvec4 idx, out vec4 wt) {
  uint lw = c.level_w[l], lh = c.level_h[l];
  vec2 u = vec2(q.x * float(lw) / float(c.level_w[0]), q.y * float(lh) / float(c.level_h[0])) - 0.5;
  vec2 i = floor(u), f = u - i;
  uint xa = uint(clamp(int(i.x), 0, int(lw) - 1)), xb = uint(clamp(int(i.x) + 1, 0, int(lw) - 1));
  uint ya = uint(clamp(int(i.y), 0, int(lh) - 1)), yb = uint(clamp(int(i.y) + 1, 0, int(lh) - 1));
  b = c.level_off[l];
  idx = uvec4(ya * lw + xa, ya * lw + xb, yb * lw + xa, yb * lw + xb);
  wt = wl * vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
}

// A box of half-widths h about q, both in map texels.
Kern make_kern(vec2 q, vec2 h) {
  Kern K;
  float lx, ly, f = float(1u << c.basis_shift);
  q /= f;
  h /= f;
  kern_axis(q.x, h.x, float(p.map_w) / f, c.level_w[0], K.X, K.wx, lx);
  kern_axis(q.y, h.y, float(p.map_h) / f, c.level_h[0], K.Y, K.wy, ly);
  K.inv = 1.0 / (c.sat_scale * lx * ly);
  K.area = lx > 0.0 && ly > 0.0 ? lx * ly : 0.0;
  // Mip level whose texel spans the kernel width 2h (of a rectangle, the square of its area);
  // linear between levels.
  float lev = clamp(log2(2.0 * (h.x == h.y ? h.x : sqrt(h.x * h.y))), 0.0, float(c.levels - 1u));
  uint l0 = uint(floor(lev)), l1 = min(l0 + 1u, c.levels - 1u);
  float t = lev - float(l0);
  kern_level(q, l0, 1.0 - t, K.b0, K.i0, K.w0);
  kern_level(q, l1, t, K.b1, K.i1, K.w1);
  return K;
}

uvec2 add64(uvec2 a, uvec2 b) {
  uint cy;
  uint lo = uaddCarry(a.x, b.x, cy);
  return uvec2(lo, a.y + b.y + cy);
}
uvec2 sub64(uvec2 a, uvec2 b) {
  uint br;
  uint lo = usubBorrow(a.x, b.x, br);
  return uvec2(lo, a.y - b.y - br);
}
float to_float(uvec2 v) {  // two's complement int64, magnitude first (no cancellation)
  bool neg = (v.y & 0x80000000u) != 0u;
  if (neg) v = add64(~v, uvec2(1u, 0u));
  float r = float(v.y) * 4294967296.0 + float(v.x);
  return neg ? -r : r;
}

// Inclusive SAT entry (x, y) = sum over [0, x) x [0, y).
uvec2 sat_at(uint layer, int x, int y) {
  if (x <= 0 || y <= 0) return uvec2(0u);
  uint j = uint(y - 1) * c.level_w[0] + uint(x - 1);
  return uvec2(cssm_get(layer, 2u * j), cssm_get(layer, 2u * j + 1u));
}

// The box average of basis layer `layer` (eq. 5.3: w * B_i).
float cssm_box(uint layer, Kern K) {
  if (c.prefilter == CSSM_FILTER_SAT) {
    uvec2 S[16];
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) S[a * 4 + b] = sat_at(layer, K.X[a], K.Y[b]);
    // The continuous box integral of the texel-constant layer: whole spans exactly in the
    // integers, the fractional border cells weighted (9 rectangles).
    const ivec2 span[3] = ivec2[3](ivec2(0, 2), ivec2(0, 1), ivec2(2, 3));
    float sum = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        float w = K.wx[a] * K.wy[b];
        if (w == 0.0) continue;
        ivec2 sa = span[a], sb = span[b];
        uvec2 r = sub64(add64(S[sa.y * 4 + sb.y], S[sa.x * 4 + sb.x]),
                        add64(S[sa.x * 4 + sb.y], S[sa.y * 4 + sb.x]));
        sum += w * to_float(r);
      }
    return sum * K.inv;
  }
  uvec4 j0 = K.b0 + K.i0, j1 = K.b1 + K.i1;
  vec4 v0 = uintBitsToFloat(uvec4(cssm_get(layer, j0.x), cssm_get(layer, j0.y),
                                  cssm_get(layer, j0.z), cssm_get(layer, j0.w)));
  vec4 v1 = uintBitsToFloat(uvec4(cssm_get(layer, j1.x), cssm_get(layer, j1.y),
                                  cssm_get(layer, j1.z), cssm_get(layer, j1.w)));
  return dot(K.w0, v0) + dot(K.w1, v1);
}

// The raw filtered visibility s_f of kernel K against the normalised receiver depth dn (eq. 5.3,
// 5.10); with csm_z, CSM-Z's numerator w * (f̄ z) instead (eq. 5.11:
// (w * z)/2 + Σ 2/c_k [sin(c_k δ)(w * z cos) − cos(c_k δ)(w * z sin)]).
float cssm_lookup(Kern K, float dn, bool csm_z) {
  float delta = c.s_z * dn - c.x0;
  float v = csm_z ? 0.5 * cssm_box(4u * c.order, K) : 0.5;
  uint base = csm_z ? 2u * c.order : 0u;
  for (uint k = 0u; k < c.order; ++k) {
    float m = float(2u * k + 1u);
    vec2 cs = cssm_cis(m, delta);
    float t = 2.0 / (3.14159265358979 * m) *
              (cs.y * cssm_box(base + k, K) - cs.x * cssm_box(base + c.order + k, K));
    v += csm_z ? t : -t;
  }
  return v;
}

// Sub-kernels along one axis: the receiver-plane threshold's range over the kernel's extent
// along it (lo, hi through q), in units of the step shift x0, rounded up, in [1, max_split];
// 1 where the neighbours do not confirm the plane (not extrapolated).
uint cssm_split(vec3 q, vec4 g, float tw, vec2 lo, vec2 hi) {
  if (g.w < SHADOWMAP_TRUSTED_SLOPE) return 1u;
  vec2 tr = sm_threshold_range(q, g, lo, hi, tw);
  float r = c.s_z * (tr.y - tr.x) / c.zrange / c.x0;
  return r > float(c.max_split) ? c.max_split : (r > 1.0 ? uint(ceil(r)) : 1u);
}

// The same over half-width h about the receiver q, split into nx x ny sub-kernels each
// against the receiver's depth at its centre (cssm.cpp). d: the pixel's own (nx = ny = 1).
float cssm_filtered(vec3 q, vec4 g, float tw, float h, float d, bool csm_z) {
  uint nx = cssm_split(q, g, tw, vec2(q.x - h, q.y), vec2(q.x + h, q.y));
  uint ny = cssm_split(q, g, tw, vec2(q.x, q.y - h), vec2(q.x, q.y + h));
  if (nx * ny == 1u) return cssm_lookup(make_kern(q.xy, vec2(h)), d, csm_z);
  vec2 sh = vec2(h / float(nx), h / float(ny));
  float sum = 0.0, area = 0.0;
  for (uint j = 0u; j < ny; ++j)
    for (uint i = 0u; i < nx; ++i) {
      vec2 b = q.xy - h + vec2(float(2u * i + 1u), float(2u * j + 1u)) * sh;
      Kern K = make_kern(b, sh);
      if (K.area <= 0.0) continue;
      float dn = clamp((sm_threshold(q, g, b, tw) - c.zmin) / c.zrange, 0.0, 1.0);
      sum += K.area * cssm_lookup(K, dn, csm_z);
      area += K.area;
    }
  return area > 0.0 ? sum / area : cssm_lookup(make_kern(q.xy, vec2(h)), d, csm_z);
}

// Ringing suppression (§5.2.3, Fig. 5.2c-d): scale about 1/2, then clamp.
float cssm_suppress(float s) { return clamp(c.alpha * (s - 0.5) + 0.5, 0.0, 1.0); }

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= pc.width || px.y >= pc.height) return;
  uint i = px.y * pc.width + px.x;
  if (fg_in[i] == 0.0) { soft[i] = hard[i]; return; }
  vec3 P = sm_rel(i);  // P − light
  vec3 q = sm_project(P);
  if (!sm_inside(q)) { soft[i] = hard[i]; return; }
  atomicAdd(stats[SHADOWMAP_STAT_PIXELS], 1u);
  bool back;
  vec4 g = sm_receiver_plane(px, q, P, back);
  if (back) { atomicAdd(stats[SHADOWMAP_STAT_SKIPPED], 1u); soft[i] = hard[i]; return; }
  float texel_world = 2.0 * q.z * p.tan_y / float(p.map_h);
  float k = p.light_radius * float(p.map_h) / (2.0 * p.tan_y);  // texels per unit of 1/d − 1/z
  // Receiver depth d: the biased receiver-plane threshold at its own texel centre, normalised.
  vec2 cc = floor(q.xy) + 0.5;
  float d = clamp((sm_threshold(q, g, cc, texel_world) - c.zmin) / c.zrange, 0.0, 1.0);
  // Blocker search (Fig. 5.1a): PCSS's disk as a box of the same area, at least one texel.
  float hs = sm_cone_box(k, p.min_depth, q.z, 1.0);
  float s_f = cssm_filtered(q, g, texel_world, hs, d, false);
  if (cssm_suppress(s_f) >= 1.0 || 1.0 - s_f < 1e-3) {
    atomicAdd(stats[SHADOWMAP_STAT_SKIPPED], 1u);  // no blockers: fully lit
    soft[i] = sm_input_edges(1.0, hard[i], 0.0);
    return;
  }
  float num = cssm_filtered(q, g, texel_world, hs, d, true);  // CSM-Z (eq. 5.11)
  float z_avg = clamp(num / (1.0 - s_f), 0.0, d);  // eq. 5.8
  float zb = c.zmin + z_avg * c.zrange;
  // The search narrowed to the blockers' cone (cssm.cpp), while it shrinks: blockers outside the
  // light's cone at the mean blocker depth cannot shadow the receiver, but pulled the mean
  // towards its depth (PCSS's region is as wide as the nearest possible blocker's cone).
  for (uint pass = 0u; pass < c.narrow; ++pass) {
    float hn = sm_cone_box(k, zb, q.z, CSSM_NARROW_MARGIN);
    if (hn >= hs) break;
    float sn = cssm_filtered(q, g, texel_world, hn, d, false);
    if (cssm_suppress(sn) >= 1.0 || 1.0 - sn < 1e-3) {
      atomicAdd(stats[SHADOWMAP_STAT_SKIPPED], 1u);  // none of them reaches it: fully lit
      soft[i] = sm_input_edges(1.0, hard[i], 0.0);
      return;
    }
    z_avg = clamp(cssm_filtered(q, g, texel_world, hn, d, true) / (1.0 - sn), 0.0, d);
    zb = c.zmin + z_avg * c.zrange;
    hs = hn;
  }
  // Penumbra width (§5.3.1): rf = k (1/z_avg − 1/d).
  float rf = k * max(1.0 / zb - 1.0 / q.z, 0.0);
  if (rf > p.max_radius) { rf = p.max_radius; atomicAdd(stats[SHADOWMAP_STAT_CLAMPED], 1u); }
  float v = cssm_suppress(cssm_filtered(q, g, texel_world, max(SM_BOX_OF_DISK * rf, 0.5), d, false));
  float pw = 1.0 + c.sharpen_a * exp(-c.sharpen_b * (d - z_avg));  // eq. 5.9
  // A blocker nearer the receiver than x0 / s_z of the depth range shadows it by less than half
  // (cssm.cpp): the expansion cannot place the penumbrae such blockers cast, so the input's edge
  // stands up to the radius of one at that depth (issue 19).
  float zh = c.zmin + max(d - c.x0 / c.s_z, 0.0) * c.zrange;
  float r_half = min(k * max(1.0 / zh - 1.0 / q.z, 0.0), p.max_radius);
  soft[i] = sm_input_edges_at(pow(v, pw), hard[i], rf, r_half);
}
