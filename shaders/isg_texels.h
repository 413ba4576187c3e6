// GLSL only: planar images read through texel views (gpu.h's Slot::texels, docs/design.md):
// plane c of an n-pixel buffer starts at c·n.
#ifndef ISG_TEXELS_H
#define ISG_TEXELS_H
float isg_at(samplerBuffer b, uint i) { return texelFetch(b, int(i)).r; }
vec3 isg_at3(samplerBuffer b, uint i, uint n) {
  return vec3(isg_at(b, i), isg_at(b, n + i), isg_at(b, 2u * n + i));
}
vec4 isg_at4(samplerBuffer b, uint i, uint n) {
  return vec4(isg_at3(b, i, n), isg_at(b, 3u * n + i));
}
#endif
