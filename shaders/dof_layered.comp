#version 450
#extension GL_GOOGLE_include_directive : require
// dof.layered: near and far fields gathered separately, as a scatter turned into a gather (a
// sample counts where its own aperture reaches this pixel, with weight 1 / its aperture area).
// The far field keeps occlusion (a sample behind this pixel spreads no further than this
// pixel's CoC, eq. 17 mirrored); the near field spreads over everything and its coverage is
// the alpha it is composited with over the far field. This fixes §3.3's stated weakness: a
// blurry foreground over an in-focus object.
#include "dof_layered_io.h"
layout(local_size_x = DOF_LOCAL, local_size_y = DOF_LOCAL) in;
layout(binding = 0) uniform samplerBuffer src_buf;  // dof.input, RGBA texels (texel views)
layout(binding = 1) uniform samplerBuffer coc_buf;
layout(binding = 2) uniform samplerBuffer tiles;
layout(std430, binding = 3) writeonly buffer Composite { float C[]; };
layout(push_constant) uniform Push { DofPush pc; };
#define DOF_HAS_COC
#define DOF_HAS_SRC
#include "dof_common.h"

// The lattice for a tile of radius R (DOF_LATTICE_DENSITY); lib/effects/dof/dof.cpp mirrors it.
uint dof_layered_grid(float R, uint grid) {
  return clamp(uint(ceil(DOF_LATTICE_DENSITY * R)), min(uint(DOF_MIN_GRID), grid), grid);
}

// The layered gather at p (frame-local pixel), CoC c0, lattice angle a, the tile's radius R,
// over the workgroup's lattice of grid² samples.
vec4 layered(uvec2 p, float c0, float a, float R, uint grid) {
  uint i = p.y * pc.width + p.x;
  float K = dof_area_factor(DOF_BLADES);
  float a_s = DOF_PI * R * R / float(grid * grid);  // image area one sample stands for
  mat2 rot = mat2(cos(a), sin(a), -sin(a), cos(a));
  vec2 p0 = vec2(p) + 0.5;
  float m0 = smoothstep(0.5, 1.5, -c0);  // near-field membership of this pixel
  vec4 c_0 = dof_src(i);
  float w0 = 1.0 / max(K * c0 * c0, 1.0);
  vec4 Sn = m0 * w0 * c_0, Sf = (1.0 - m0) * w0 * c_0;
  float Wn = m0 * w0, Wf = (1.0 - m0) * w0;
  for (uint k = 0u; k < grid * grid; ++k) {
    vec2 d = R * dof_stretch(rot * dof_lattice[k]);
    float ci = dof_fetch_coc(p0 + d);
    vec2 v = ci >= 0.0 ? -d : d;
    float mi = smoothstep(0.5, 1.5, -ci);
    float dens = a_s / max(K * ci * ci, a_s);
    float behind = smoothstep(0.0, 1.0, ci - c0) * (1.0 - m0);
    float r_far = mix(abs(ci), min(abs(ci), max(c0, 0.0)), behind);
    // Seen from inside a blurred near object's edge, the lens looks past it at the far field
    // within p0's own CoC (partial occlusion): far samples that near reach p0.
    r_far = max(r_far, m0 * max(-c0, 0.0));
    // In-focus samples (CoC under half a pixel) are the centre pixel's business, not the ring's.
    float wf = (1.0 - mi) * dof_cover(v, r_far, DOF_BLADES, pc.rotation) * dens *
               smoothstep(0.25, 0.75, r_far);
    float wn = mi * dof_cover(v, abs(ci), DOF_BLADES, pc.rotation) * dens;
    if (wf + wn > 0.0) {
      vec4 ci4 = dof_fetch_src(p0 + d);
      Sf += wf * ci4; Wf += wf;
      Sn += wn * ci4; Wn += wn;
    }
  }
  float alpha = clamp(Wn, 0.0, 1.0);
  // Where the far field found nothing (inside a large near object) the near field is opaque.
  alpha += (1.0 - alpha) * (1.0 - smoothstep(0.0, 0.05, Wf / (Wf + Wn)));
  vec4 near_c = Sn / max(Wn, 1e-20), far_c = Sf / max(Wf, 1e-20);
  return alpha * near_c + (1.0 - alpha) * far_c;
}

