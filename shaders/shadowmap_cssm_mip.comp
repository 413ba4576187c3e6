#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_cssm_io.h"
// CSSM mipmap prefiltering (§5.3.1): level pc.level of every basis image, each texel the 2x2
// box of the level below (the last row or column of an odd level repeats). Invocation y picks
// the row; x walks the row's texels times the groups a texel, the z image after them.
layout(local_size_x = CSSM_LOCAL, local_size_y = CSSM_LOCAL) in;
layout(std430, binding = 0) readonly buffer Cprm { CssmParams c; };
layout(std430, binding = 1) buffer TabV { uvec4 tabv[]; };  // tab's CSM half
layout(std430, binding = 2) buffer TabZ { uvec4 tabz[]; };  // tab's CSM-Z half
layout(std430, binding = 3) buffer Tz { uint tz[]; };
layout(push_constant) uniform Push { CssmPush pc; };

void main() {
  uint l = pc.level, G = c.groups;
  uint w1 = c.level_w[l], h1 = c.level_h[l], w0 = c.level_w[l - 1u], h0 = c.level_h[l - 1u];
  uint gx = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
  if (gx >= w1 * (G + 1u) || y >= h1) return;
  uint x = gx % w1, j = gx / w1;  // texel, group (G: the z image)
  uint s = c.level_off[l - 1u];
  uint xa = 2u * x, xb = min(2u * x + 1u, w0 - 1u), ya = 2u * y, yb = min(2u * y + 1u, h0 - 1u);
  uvec4 t = uvec4(s + ya * w0 + xa, s + ya * w0 + xb, s + yb * w0 + xa, s + yb * w0 + xb);
  uint d = c.level_off[l] + y * w1 + x;
  uint H = G / 2u;
  if (j < H) {
    vec4 v = 0.25 * ((uintBitsToFloat(tabv[t.x * H + j]) + uintBitsToFloat(tabv[t.y * H + j])) +
                     (uintBitsToFloat(tabv[t.z * H + j]) + uintBitsToFloat(tabv[t.w * H + j])));
    tabv[d * H + j] = floatBitsToUint(v);
  } else if (j < G) {
    uint k = j - H;
    vec4 v = 0.25 * ((uintBitsToFloat(tabz[t.x * H + k]) + uintBitsToFloat(tabz[t.y * H + k])) +
                     (uintBitsToFloat(tabz[t.z * H + k]) + uintBitsToFloat(tabz[t.w * H + k])));
    tabz[d * H + k] = floatBitsToUint(v);
  } else {
    float v = 0.25 * ((uintBitsToFloat(tz[t.x]) + uintBitsToFloat(tz[t.y])) +
                      (uintBitsToFloat(tz[t.z]) + uintBitsToFloat(tz[t.w])));
    tz[d] = floatBitsToUint(v);
  }
}
