#version 450
// Pass reflections.pack.cells (issue 18): a lane per REFL_COARSE² cell, after reflections.pack.
// A coarse tap stands for its cell: the cell's colour is refl averaged over the cell's pixels
// that hold reflection data, each weighed by its range weight (eq. 10) to the pixel the cell
// keeps (whose geometry and distance reflections.pack copied), so a far gather tap reads the
// cell's part of that surface, prefiltered, rather than one pixel of it (issue 18's pre-filtered
// footprints). Shared gloss composite RMSE at 25x49 samples 0.00216 -> 0.00206.
// lib/effects/reflections/reflections.cpp's make_cells mirrors it.
#extension GL_GOOGLE_include_directive : require
#include "reflections_isg_io.h"
#include "isg_view.h"
layout(local_size_x = REFL_PACK_LOCAL, local_size_y = 1) in;
layout(binding = 0) uniform usamplerBuffer pack_geo;   // the pixels' then the cells' texels
layout(binding = 1) uniform samplerBuffer pack_color;
// The cells' colours: refl.pack.color from REFL_COARSE_BASE.
layout(std430, binding = 2) buffer CoarseColor { vec4 coarse_color[]; };
layout(push_constant) uniform Push { ReflIsgPush pc; };
#include "reflections_range.h"  // range_fn, eq. 10-12

void main() {
  uvec2 cell = gl_GlobalInvocationID.xy;
  uvec2 cells = (uvec2(pc.width, pc.height) + REFL_COARSE - 1u) / REFL_COARSE;
  if (cell.x >= cells.x || cell.y >= cells.y) return;
  uint j = REFL_COARSE_CELL(pc.width, cell.x, cell.y);
  vec4 c0 = coarse_color[j];
  if (c0.w < 0.0) return;  // the kept pixel holds nothing to gather: the tap skips the cell
  uvec4 g0 = texelFetch(pack_geo, int(REFL_COARSE_BASE(pc.width, pc.height) + j));
  vec3 P0 = uintBitsToFloat(g0.xyz), N0 = isg_oct_decode(g0.w);
  uvec2 lo = cell * REFL_COARSE, hi = min(lo + REFL_COARSE, uvec2(pc.width, pc.height));
  vec3 s = vec3(0.0);
  float ws = 0.0;  // > 0: the kept pixel is among them, its weight 1
  for (uint y = lo.y; y < hi.y; ++y)
    for (uint x = lo.x; x < hi.x; ++x) {
      uint i = y * pc.width + x;
      vec4 c = texelFetch(pack_color, int(i));
      if (c.w < 0.0) continue;
      float w = range_fn(texelFetch(pack_geo, int(i)), P0, N0);
      s += w * c.rgb;
      ws += w;
    }
  coarse_color[j] = vec4(s / ws, c0.w);
}
