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
#endif
