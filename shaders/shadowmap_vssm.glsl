// The body of shaders/shadowmap_vssm.comp and shadowmap_vssm64.comp (included after #version).
#include "shadowmap_io.h"
#include "shadowmap_vssm_io.h"
// VSSM_REAL: the type of the moments' arithmetic. A sub-kernel's variance is E((z − z0)²) minus
// (E(z) − z0)², two numbers of the order of (depth − the map's mean depth)² whose difference
// decides against vssm.flat_var (1e-4 of the scene radius) whether it is planar. In float that
// difference is rounding (depths near 8 with z0 44: E((z − z0)²) = 1271, a float step 1.2e-4),
// and lavapipe and an NVIDIA H200 each took their own branches there (grazing ramp test: GPU
// against reference up to 0.10 apart on the H200). Where the device has shaderFloat64 the moments
// are summed and subtracted in double (shadowmap_vssm64.comp), as the reference does, from the
// SATs' exact integer sums and power-of-two scales (sat_fixed_point); else in float
// (shadowmap_vssm.comp).
#ifndef VSSM_REAL
#define VSSM_REAL float
#endif
#define R VSSM_REAL
// Variance soft shadow maps (thesis ch. 7, Algorithm 2): the min-max HSM proves pixels fully
// lit or in umbra (§7.5.1); the blocker search's kernel, split into m x m sub-kernels, gives
// the mean blocker depth by eq. 7.4 (planar sub-kernels, Chebyshev eq. 7.1 on their pooled
// moments of eq. 7.5) and PCF (non-planar ones, §7.4.2); the filter kernel is traversed as a
// quad-tree of height H without a stack (Algorithm 3); near contact a 3x3 PCF (§7.5.4). A
// sub-kernel counts as planar only where the receiver's threshold is flat across it
// (threshold_flat): else it is split, or filtered by PCF at the tree's leaves. The filter's PCF
// taps count only blockers the light's cone from the receiver reaches (sm_reaches, issue 19).
// The blocker search narrowed (issue 19, shadows.vssm_narrow passes; 0: the thesis's single
// search): the first search covers PCSS's region, the cone of the nearest depth anywhere in the
// map, so its mean blocker depth takes in blockers that no cone from the receiver reaches (as
// cssm's, cssm.cpp). Each pass searches again over the box of the cone at the mean found so far
// (sm_cone_box, VSSM_NARROW_MARGIN times), while that box shrinks: where it holds no blocker the
// receiver is lit, else its mean is the new one. Ratio to doing nothing's RMSE, 0 -> 2 passes:
// own Cycles cases grazing 0.49 -> 0.38, lowlight 0.46 -> 0.29, overlap 0.41 -> 0.29,
// grazing-sm4096 0.43 -> 0.31, contact-far1e5 0.27 -> 0.24; shared contact 0.24 -> 0.20,
// rowdepth 0.27 -> 0.19. Margin 1 (the box of the cone's area) against 1.5 and 2.2: grazing
// 0.38, 0.42, 0.37; lowlight 0.29, 0.31, 0.34; overlap 0.29, 0.32, 0.36; rowdepth 0.19, 0.22,
// 0.23. 1 pass: lowlight 0.31, overlap 0.31; 4: 0.28, 0.28. Cost: shared contact's pass 287 ->
// 353 ms on lavapipe.
// lib/effects/shadowmaps/vssm.cpp holds the double mirror.
layout(local_size_x = SHADOWMAP_LOCAL, local_size_y = SHADOWMAP_LOCAL) in;
layout(std430, binding = 0) readonly buffer Prm { ShadowmapParams p_in; };
ShadowmapParams p;  // p_in, copied once at the top of main
layout(binding = 1) uniform samplerBuffer geo;
layout(binding = 2) uniform samplerBuffer fg_in;
layout(binding = 3) uniform samplerBuffer hard;
layout(binding = 4) uniform samplerBuffer smap;
layout(std430, binding = 5) readonly buffer Vprm { VssmParams v; };
layout(binding = 6) uniform samplerBuffer hsm;
layout(binding = 7) uniform usamplerBuffer sat1;  // the SATs of z
layout(binding = 11) uniform usamplerBuffer sat2;  // and of (z − z0)²
layout(std430, binding = 8) buffer Soft { float soft[]; };  // also the listed pixels' first z_avg
layout(std430, binding = 9) buffer Stats { uint stats[]; };
layout(std430, binding = 10) buffer Own { uint own[]; };
layout(push_constant) uniform Push { ShadowmapPush pc; };
#define SHADOWMAP_COUNTS
#define SHADOWMAP_OWN
#include "shadowmap_common.h"

