#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_EXT_control_flow_attributes : require
#include "shadowmap_io.h"
#include "shadowmap_cssm_io.h"
// CSSM shading (thesis §5.2-5.3, Fig. 5.4): a box blocker search as wide as PCSS's, the
// average blocker depth from the prefiltered CSM and CSM-Z images (eq. 5.8, 5.11), the
// penumbra width from it, one prefiltered CSM lookup over that width (eq. 5.3, 5.10), ringing
// suppression (§5.2.3) and sharpening (eq. 5.9); each lookup split into sub-kernels with the
// receiver's depth at their centres where the receiver plane's depth changes across it (see
// cssm.cpp). Mirrors cssm_reference (cssm.cpp).
// One lookup site: every lookup of a pixel (the search, its narrowed passes, the filter) runs
// through the one loop of main and the one sub-kernel loop of cssm_filtered, and a lookup
// reads four basis images a load. Written as the thesis's steps one after the other, with the
// lookup inlined at each, LLVM took ten minutes to compile this kernel on lavapipe (issue 51).
layout(local_size_x = SHADOWMAP_LOCAL, local_size_y = SHADOWMAP_LOCAL) in;
layout(std430, binding = 0) readonly buffer Prm { ShadowmapParams p_in; };
layout(std430, binding = 1) readonly buffer Cprm { CssmParams c_in; };
// Copies made once at the top of main: read from the buffers in the lookups' inner loops, the
// parameters cost lavapipe a load each time (as shadowmap_pcss's p).
ShadowmapParams p;
CssmParams c;
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
layout(binding = 8) uniform usamplerBuffer tab;  // shadowmap_cssm_io.h, as texels
layout(std430, binding = 9) readonly buffer Tz { uint tz[]; };
layout(std430, binding = 10) readonly buffer Hsm { vec2 hsm[]; };
layout(std430, binding = 11) buffer Own { uint own[]; };
#define SHADOWMAP_STORAGE_BUFFERS
#define SHADOWMAP_COUNTS
#define SHADOWMAP_OWN
#include "shadowmap_common.h"
#define SM_HSM c.hsm
vec2 sm_hsm_texel(uint i) { return hsm[i]; }
#include "shadowmap_hsm.h"
#include "shadowmap_cssm_common.h"
// shadows.cssm_filter, a specialization constant (llvmpipe runs both sides of a branch on a
// buffer's value, docs/design.md): the mipmap's taps, else the SAT's corners.
layout(constant_id = 1) const bool CSSM_MIP = false;

// A box kernel of half-width h texels about q, as SAT corners or as mip taps.
struct Kern {
  ivec4 X, Y;     // SAT: corner columns / rows X0, X0 + 1, X1, X1 + 1 (clamped to the map)
  vec3 wx, wy;    // SAT: weights of the span [X0, X1), the cell X0, the cell X1
  float inv;      // SAT: 1 / (fixed-point scale · clipped area)
  float area;     // the clipped area, block units²
  uint b0, b1;    // mip: first texel of the two levels
  uvec4 i0, i1;   // mip: bilinear texels within each level
  vec4 w0, w1;    // mip: their weights (the level blend included)
};

// Block units (the basis's texels): `bound` the map's extent, `n` the basis size. The SAT's box
// snapped to whole texels: edges at the nearest texel boundary, widened to hold the texel of
// its centre (a box narrower than a texel would else snap to its neighbour).
void kern_axis(float qc, float h, float bound, uint size, out ivec4 X, out vec3 w, out float len) {
  float lo = max(qc - h, 0.0), hi = min(qc + h, bound);
  int n = int(size), cx = clamp(int(floor(qc)), 0, n - 1);
  int X0 = clamp(min(int(floor(lo + 0.5)), cx), 0, n - 1);
  int X1 = clamp(max(int(floor(hi + 0.5)), cx + 1), X0 + 1, n);
  X = ivec4(X0, X1, 0, 0);
  w = vec3(float(X1 - X0), 0.0, 0.0);
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
  K.inv = 1.0 / (c.sat_scale * K.wx.x * K.wy.x);
  K.area = lx > 0.0 && ly > 0.0 ? lx * ly : 0.0;
  if (CSSM_MIP) {
    // Mip level whose texel spans the kernel width 2h (of a rectangle, the square of its area);
    // linear between levels.
    float lev = clamp(log2(2.0 * (h.x == h.y ? h.x : sqrt(h.x * h.y))), 0.0, float(c.levels - 1u));
    uint l0 = uint(floor(lev)), l1 = min(l0 + 1u, c.levels - 1u);
    float t = lev - float(l0);
    kern_level(q, l0, 1.0 - t, K.b0, K.i0, K.w0);
    kern_level(q, l1, t, K.b1, K.i1, K.w1);
  }
  return K;
}

