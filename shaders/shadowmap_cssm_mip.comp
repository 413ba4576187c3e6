#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmap_cssm_io.h"
// CSSM mipmap prefiltering (§5.3.1): level pc.level of every basis layer, each texel the 2x2
// box of the level below (the last row or column of an odd level repeats).
layout(local_size_x = CSSM_LOCAL, local_size_y = CSSM_LOCAL) in;
layout(std430, binding = 0) readonly buffer Cprm { CssmParams c; };
layout(push_constant) uniform Push { CssmPush pc; };
#define CSSM_TABLES_BINDING 1
#define CSSM_TABLES_READ
#define CSSM_TABLES_WRITE
#include "shadowmap_cssm_common.h"

float tab(uint layer, uint j) { return uintBitsToFloat(cssm_get(layer, j)); }

void main() {
  uint l = pc.level;
  uint w1 = c.level_w[l], h1 = c.level_h[l], w0 = c.level_w[l - 1u], h0 = c.level_h[l - 1u];
  uint x = gl_GlobalInvocationID.x, y = gl_GlobalInvocationID.y;
  if (x >= w1 || y >= h1 * c.layers) return;
  uint layer = y / h1, yy = y % h1;
  uint s = c.level_off[l - 1u];
  uint xa = 2u * x, xb = min(2u * x + 1u, w0 - 1u), ya = 2u * yy, yb = min(2u * yy + 1u, h0 - 1u);
  float v = 0.25 * ((tab(layer, s + ya * w0 + xa) + tab(layer, s + ya * w0 + xb)) +
                    (tab(layer, s + yb * w0 + xa) + tab(layer, s + yb * w0 + xb)));
  cssm_set(layer, c.level_off[l] + yy * w1 + x, floatBitsToUint(v));
}