#define SM_HSM v.hsm
vec2 sm_hsm_texel(uint i) { return texelFetch(hsm, int(i)).xy; }
#include "shadowmap_hsm.h"

uvec2 sub64(uvec2 a, uvec2 b) {
  uint borrow;
  uint lo = usubBorrow(a.x, b.x, borrow);
  return uvec2(lo, a.y - b.y - borrow);
}
uvec2 add64(uvec2 a, uvec2 b) {
  uint carry;
  uint lo = uaddCarry(a.x, b.x, carry);
  return uvec2(lo, a.y + b.y + carry);
}
// Entry (x, y) of both SATs (xy: z, zw: (z − z0)²); 0 on the zero row and column.
uvec4 sat_at(int x, int y) {
  if (x <= 0 || y <= 0) return uvec4(0u);
  int i = int(uint(y - 1) * p.map_w + uint(x - 1));
  return uvec4(texelFetch(sat1, i).xy, texelFetch(sat2, i).xy);
}
// A continuous interval [a, b) of texels as three integer runs with weights: the partly covered
// first texel, the whole ones, the partly covered last one (the box filter of the exact width,
// wherever it is centred). Run r spans [edge[r], edge[r + 1]); an interval within one texel
// has one run of weight b − a and two empty ones (weight 0, no span), so the corners are
// always 4 x 4 and the loops unroll.
void runs(float a, float b, out ivec4 edge, out vec3 wt) {
  int i0 = int(floor(a)), i1 = int(ceil(b)) - 1;  // first and last texel touched
  if (i0 >= i1) {
    edge = ivec4(i0, i0 + 1, i0 + 1, i0 + 1); wt = vec3(b - a, 0.0, 0.0);
    return;
  }
  edge = ivec4(i0, i0 + 1, i1, i1 + 1);
  wt = vec3(float(i0 + 1) - a, 1.0, b - float(i1));
}
R to_real(uvec2 s) { return R(int(s.y)) * R(4294967296.0) + R(s.x); }

// The moments of one sub-kernel [lo, hi): area T, mean E(z), E((z − z0)²) (ezf: E(z) in float;
// var: the variance). Both box sums come from the 4 x 4 SAT entries at the runs' edges (one
// fetch from each table), each run's rectangle exact in the integers.
struct Moments { float T; R ez, ez2; float ezf, var; };
float variance(R ez, R ez2) { return float(max(ez2 - (ez - R(v.z0)) * (ez - R(v.z0)), R(0.0))); }
Moments moments(vec2 lo, vec2 hi) {
  ivec4 ex, ey;
  vec3 wx, wy;
  runs(lo.x, hi.x, ex, wx);
  runs(lo.y, hi.y, ey, wy);
  uvec4 c[16];
  [[unroll]] for (int j = 0; j < 4; ++j)
    [[unroll]] for (int i = 0; i < 4; ++i) c[j * 4 + i] = sat_at(ex[i], ey[j]);
  R s1 = R(0.0), s2 = R(0.0), sw = R(0.0);  // sw: the weights' sum, the area they cover
  [[unroll]] for (int j = 0; j < 3; ++j)
    [[unroll]] for (int i = 0; i < 3; ++i) {
      int a = j * 4 + i;
      float w = wx[i] * wy[j];
      uvec4 r1 = uvec4(sub64(add64(c[a + 5].xy, c[a].xy), add64(c[a + 1].xy, c[a + 4].xy)),
                       sub64(add64(c[a + 5].zw, c[a].zw), add64(c[a + 1].zw, c[a + 4].zw)));
      s1 += R(w) * to_real(r1.xy);
      s2 += R(w) * to_real(r1.zw);
      sw += R(w) * R((ex[i + 1] - ex[i]) * (ey[j + 1] - ey[j]));
    }
  Moments m;
  m.T = (hi.x - lo.x) * (hi.y - lo.y);
  // Divided by the weights' own sum, not by T: the offsets (E(z − z0)² about 1300 on a map from
  // 8 to 95 m) come back exactly where the two differ by float rounding.
  m.ez = s1 / (sw * R(v.scale1)) + R(v.off1);
  m.ez2 = s2 / (sw * R(v.scale2)) + R(v.off2);
  m.ezf = float(m.ez);
  m.var = variance(m.ez, m.ez2);
  return m;
}

