#version 450
// Pass reflections.pack (issue 18): everything a tap of reflections.isg reads, packed into two
// 16-byte texels per pixel so that a tap is two loads instead of about fifteen scattered floats
// from planar buffers: refl.pack.geo = (P − eye as float bits, octahedral N) and
// refl.pack.color = (refl, refl.dist or REFL_NO_REFLECTION); then the same, from
// REFL_COARSE_BASE, for one pixel of each REFL_COARSE² cell (the coarse taps of wide searches).
// Positions are relative to the camera (shaders/isg_view.h), so a scene far from the origin
// keeps its precision.
#extension GL_GOOGLE_include_directive : require
#include "reflections_isg_io.h"
#include "isg_view.h"
#include "isg_texels.h"
layout(local_size_x = REFL_PACK_LOCAL, local_size_y = 1) in;
layout(binding = 0) uniform samplerBuffer refl;
layout(binding = 1) uniform samplerBuffer dist;
layout(binding = 2) uniform samplerBuffer weight;
layout(binding = 3) uniform samplerBuffer nrm;
layout(binding = 4) uniform samplerBuffer geo;  // P (3 planes) or Z
layout(binding = 5) uniform samplerBuffer fg;
layout(std430, binding = 6) writeonly buffer PackGeo { uvec4 pack_geo[]; };
layout(std430, binding = 7) writeonly buffer PackColor { vec4 pack_color[]; };
// The same buffers from texel REFL_COARSE_BASE: the cells.
layout(std430, binding = 8) writeonly buffer CoarseGeo { uvec4 coarse_geo[]; };
layout(std430, binding = 9) writeonly buffer CoarseColor { vec4 coarse_color[]; };
layout(push_constant) uniform Push { ReflIsgPush pc; };
// Settings that choose code paths (REFL_HAS_*): compiled in, not branched on.
layout(constant_id = 0) const uint REFL_FLAGS = 0u;

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint n = pc.width * pc.height, i = p.y * pc.width + p.x;
  mat3 rot = mat3(pc.r00, pc.r10, pc.r20, pc.r01, pc.r11, pc.r21, pc.r02, pc.r12, pc.r22);
  vec3 rel;
  if ((REFL_FLAGS & REFL_HAS_POSITION) != 0u) {
    rel = isg_rel_from_world(isg_at3(geo, i, n), vec3(pc.eye_x, pc.eye_y, pc.eye_z),
                             vec3(pc.eye_lo_x, pc.eye_lo_y, pc.eye_lo_z));
  } else {
    // Frame coordinates (a tile adds its origin), so a tile rounds as the whole frame does.
    vec2 xy = vec2(p + uvec2(pc.origin & 0xffffu, pc.origin >> 16)) + 0.5;
    rel = isg_rel_from_depth(xy, texelFetch(geo, int(i)).r, vec2(pc.cx, pc.cy), pc.f_px, rot);
  }
  vec3 N = isg_at3(nrm, i, n);
  N = length(N) > 0.0 ? N : vec3(0.0, 0.0, 1.0);
  uvec4 g = uvec4(floatBitsToUint(rel), isg_oct_encode(N));
  vec3 w = isg_at3(weight, i, n);
  bool has_refl = texelFetch(fg, int(i)).r != 0.0 && max(w.r, max(w.g, w.b)) > 0.0;
  float d = texelFetch(dist, int(i)).r;
  vec4 c = vec4(isg_at3(refl, i, n), has_refl ? (d > 0.0 ? d : 0.0) : REFL_NO_REFLECTION);
  pack_geo[i] = g;
  pack_color[i] = c;
  // The pixel its coarse cell copies (REFL_COARSE_PICK, or the image's last row / column).
  uvec2 cell = p / REFL_COARSE;
  if (p == min(cell * REFL_COARSE + REFL_COARSE_PICK, uvec2(pc.width, pc.height) - 1u)) {
    uint j = REFL_COARSE_CELL(pc.width, cell.x, cell.y);
    coarse_geo[j] = g;
    coarse_color[j] = c;
  }
}