// The texel index of SAT entry (x, y) (x, y >= 1; the zero row and column are not stored).
int sat_texel(int x, int y) { return (x <= 0 || y <= 0) ? -1 : (y - 1) * int(c.level_w[0]) + (x - 1); }
// Group j of the half from texel `off` of `tab` at basis texel t.
uvec4 tab_at(uint off, int t, uint j) {
  return t < 0 ? uvec4(0u) : texelFetch(tab, int(off + uint(t) * (c.groups / 2u) + j));
}
uint tz_at(int t) { return t < 0 ? 0u : tz[uint(t)]; }

// The box average of four basis images, group j of `tab` (eq. 5.3: w * B_i). SAT: the box's
// integral from its four corners in wrapping uint arithmetic, exact; mipmap: two levels'
// bilinear taps.
vec4 cssm_box(uint off, uint j, Kern K) {
  if (!CSSM_MIP) {
    int t00 = sat_texel(K.X.x, K.Y.x), t10 = sat_texel(K.X.y, K.Y.x);
    int t01 = sat_texel(K.X.x, K.Y.y), t11 = sat_texel(K.X.y, K.Y.y);
    uvec4 r = (tab_at(off, t11, j) + tab_at(off, t00, j)) - (tab_at(off, t10, j) + tab_at(off, t01, j));
    return vec4(ivec4(r)) * K.inv;
  }
  uvec4 j0 = K.b0 + K.i0, j1 = K.b1 + K.i1;
  vec4 v = vec4(0.0);
  [[unroll]] for (int k = 0; k < 4; ++k)
    v += K.w0[k] * uintBitsToFloat(tab_at(off, int(j0[k]), j)) +
         K.w1[k] * uintBitsToFloat(tab_at(off, int(j1[k]), j));
  return v;
}
// The same of the z image.
float cssm_box_z(Kern K) {
  if (!CSSM_MIP) {
    int t00 = sat_texel(K.X.x, K.Y.x), t10 = sat_texel(K.X.y, K.Y.x);
    int t01 = sat_texel(K.X.x, K.Y.y), t11 = sat_texel(K.X.y, K.Y.y);
    return float(int((tz_at(t11) + tz_at(t00)) - (tz_at(t10) + tz_at(t01)))) * K.inv;
  }
  uvec4 j0 = K.b0 + K.i0, j1 = K.b1 + K.i1;
  return dot(K.w0, uintBitsToFloat(uvec4(tz[j0.x], tz[j0.y], tz[j0.z], tz[j0.w]))) +
         dot(K.w1, uintBitsToFloat(uvec4(tz[j1.x], tz[j1.y], tz[j1.z], tz[j1.w])));
}

