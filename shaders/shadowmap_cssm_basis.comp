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
  uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
  if (x >= pc.width || y >= pc.height) return;
  uint i = y * pc.width + x;
  float z = cssm_norm(smap[i]);
  float zeta = c.s_z * z;
  uint M = c.order;
  for (uint k = 0u; k < M; ++k) {
    vec2 cs = cssm_cis(float(2u * k + 1u), zeta);
    put(k, i, cs.x);
    put(M + k, i, cs.y);
    put(2u * M + k, i, z * cs.x);
    put(3u * M + k, i, z * cs.y);
  }
  put(4u * M, i, z);
}
