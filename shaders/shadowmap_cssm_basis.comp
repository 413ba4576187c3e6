#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_cssm_io.h"
// CSSM basis images (thesis eq. 5.2-5.3, 5.11): the 4M + 1 images of CssmParams from the map,
// in the layout of shadowmap_cssm_io.h, written as SAT entries (32-bit integers, scanned next
// by sat_scan32) or as mip level 0 (float bits).
layout(local_size_x = CSSM_LOCAL, local_size_y = CSSM_LOCAL) in;
layout(std430, binding = 0) readonly buffer Cprm { CssmParams c; };
layout(std430, binding = 1) readonly buffer Smap { float smap[]; };
layout(std430, binding = 2) writeonly buffer Tab { uvec4 tab[]; };
layout(std430, binding = 3) writeonly buffer Tz { uint tz[]; };
layout(push_constant) uniform Push { CssmPush pc; };
#include "shadowmap_cssm_common.h"

uint put(float v) {
  return c.prefilter == CSSM_FILTER_SAT ? uint(int(floor(v * c.sat_scale + 0.5))) : floatBitsToUint(v);
}

void main() {
  uint bw = c.level_w[0], bh = c.level_h[0];
  uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
  if (x >= bw || y >= bh) return;
  uint i = y * bw + x, M = c.order, F = 1u << c.basis_shift, half_g = c.groups / 2u;
  uint x1 = min((x + 1u) * F, pc.width), y1 = min((y + 1u) * F, pc.height);
  float inv = 1.0 / float((x1 - x * F) * (y1 - y * F));
  // The block's average of each basis function over the map texels it covers, a group at a
  // time: (cos, sin) of terms 2j and 2j + 1, of CSM and of CSM-Z.
  for (uint j = 0u; j < half_g; ++j) {
    vec4 a = vec4(0.0), b = vec4(0.0);
    float m0 = float(4u * j + 1u);
    bool second = 2u * j + 1u < M;
    for (uint yy = y * F; yy < y1; ++yy)
      for (uint xx = x * F; xx < x1; ++xx) {
        float z = cssm_norm(smap[yy * pc.width + xx]);
        vec2 c0 = cssm_cis(m0, c.s_z * z), c1 = second ? cssm_cis(m0 + 2.0, c.s_z * z) : vec2(0.0);
        a += vec4(c0, c1);
        b += z * vec4(c0, c1);
      }
    a *= inv;
    b *= inv;
    tab[i * c.groups + j] = uvec4(put(a.x), put(a.y), put(a.z), put(a.w));
    tab[i * c.groups + half_g + j] = uvec4(put(b.x), put(b.y), put(b.z), put(b.w));
  }
  float az = 0.0;
  for (uint yy = y * F; yy < y1; ++yy)
    for (uint xx = x * F; xx < x1; ++xx) az += cssm_norm(smap[yy * pc.width + xx]);
  tz[i] = put(az * inv);
}
