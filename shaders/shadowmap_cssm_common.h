// GLSL only: what the cssm passes share. Before including, declare the buffer
//   cprm (CssmParams c).
#ifndef SHADOWMAP_CSSM_COMMON_H
#define SHADOWMAP_CSSM_COMMON_H

// (cos, sin) of π·m·x, m = 2k − 1 (so c_k x, eq. 5.10), with the argument reduced to [−π, π]
// first: the built-ins are only specified there, and c_k ζ reaches 31π for M = 16.
vec2 cssm_cis(float m, float x) {
  float t = m * x;
  t -= 2.0 * floor(0.5 * t + 0.5);  // [−1, 1)
  return vec2(cos(3.14159265358979 * t), sin(3.14159265358979 * t));
}

// A light depth normalised over the map's depth range; background texels (contract: <= 0 or
// >= ISG_BACKGROUND_DEPTH) are as far as the farthest blocker.
float cssm_norm(float z) {
  if (!(z > 0.0 && z < ISG_BACKGROUND_DEPTH)) return 1.0;
  return clamp((z - c.zmin) / c.zrange, 0.0, 1.0);
}

#endif