// The raw filtered visibility s_f of kernel K against the normalised receiver depth dn (eq. 5.3,
// 5.10); with csm_z, CSM-Z's numerator w * (f̄ z) instead (eq. 5.11:
// (w * z)/2 + Σ 2/c_k [sin(c_k δ)(w * z cos) − cos(c_k δ)(w * z sin)]). The terms' (cos, sin)
// of c_k δ by rotation: e^{iπ(2k+1)δ} = e^{iπδ} (e^{2iπδ})^k.
float cssm_lookup(Kern K, float dn, bool csm_z) {
  float delta = c.s_z * dn - c.x0;
  float v = csm_z ? 0.5 * cssm_box_z(K) : 0.5;
  uint half_g = c.groups / 2u, off = csm_z ? c.half_texels : 0u;
  vec2 e1 = cssm_cis(1.0, delta), e2 = vec2(e1.x * e1.x - e1.y * e1.y, 2.0 * e1.x * e1.y);
  vec2 e = e1;  // (cos, sin) of c_k δ for the group's first term
  for (uint j = 0u; j < half_g; ++j) {
    vec4 B = cssm_box(off, j, K);  // (cos, sin) boxes of terms 2j and 2j + 1
    vec2 en = vec2(e.x * e2.x - e.y * e2.y, e.x * e2.y + e.y * e2.x);
    float m = float(4u * j + 1u);
    float t = 2.0 / (3.14159265358979 * m) * (e.y * B.x - e.x * B.y) +
              2.0 / (3.14159265358979 * (m + 2.0)) * (en.y * B.z - en.x * B.w);
    v += csm_z ? t : -t;
    e = vec2(en.x * e2.x - en.y * e2.y, en.x * e2.y + en.y * e2.x);
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
  bool one = nx * ny == 1u;
  vec2 sh = vec2(h / float(nx), h / float(ny));
  float sum = 0.0, area = 0.0;
  for (uint s = 0u; s < nx * ny; ++s) {
    uint i = s % nx, j = s / nx;
    vec2 b = one ? q.xy : q.xy - h + vec2(float(2u * i + 1u), float(2u * j + 1u)) * sh;
    Kern K = make_kern(b, one ? vec2(h) : sh);
    if (one || K.area > 0.0) {
      float dn = one ? d : clamp((sm_threshold(q, g, b, tw) - c.zmin) / c.zrange, 0.0, 1.0);
      float a = one ? 1.0 : K.area;
      sum += a * cssm_lookup(K, dn, csm_z);
      area += a;
    }
    // Every sub-kernel outside the map: the whole box's lookup, as one (the reference's).
    if (s + 1u == nx * ny && area <= 0.0) { nx = ny = 1u; one = true; s = ~0u; }
  }
  return sum / area;
}

// Ringing suppression (§5.2.3, Fig. 5.2c-d): scale about 1/2, then clamp.
float cssm_suppress(float s) { return clamp(c.alpha * (s - 0.5) + 0.5, 0.0, 1.0); }

void main() {
  p = p_in;
  c = c_in;
  uvec2 px;
  if (!sm_pixel_of(px)) return;
  uint i = px.y * pc.width + px.x;
  if (fg_in[i] == 0.0) { soft[i] = hard[i]; return; }
  vec3 P = sm_rel(i);  // P − light
  vec3 q = sm_project(P);
  if (!sm_inside(q)) { soft[i] = hard[i]; return; }
  if (!SM_OWN) sm_count(SHADOWMAP_STAT_PIXELS);
  bool back;
  vec4 g = sm_receiver_plane(px, q, P, back);
  if (back) { sm_count(SHADOWMAP_STAT_SKIPPED); soft[i] = hard[i]; return; }
  float texel_world = sm_texel_world(q.z);
  float k = sm_k();  // texels per unit of w(d) − w(z) (1/d − 1/z; a sun: z − d)
  // Receiver depth d: the biased receiver-plane threshold at its own texel centre, normalised.
  vec2 cc = floor(q.xy) + 0.5;
  float d = clamp((sm_threshold(q, g, cc, texel_world) - c.zmin) / c.zrange, 0.0, 1.0);
  // The min-max HSM (thesis §7.5.1, as vssm's): where every texel of the search's box lies
  // behind the receiver's threshold over it the pixel is lit with no lookup; where every texel
  // of PCSS's whole region lies in front of it (the region every blocker's cone stays within),
  // in umbra. A receiver beyond the map's farthest surface is tested as lying on it (the
  // background, clamped to it there, is no blocker; vssm.cpp).
  float hs = sm_cone_box(k, p.min_depth, q.z, 1.0), h = hs;
  {
    vec3 qv = vec3(q.xy, min(q.z, c.hsm.far_z));
    vec2 lo = max(q.xy - hs, vec2(0.0)), hi = min(q.xy + hs, vec2(p.map_w, p.map_h));
    if (sm_hsm_range(lo, hi).x >= sm_threshold_range(qv, g, lo, hi, texel_world).y) {
      sm_count(SHADOWMAP_STAT_SKIPPED);
      soft[i] = sm_input_edges(1.0, hard[i], 0.0);
      return;
    }
    float rs = max(sm_cone_radius(k, p.min_depth, qv.z, 1.0), 0.5);
    lo = max(q.xy - rs, vec2(0.0));
    hi = min(q.xy + rs, vec2(p.map_w, p.map_h));
    if (sm_hsm_range(lo, hi).y < sm_threshold_range(qv, g, lo, hi, texel_world).x) {
      sm_count(SHADOWMAP_STAT_SKIPPED);
      soft[i] = sm_input_edges(0.0, hard[i], 0.0);
      return;
    }
  }
  // The steps, each a lookup over half-width h: the blocker search (Fig. 5.1a: PCSS's disk as a
  // box of the same area, at least one texel) s_f, then CSM-Z over the same box (eq. 5.11) for
  // z_avg (eq. 5.8); the narrowed searches likewise (the search narrowed to the blockers' cone,
  // cssm.cpp, while it shrinks: blockers outside the light's cone at the mean blocker depth
  // cannot shadow the receiver, but pulled the mean towards its depth); last the filter over
  // the penumbra's width (§5.3.1).
  float s_f = 1.0, z_avg = 0.0, zb = 0.0, rf = 0.0;
  uint step = 0u;  // 0: s_f over h; 1: CSM-Z over h; 2: the filter
  for (uint pass = 0u;;) {
    float r = cssm_filtered(q, g, texel_world, h, d, step == 1u);
    if (step == 2u) { s_f = r; break; }
    if (step == 0u) {
      if (cssm_suppress(r) >= 1.0 || 1.0 - r < 1e-3) {
        sm_count(SHADOWMAP_STAT_SKIPPED);  // no blockers (within reach): fully lit
        soft[i] = sm_input_edges(1.0, hard[i], 0.0);
        return;
      }
      // The first dispatch ends here: the pixels with blockers are the second's (sm_pixel_of).
      if (!SM_OWN) { sm_own_append(i); return; }
      s_f = r;
      step = 1u;
      continue;
    }
    z_avg = clamp(r / (1.0 - s_f), 0.0, d);
    zb = c.zmin + z_avg * c.zrange;
    hs = h;
    float hn = pass < c.narrow ? sm_cone_box(k, zb, q.z, CSSM_NARROW_MARGIN) : hs;
    ++pass;
    if (hn < hs) {
      h = hn;
      step = 0u;
      continue;
    }
    // Penumbra width (§5.3.1): rf = k (1/z_avg − 1/d) (a sun: k (d − z_avg)).
    rf = k * sm_gap(zb, q.z);
    if (rf > p.max_radius) { rf = p.max_radius; sm_count(SHADOWMAP_STAT_CLAMPED); }
    h = max(SM_BOX_OF_DISK * rf, 0.5);
    step = 2u;
  }
  float v = cssm_suppress(s_f);
  float pw = 1.0 + c.sharpen_a * exp(-c.sharpen_b * (d - z_avg));  // eq. 5.9
  // A blocker nearer the receiver than x0 / s_z of the depth range shadows it by less than half
  // (cssm.cpp): the expansion cannot place the penumbrae such blockers cast, so the input's edge
  // stands up to the radius of one at that depth (issue 19).
  float zh = c.zmin + max(d - c.x0 / c.s_z, 0.0) * c.zrange;
  float r_half = min(k * sm_gap(zh, q.z), p.max_radius);
  soft[i] = sm_input_edges_at(pow(v, pw), hard[i], rf, r_half);
}
