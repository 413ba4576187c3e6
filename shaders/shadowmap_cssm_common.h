// GLSL only: what the cssm passes share. Before including, declare the buffer
//   cprm (CssmParams c), and define CSSM_TABLES_BINDING (the first of the CSSM_CHUNKS table
//   bindings) and CSSM_TABLES_READ and/or CSSM_TABLES_WRITE.
#ifndef SHADOWMAP_CSSM_COMMON_H
#define SHADOWMAP_CSSM_COMMON_H

#if defined(CSSM_TABLES_READ) && defined(CSSM_TABLES_WRITE)
#define CSSM_TABLES_QUAL
#elif defined(CSSM_TABLES_READ)
#define CSSM_TABLES_QUAL readonly
#else
#define CSSM_TABLES_QUAL writeonly
#endif
#define CSSM_TABLE(n) \
  layout(std430, binding = CSSM_TABLES_BINDING + n) CSSM_TABLES_QUAL buffer T##n { uint t##n[]; };
CSSM_TABLE(0)
CSSM_TABLE(1)
CSSM_TABLE(2)
CSSM_TABLE(3)
CSSM_TABLE(4)
CSSM_TABLE(5)
CSSM_TABLE(6)
CSSM_TABLE(7)

#ifdef CSSM_TABLES_READ
// Element j (uints) of basis layer `layer`.
uint cssm_get(uint layer, uint j) {
  uint ch = layer / c.chunk_layers, e = (layer - ch * c.chunk_layers) * c.layer_elems + j;
  switch (ch) {
    case 0u: return t0[e];
    case 1u: return t1[e];
    case 2u: return t2[e];
    case 3u: return t3[e];
    case 4u: return t4[e];
    case 5u: return t5[e];
    case 6u: return t6[e];
    default: return t7[e];
  }
}
#endif
#ifdef CSSM_TABLES_WRITE
void cssm_set(uint layer, uint j, uint v) {
  uint ch = layer / c.chunk_layers, e = (layer - ch * c.chunk_layers) * c.layer_elems + j;
  switch (ch) {
    case 0u: t0[e] = v; break;
    case 1u: t1[e] = v; break;
    case 2u: t2[e] = v; break;
    case 3u: t3[e] = v; break;
    case 4u: t4[e] = v; break;
    case 5u: t5[e] = v; break;
    case 6u: t6[e] = v; break;
    default: t7[e] = v; break;
  }
}
#endif

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
