// GLSL only: the range function of eq. 10-12 on refl.pack.geo's texels (P − eye as float bits,
// octahedral N), shared by reflections.pack.cells (reflections_cells.comp: the coarse cells'
// means) and the dispatches of reflections.isg. Included after the push constants `pc` (ReflIsgPush); needs isg_view.h.
#ifndef REFLECTIONS_RANGE_H
#define REFLECTIONS_RANGE_H

// r = exp(-(a·l² + b·n²)/σ), l = |w(p_i) − w(p_0)| / scene_radius, n = 1 − N_i·N_0.
float range_fn(uvec4 g, vec3 P0, vec3 N0) {
  vec3 d = uintBitsToFloat(g.xyz) - P0;
  float l2 = dot(d, d) * (pc.inv_scene_radius * pc.inv_scene_radius);
  float nn = 1.0 - dot(isg_oct_decode(g.w), N0);
  return exp(-(pc.a * l2 + pc.b * nn * nn) * pc.inv_sigma);
}

#endif