// Wide CoCs at half resolution (issue 18): each 2×2 quad's top-left pixel (its representative)
// gathers where |CoC| >= DOF_REUSE_COC; a pixel with such a CoC takes its result bilinearly from
// the representatives around it in the workgroup's quad grid whose CoC has its sign and lies
// within DOF_REUSE_TOL·|CoC| of its own (at least DOF_REUSE_COVER of the bilinear weight, else it
// gathers itself): the result moves little over a pixel where the blur is wide and the depth
// smooth, and depth edges, where neighbouring CoCs differ, gather per pixel.
#define QUADS (DOF_LOCAL / 2u)
shared vec4 q_out[QUADS * QUADS];
shared float q_coc[QUADS * QUADS];  // the representative's CoC; 0: none (no gather of its own)
bool reuse(float c0, out vec4 m) {
  uvec2 q0;  // the lower corner of the quads around the pixel (at their top-left pixels)
  vec2 a;
  isg_quad_bilinear(gl_LocalInvocationID.xy, QUADS, q0, a);
  vec4 s = vec4(0.0);
  float ws = 0.0;
  for (uint k = 0u; k < 4u; ++k) {
    uint q = (q0.y + (k >> 1u)) * QUADS + q0.x + (k & 1u);
    float w = isg_quad_weight(a, k);
    float cq = q_coc[q];
    if (w <= 0.0 || cq * c0 <= 0.0 || abs(cq - c0) > DOF_REUSE_TOL * abs(c0)) continue;
    s += w * q_out[q];
    ws += w;
  }
  m = ws > 0.0 ? s / ws : vec4(0.0);
  return ws >= DOF_REUSE_COVER;
}

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  bool inside = p.x < pc.width && p.y < pc.height;
  uvec2 pt = min(p, uvec2(pc.width, pc.height) - 1u);  // a workgroup lies in one DOF_TILE tile
  uint t = 4u * ((pt.y / DOF_TILE) * pc.tiles_x + pt.x / DOF_TILE);
  bool cheap = texelFetch(tiles, int(t + 3u)).r != 0.0;
  float R = max(texelFetch(tiles, int(t + 2u)).r, 0.5);
  // Samples matched to the blur (issue 18): a lattice of spacing about 1 / DOF_LATTICE_DENSITY
  // pixels over the tile's largest CoC, at most dof.samples (the cheap path's radius |c0| is
  // within that CoC too).
  uint grid = dof_layered_grid(R, pc.grid);
  dof_fill_lattice_of(grid);
  // The quads' representatives, one invocation per quad (the first QUADS² lanes).
  uint q = gl_LocalInvocationIndex;
  if (!cheap && q < QUADS * QUADS) {
    uvec2 rp = gl_WorkGroupID.xy * DOF_LOCAL + 2u * uvec2(q % QUADS, q / QUADS);
    float cr = 0.0;
    if (rp.x < pc.width && rp.y < pc.height) {
      cr = texelFetch(coc_buf, int(rp.y * pc.width + rp.x)).r;
      if (abs(cr) >= DOF_REUSE_COC)
        q_out[q] = layered(rp, cr, isg_pixel_angle(rp + uvec2(pc.origin & 0xffffu, pc.origin >> 16)), R, grid);
      else
        cr = 0.0;
    }
    q_coc[q] = cr;
  }
  barrier();
  if (!inside) return;
  uint n = pc.width * pc.height;
  uint i = p.y * pc.width + p.x;
  float c0 = texelFetch(coc_buf, int(i)).r;
  float a = isg_pixel_angle(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16));
  vec4 out_c;
  if (cheap) {
    out_c = dof_cheap(p, c0, a, grid);
  } else if (!(abs(c0) >= DOF_REUSE_COC && reuse(c0, out_c))) {
    out_c = layered(p, c0, a, R, grid);
  }
  for (uint k = 0u; k < 4u; ++k) C[k * n + i] = out_c[k];
}
