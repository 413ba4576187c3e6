// GLSL only: the sampling every gather shares (image-space gathering §3.1): a regular grid
// through the Shirley–Chiu concentric map, rotated per pixel by an integer hash of the pixel —
// never of the frame. lib/effects/sampling.h is its double mirror.
#ifndef ISG_SAMPLING_H
#define ISG_SAMPLING_H

uint isg_pixel_hash(uint x, uint y) {
  uint h = (x * 0x8da6b343u) ^ (y * 0xd8163841u);
  h ^= h >> 16; h *= 0x7feb352du; h ^= h >> 15; h *= 0x846ca68bu; h ^= h >> 16;
  return h;
}

// The pixel's rotation of the sample grid, in [0, 2π).
float isg_pixel_angle(uvec2 p) {
  return float(isg_pixel_hash(p.x, p.y)) * (2.0 * 3.14159265358979 / 4294967296.0);
}

// Cell k of a grid x grid lattice mapped onto the unit disk.
vec2 isg_concentric(uint k, uint grid) {
  const float pi = 3.14159265358979;
  float a = 2.0 * (float(k % grid) + 0.5) / float(grid) - 1.0;
  float b = 2.0 * (float(k / grid) + 0.5) / float(grid) - 1.0;
  if (a == 0.0 && b == 0.0) return vec2(0.0);
  float r, phi;
  if (abs(a) > abs(b)) { r = a; phi = (pi / 4.0) * (b / a); }
  else { r = b; phi = pi / 2.0 - (pi / 4.0) * (a / b); }
  return r * vec2(cos(phi), sin(phi));
}
// Half-resolution reuse (issue 18): the pixel at l in its workgroup against the workgroup's
// quads x quads grid of 2×2 quads, quad q standing at its top-left pixel 2q (clamped at the
// border): q0 the lower corner, a the bilinear fractions; corner k (bit 0: +x, bit 1: +y) weighs
// isg_quad_weight(a, k). lib/effects/sampling.h's quad_bilinear mirrors it.
// isg_cell_bilinear: the same over a grid of cells.x x cells.y cells of step x step pixels
// (reflections' 4x4 blocks over the whole image); a grid one cell wide keeps q0 at 0.
void isg_cell_bilinear(uvec2 l, uvec2 cells, float step, out uvec2 q0, out vec2 a) {
  vec2 f = vec2(l) / step;
  vec2 c = clamp(floor(f), vec2(0.0), vec2(max(ivec2(cells) - 2, ivec2(0))));
  q0 = uvec2(c);
  a = clamp(f - c, vec2(0.0), vec2(1.0));
}
void isg_quad_bilinear(uvec2 l, uint quads, out uvec2 q0, out vec2 a) { isg_cell_bilinear(l, uvec2(quads), 2.0, q0, a); }
float isg_quad_weight(vec2 a, uint k) {
  return ((k & 1u) != 0u ? a.x : 1.0 - a.x) * ((k >> 1u) != 0u ? a.y : 1.0 - a.y);
}

#endif
