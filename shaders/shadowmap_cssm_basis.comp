#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_cssm_io.h"
// CSSM basis images (thesis eq. 5.2-5.3, 5.11): the 4M + 1 images of CssmParams from the map,
// in the layout of shadowmap_cssm_io.h. SAT: a lane per basis row and part (a group's CSM and
// CSM-Z pairs, or the z image) walks the row, quantises each texel's values to 32-bit integers
// and writes their running sums along the row (the row scan of the SAT; sat_scan32 adds the
// columns next). Mipmap (CSSM_MIP): a lane per texel writes level 0 as float bits.
layout(local_size_x = CSSM_LOCAL, local_size_y = CSSM_LOCAL) in;
layout(std430, binding = 0) readonly buffer Cprm { CssmParams c; };
layout(std430, binding = 1) readonly buffer Smap { float smap[]; };
layout(std430, binding = 2) writeonly buffer TabV { uvec4 tabv[]; };  // tab's CSM half
layout(std430, binding = 3) writeonly buffer TabZ { uvec4 tabz[]; };  // tab's CSM-Z half
layout(std430, binding = 4) writeonly buffer Tz { uint tz[]; };
layout(push_constant) uniform Push { CssmPush pc; };
layout(constant_id = 1) const bool CSSM_MIP = false;
#include "shadowmap_cssm_common.h"

uint quant(float v) { return uint(int(floor(v * c.sat_scale + 0.5))); }

// Block (x, y)'s average of group j's four CSM values (cos, sin of terms 2j, 2j + 1) in a, of
// its CSM-Z values in b, and of z; the block covers F x F map texels (fewer at the edges).
void block(uint x, uint y, uint j, out vec4 a, out vec4 b, out float az) {
  uint F = 1u << c.basis_shift;
  uint x1 = min((x + 1u) * F, pc.width), y1 = min((y + 1u) * F, pc.height);
  a = vec4(0.0);
  b = vec4(0.0);
  az = 0.0;
  bool second = 2u * j + 1u < c.order;
  for (uint yy = y * F; yy < y1; ++yy)
    for (uint xx = x * F; xx < x1; ++xx) {
      float z = cssm_norm(smap[yy * pc.width + xx]);
      vec2 e = cssm_cis(float(4u * j + 1u), c.s_z * z);
      vec2 en = second ? cssm_cis(float(4u * j + 3u), c.s_z * z) : vec2(0.0);
      a += vec4(e, en);
      b += z * vec4(e, en);
      az += z;
    }
  float inv = 1.0 / float((x1 - x * F) * (y1 - y * F));
  a *= inv;
  b *= inv;
  az *= inv;
}

void main() {
  uint bw = c.level_w[0], bh = c.level_h[0], half_g = c.groups / 2u;
  if (CSSM_MIP) {
    uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
    if (x >= bw || y >= bh) return;
    uint i = y * bw + x;
    float az;
    for (uint j = 0u; j < half_g; ++j) {
      vec4 a, b;
      block(x, y, j, a, b, az);
      tabv[i * half_g + j] = floatBitsToUint(a);
      tabz[i * half_g + j] = floatBitsToUint(b);
    }
    tz[i] = floatBitsToUint(az);
    return;
  }
  uint line = gl_GlobalInvocationID.y * CSSM_BASIS_ROW + gl_GlobalInvocationID.x;
  uint y = line / (half_g + 1u), part = line % (half_g + 1u);
  if (y >= bh) return;
  uvec4 ra = uvec4(0u), rb = uvec4(0u);
  uint rz = 0u;
  // One block() a texel for every lane, the z part's too (its group's values unused): lavapipe
  // runs every lane through both branches, so two calls cost every lane both.
  uint j = min(part, half_g - 1u);
  for (uint x = 0u; x < bw; ++x) {
    vec4 a, b;
    float az;
    uint i = y * bw + x;
    block(x, y, j, a, b, az);
    if (part < half_g) {
      ra += uvec4(quant(a.x), quant(a.y), quant(a.z), quant(a.w));
      rb += uvec4(quant(b.x), quant(b.y), quant(b.z), quant(b.w));
      tabv[i * half_g + part] = ra;
      tabz[i * half_g + part] = rb;
    } else {
      rz += quant(az);
      tz[i] = rz;
    }
  }
}
