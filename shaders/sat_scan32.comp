#version 450
#extension GL_GOOGLE_include_directive : require
#include "sat_io.h"
// In-place inclusive prefix sums of 32-bit integers in wrapping (modular) arithmetic, along rows
// (axis 0) or columns (axis 1), one invocation a line and uint as sat_scan.comp. An entry is
// pc.tables consecutive uints (the tables interleaved, sat_io.h). Any rectangle sum taken from four entries in the same arithmetic is exact while its
// true value lies within ±2^31 (CSSM's basis SATs, shadowmap_cssm_io.h).
layout(local_size_x = SAT_LINES, local_size_y = 1) in;
layout(std430, binding = 0) buffer Sat { uint sat[]; };
layout(push_constant) uniform Push { SatPush pc; };

void main() {
  // Invocation x: uint (x % tables) of line (x / tables), so neighbouring lanes touch
  // neighbouring uints along rows and along columns alike.
  uint id = gl_GlobalInvocationID.x, line = id / pc.tables, word = id % pc.tables;
  uint len = pc.axis == 0u ? pc.width : pc.height;
  uint lines = pc.axis == 0u ? pc.height : pc.width;
  if (line >= lines) return;
  uint base = (pc.axis == 0u ? line * pc.width : line) * pc.tables + word;
  uint stride = (pc.axis == 0u ? 1u : pc.width) * pc.tables;
  uint run = 0u;
  for (uint j = 0u; j < len; ++j) {
    uint k = base + j * stride;
    run += sat[k];
    sat[k] = run;
  }
}