// Cell (ix, iy) of an n x n split of [a, b).
void cell(vec2 a, vec2 b, int n, int ix, int iy, out vec2 lo, out vec2 hi) {
  vec2 size = (b - a) / float(n);
  lo = a + size * vec2(ix, iy);
  hi = a + size * vec2(ix + 1, iy + 1);
}
bool empty(vec2 lo, vec2 hi) { return hi.x - lo.x < 1e-3 || hi.y - lo.y < 1e-3; }

// PCF over a g x g grid in [lo, hi) (each tap the texel under a cell centre): lit fraction;
// blockers' count and depth sum. kr > 0 (the filter's): blockers only within reach (sm_reaches).
float pcf(vec2 lo, vec2 hi, uint g, vec3 q, vec4 gr, float tw, float kr, out float nb, out float zb) {
  nb = 0.0;
  zb = 0.0;
  for (uint j = 0u; j < g; ++j)
    for (uint i = 0u; i < g; ++i) {
      vec2 c = min(floor(lo + (vec2(i, j) + 0.5) / float(g) * (hi - lo)),
                   vec2(p.map_w - 1u, p.map_h - 1u)) + 0.5;
      float z = sm_fetch(c);
      if (z < sm_threshold(q, gr, c, tw) && sm_reaches(q, c, z, kr)) { nb += 1.0; zb += z; }
    }
  return 1.0 - nb / float(g * g);
}

// The square of half-width r around q, clipped to the map (at least a texel wide).
void square(vec3 q, float r, out vec2 lo, out vec2 hi) {
  r = max(r, 0.5);
  lo = max(q.xy - r, vec2(0.0));
  hi = min(q.xy + r, vec2(p.map_w, p.map_h));
}

// Whether the receiver's threshold moves by less than `gap` (the sub-kernel's lead on it,
// t − E(z)) over [lo, hi) (issue 19). Chebyshev's bound (eq. 7.1) and eq. 7.4 take one threshold
// for the sub-kernel; where the receiver plane's own depths spread over more than that lead (a
// floor lit at grazing light, a wide kernel), the lit receiver's spread counts as variance and
// lets light through the blockers, and eq. 7.4 places them too near the light (own lowlight
// case: a sphere's umbra came out 0.55 lit). Such sub-kernels are split further or filtered by
// PCF, which tests each tap against its own threshold.
// tr: the threshold's range over the sub-kernel (hsm_verdict's).
bool threshold_flat(vec2 tr, float gap) { return tr.y - tr.x < gap; }

