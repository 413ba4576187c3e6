#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_cssm_io.h"
// CSSM basis images (thesis eq. 5.2-5.3, 5.11): the 4M + 1 layers of CssmParams from the map,
// written as SAT entries (64-bit fixed point, scanned next by sat_scan) or as mip level 0.
layout(local_size_x = CSSM_LOCAL, local_size_y = CSSM_LOCAL) in;
layout(std430, binding = 0) readonly buffer Cprm { CssmParams c; };
layout(std430, binding = 1) readonly buffer Smap { float smap[]; };
layout(push_constant) uniform Push { CssmPush pc; };
#define CSSM_TABLES_BINDING 2
#define CSSM_TABLES_WRITE
#include "shadowmap_cssm_common.h"

void put(uint layer, uint i, float v) {
  if (c.prefilter == CSSM_FILTER_SAT) {
    int q = int(floor(v * c.sat_scale + 0.5));
    cssm_set(layer, 2u * i, uint(q));
    cssm_set(layer, 2u * i + 1u, q < 0 ? 0xffffffffu : 0u);
  } else {
    cssm_set(layer, i, floatBitsToUint(v));  // mip level 0 starts each layer's chain
  }
}

void main() {
  uint bw = c.level_w[0], bh = c.level_h[0];
  uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
  if (x >= bw || y >= bh) return;
  uint i = y * bw + x, M = c.order, F = 1u << c.basis_shift;
  // The block's average of each basis function over the map texels it covers.
  float acc[CSSM_MAX_LAYERS];
  for (uint l = 0u; l <= 4u * M; ++l) acc[l] = 0.0;
  uint x1 = min((x + 1u) * F, pc.width), y1 = min((y + 1u) * F, pc.height);
  for (uint yy = y * F; yy < y1; ++yy)
    for (uint xx = x * F; xx < x1; ++xx) {
      float z = cssm_norm(smap[yy * pc.width + xx]);
      float zeta = c.s_z * z;
      for (uint k = 0u; k < M; ++k) {
        vec2 cs = cssm_cis(float(2u * k + 1u), zeta);
        acc[k] += cs.x;
        acc[M + k] += cs.y;
        acc[2u * M + k] += z * cs.x;
        acc[3u * M + k] += z * cs.y;
      }
      acc[4u * M] += z;
    }
  float inv = 1.0 / float((x1 - x * F) * (y1 - y * F));
  for (uint l = 0u; l <= 4u * M; ++l) put(l, i, acc[l] * inv);
}
