// GLSL only: positions relative to the camera, the form every gather reads (issue 18/19). A
// world position far from the origin is never formed in float on the GPU: P − eye is taken
// against the eye split into a float and its remainder (P − eye_hi is exact by Sterbenz where P
// is near the eye), and from depth the camera-space point is rotated into world axes.
// lib/effects/view.h is the double mirror.
#ifndef ISG_VIEW_H
#define ISG_VIEW_H

// P − eye for a world position P, eye = eye_hi + eye_lo.
vec3 isg_rel_from_world(vec3 P, vec3 eye_hi, vec3 eye_lo) { return (P - eye_hi) - eye_lo; }

// P − eye for planar depth z at frame pixel centre xy; rot is world -> camera.
vec3 isg_rel_from_depth(vec2 xy, float z, vec2 c, float f_px, mat3 rot) {
  vec3 cam = vec3((xy.x - c.x) / f_px * z, -(xy.y - c.y) / f_px * z, -z);
  return transpose(rot) * cam;
}

// Octahedral unit vector in two snorm16s (Cigolle et al. 2014): 4 bytes, ≤ 3e-5 rad of error.
uint isg_oct_encode(vec3 n) {
  n /= abs(n.x) + abs(n.y) + abs(n.z);
  vec2 e = n.xy;
  if (n.z < 0.0) e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return packSnorm2x16(e);
}
vec3 isg_oct_decode(uint bits) {
  vec2 e = unpackSnorm2x16(bits);
  vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  float t = max(-v.z, 0.0);
  v.x += v.x >= 0.0 ? -t : t;
  v.y += v.y >= 0.0 ? -t : t;
  return normalize(v);
}
#endif