// Chebyshev's bound (eq. 7.1): the lit fraction of depths of mean mu and variance var against
// threshold t. The filter takes it on each planar sub-kernel against its own threshold (the
// receiver's depth at its centre, unbiased): the filter's lit area is the sum of its planar
// sub-kernels' (issue 19). Algorithm 3 pools their moments and tests them against one mean
// threshold; where the receiver is lit at a grazing angle their thresholds differ by more than
// their blockers' spread, and the pooled variance (the spread between their means counts in it)
// lets light through the blockers: own grazing case 0.566 → 0.542 of doing nothing (at H 3).
// The blocker search keeps the thesis's pooled moments (eq. 7.5): tested sub-kernel by
// sub-kernel there, a sub-kernel holding only the receiver's own texels, put in front of its
// threshold by P's float32 noise, counts as a blocker at the receiver's depth, and the contact
// shadow that follows took the own contact scene 1e6 m from the origin, from P, from 0.44 to
// 0.58 (at the origin, 0.241 → 0.236: too little to pay for it).
float chebyshev(float mu, float var, float t) {
  float d = t - mu;
  return d > 0.0 ? var / (var + d * d) : 1.0;
}

// The HSM's verdict on a sub-kernel: 1 all lit, -1 all blocked, 0 neither; tr the receiver's
// threshold range over it (threshold_flat's too: computed once, as every lane runs every
// branch's code on lavapipe).
int hsm_verdict(vec3 q, vec4 g, vec2 lo, vec2 hi, float tw, out vec2 tr) {
  vec2 zr = sm_hsm_range(lo, hi);
  tr = sm_threshold_range(q, g, lo, hi, tw);
  return zr.x >= tr.y ? 1 : (zr.y < tr.x ? -1 : 0);
}

// The blocker search over [a, b): whether it finds blockers, and their mean depth zavg.
bool blocker_search(vec3 q, vec4 g, float tw, float unbias, vec2 a, vec2 b, int m, out float zavg) {
  // Blocker search (Algorithm 2, L11-L15): the whole kernel when it is planar (its mean depth
  // in front of the receiver), else m x m sub-kernels (§7.4.2), the planar ones' moments pooled
  // (eq. 7.5; see chebyshev for why here and not in the filter).
  float sA = 0.0, sT = 0.0;  // planar group: area, Σ E(z)T, Σ E(z²)T, Σ t T
  R sZ = R(0.0), sZ2 = R(0.0);
  float bPcf = 0.0, zPcf = 0.0;                   // non-planar group: blocker area, Σ z·area
  for (int iy = 0; iy < m; ++iy)
    for (int ix = 0; ix < m; ++ix) {
      vec2 lo, hi;
      cell(a, b, m, ix, iy, lo, hi);
      if (empty(lo, hi)) continue;
      vec2 tr;
      int hv = hsm_verdict(q, g, lo, hi, tw, tr);
      if (hv > 0) continue;  // no blockers
      Moments mo = moments(lo, hi);
      float t = sm_threshold(q, g, 0.5 * (lo + hi), tw);
      bool flat_t = mo.ezf < t && threshold_flat(tr, t - mo.ezf);
      if (hv < 0) {
        bPcf += mo.T; zPcf += mo.ezf * mo.T;  // all blockers: their mean depth is E(z)
      } else if (flat_t || (mo.ezf < t && v.leaf_grid == 0u)) {
        sA += mo.T; sZ += mo.ez * mo.T; sZ2 += mo.ez2 * mo.T; sT += (t + unbias) * mo.T;
      } else if ((mo.ezf < t || mo.var >= v.flat_var) && v.leaf_grid > 0u) {
        float nb, zb;
        pcf(lo, hi, v.leaf_grid, q, g, tw, 0.0, nb, zb);
        float n = float(v.leaf_grid * v.leaf_grid);
        bPcf += mo.T * nb / n;
        zPcf += mo.T * zb / n;
      }
    }
  float bVsm = 0.0, zVsm = 0.0;
  if (sA > 0.0) {
    float mu = float(sZ / R(sA)), t = sT / sA, var = variance(sZ / R(sA), sZ2 / R(sA));
    if (mu < t) {
      float lit = chebyshev(mu, var, t);
      if (lit < 1.0 - 1e-6) {
        bVsm = (1.0 - lit) * sA;
        zVsm = (mu - lit * t) / (1.0 - lit) * bVsm;  // eq. 7.4, z_unocc = t
      }
    }
  }
  zavg = bVsm + bPcf > 0.0 ? clamp((zVsm + zPcf) / (bVsm + bPcf), p.min_depth, q.z) : 0.0;
  return bVsm + bPcf > 0.0;
}

