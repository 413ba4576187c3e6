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
layout(std430, binding = 0) readonly buffer Src { vec4 src_buf[]; };  // dof.input, RGBA texels
layout(std430, binding = 1) readonly buffer Coc { float coc_buf[]; };
layout(std430, binding = 2) readonly buffer Tiles { float tiles[]; };
layout(std430, binding = 3) writeonly buffer Composite { float C[]; };
layout(push_constant) uniform Push { DofPush pc; };
#define DOF_HAS_COC
#define DOF_HAS_SRC
#include "dof_common.h"

void main() {
  dof_fill_lattice();
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint n = pc.width * pc.height;
  uint i = p.y * pc.width + p.x;
  float c0 = coc_buf[i];
  uint t = 4u * ((p.y / DOF_TILE) * pc.tiles_x + p.x / DOF_TILE);
  float a = isg_pixel_angle(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16));
  vec4 out_c;
  if (tiles[t + 3u] != 0.0) {
    out_c = dof_cheap(p, c0, a);
  } else {
    float R = max(tiles[t + 2u], 0.5);
    float K = dof_area_factor(pc.blades);
    float a_s = DOF_PI * R * R / float(pc.grid * pc.grid);  // image area one sample stands for
    mat2 rot = mat2(cos(a), sin(a), -sin(a), cos(a));
    vec2 p0 = vec2(p) + 0.5;
    float m0 = smoothstep(0.5, 1.5, -c0);  // near-field membership of this pixel
    vec4 c_0 = dof_src(i);
    float w0 = 1.0 / max(K * c0 * c0, 1.0);
    vec4 Sn = m0 * w0 * c_0, Sf = (1.0 - m0) * w0 * c_0;
    float Wn = m0 * w0, Wf = (1.0 - m0) * w0;
    for (uint k = 0u; k < pc.grid * pc.grid; ++k) {
      vec2 d = R * (rot * dof_lattice[k]);
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
      float wf = (1.0 - mi) * dof_cover(v, r_far, pc.blades, pc.rotation) * dens *
                 smoothstep(0.25, 0.75, r_far);
      float wn = mi * dof_cover(v, abs(ci), pc.blades, pc.rotation) * dens;
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
    out_c = alpha * near_c + (1.0 - alpha) * far_c;
  }
  for (uint k = 0u; k < 4u; ++k) C[k * n + i] = out_c[k];
}