// The first dispatch ends at the HSM's verdict (Algorithm 2, L8-L10) or the first blocker
// search, the second takes the pixels they leave (sm_pixel_of).
void main() {
  p = p_in;
  uvec2 px;
  if (!sm_pixel_of(px)) return;
  uint i = px.y * pc.width + px.x;
  if (texelFetch(fg_in, int(i)).r == 0.0) { soft[i] = texelFetch(hard, int(i)).r; return; }
  vec3 P = sm_rel(i);  // P − light
  vec3 q = sm_project(P);
  if (!sm_inside(q)) { soft[i] = texelFetch(hard, int(i)).r; return; }
  if (!SM_OWN) sm_count(SHADOWMAP_STAT_PIXELS);
  bool back;
  vec4 g = sm_receiver_plane(px, q, P, back);
  if (back) { sm_count(SHADOWMAP_STAT_SKIPPED); soft[i] = texelFetch(hard, int(i)).r; return; }
  // A receiver beyond the map's farthest surface (far_z, where the background stands in the
  // SATs and the HSM) is shaded as lying on it: else the background would block it (vssm.cpp).
  float h_in = texelFetch(hard, int(i)).r;
  q.z = min(q.z, v.hsm.far_z);
  float tw = sm_texel_world(q.z);
  float k = sm_k();
  float rs = sm_cone_radius(k, p.min_depth, q.z, 1.0);
  vec2 a, b;
  square(q, rs, a, b);
  // HSM (Algorithm 2, L8-L10): bounds of the receiver's threshold over the kernel.
  float lim = g.w * tw * (rs + 1.0) * 1.5;
  // The bias decides which sub-kernels hold blockers; Chebyshev's bound (eq. 7.1) and eq. 7.4
  // take the receiver's own depth (z_unocc = t), where they are exact for two planes.
  float unbias = p.bias * tw + p.spread_bias * g.z;
  float base = q.z - p.bias * tw - p.spread_bias * g.z;
  vec2 zr = sm_hsm_range(a, b);
  if (zr.x >= base + lim) { sm_count(SHADOWMAP_STAT_SKIPPED); soft[i] = sm_input_edges(1.0, h_in, 0.0); return; }
  if (zr.y < base - lim) { sm_count(SHADOWMAP_STAT_SKIPPED); soft[i] = sm_input_edges(0.0, h_in, 0.0); return; }
  // The first dispatch runs the first blocker search too: where it finds no blocker (most lit
  // pixels) the receiver is lit; it lists the rest, their mean blocker depth left in soft[i] for
  // the second dispatch, which narrows the search and filters. llvmpipe runs every lane through
  // all the code there is, masked: the narrowing and the filter must not run for the pixels the
  // first search settles (shadowmap_common.h's SM_OWN).
  float zavg;
  if (!SM_OWN) {
    if (!blocker_search(q, g, tw, unbias, a, b, int(v.m_first), zavg)) {
      sm_count(SHADOWMAP_STAT_SKIPPED);
      soft[i] = sm_input_edges(1.0, h_in, 0.0);
      return;
    }
    soft[i] = zavg;
    sm_own_append(i);
    return;
  }

  // The search narrowed to the blockers' cone (vssm.cpp), while it shrinks: where the narrowed
  // box holds no blocker the receiver is lit, else its mean blocker depth is the new one.
  zavg = soft[i];
  bool found = true;
  float hs = max(rs, 0.5);
  for (uint pass = 0u; found && pass < v.narrow; ++pass) {
    float hn = sm_cone_box(k, zavg, q.z, VSSM_NARROW_MARGIN);
    if (hn >= hs) break;
    square(q, hn, a, b);
    found = blocker_search(q, g, tw, unbias, a, b, int(v.m), zavg);
    hs = hn;
  }
  if (!found) { sm_count(SHADOWMAP_STAT_SKIPPED); soft[i] = sm_input_edges(1.0, h_in, 0.0); return; }
  float rf = k * sm_gap(zavg, q.z);
  if (rf > p.max_radius) { rf = p.max_radius; sm_count(SHADOWMAP_STAT_CLAMPED); }
  // The square kernel of the light disk's area (half-width √π/2 · r; a rect light's
  // area-equivalent disk).
  square(q, 0.8862269 * rf, a, b);
  if (q.z - zavg < v.contact) {
    // Contact (§7.5.4): the penumbra is narrow and the SAT's precision short: 3x3 PCF.
    sm_count(SHADOWMAP_STAT_CONTACT);
    float nb, zb;
    square(q, max(rf, 1.0), a, b);
    soft[i] = sm_input_edges(pcf(a, b, 3u, q, g, tw, p.reach * k, nb, zb), h_in, rf);
    return;
  }
  // The filter kernel as a quad-tree of height H, traversed linearly (Algorithm 3): a node is
  // (level, ix, iy); Next is the next sibling, or the parent's Next after the last one.
  // Areas: proven lit (lA), proven umbra (uA), filtered (fA, of which fLit lit: Chebyshev on
  // each planar sub-kernel, PCF on non-planar leaves).
  float lA = 0.0, uA = 0.0, fA = 0.0, fLit = 0.0;
  int level = 0, nx = 0, ny = 0;
  int H = int(v.tree_h);
  for (;;) {
    vec2 lo, hi;
    cell(a, b, 1 << level, nx, ny, lo, hi);
    bool down = false;
    vec2 tr;
    int hv = hsm_verdict(q, g, lo, hi, tw, tr);
    if (empty(lo, hi)) hv = 2;
    float T = (hi.x - lo.x) * (hi.y - lo.y);
    if (hv == 1) {
      lA += T;  // the HSM proves it lit
    } else if (hv == -1) {
      uA += T;  // ... or in umbra
    } else if (hv == 0) {
      Moments mo = moments(lo, hi);
      float t = sm_threshold(q, g, 0.5 * (lo + hi), tw);
      float var = mo.var;
      bool flat_t = mo.ezf < t && threshold_flat(tr, t - mo.ezf);
      if (mo.ezf >= t && var < v.flat_var) {
        lA += mo.T;                                   // L10-L12: planar and behind: lit
      } else if (flat_t) {
        fLit += mo.T * chebyshev(mo.ezf, mo.var, t + unbias);  // L14-L18, eq. 7.1 on its own
        fA += mo.T;
        // (a sub-kernel with blockers whose threshold is not flat goes down, or to PCF)
      } else if (level < H) {
        down = true;                                  // L21
      } else if (v.leaf_grid > 0u) {
        float nb, zb;                                 // L23-L26
        fLit += mo.T * pcf(lo, hi, v.leaf_grid, q, g, tw, p.reach * k, nb, zb);
        fA += mo.T;
      } else if (mo.ezf < t) {
        fLit += mo.T * chebyshev(mo.ezf, mo.var, t + unbias);
        fA += mo.T;
      } else {
        lA += mo.T;  // no PCF: taken as lit, as plain variance shadow maps do
      }
    }
    if (down) { ++level; nx *= 2; ny *= 2; continue; }
    // Next.
    bool done = false;
    for (;;) {
      if (level == 0) { done = true; break; }
      if ((nx & 1) == 0) { ++nx; break; }
      if ((ny & 1) == 0) { --nx; ++ny; break; }
      --level; nx >>= 1; ny >>= 1;
    }
    if (done) break;
  }
  soft[i] = sm_input_edges((lA + fLit) / (lA + uA + fA), h_in, rf);  // L29-L32
}
