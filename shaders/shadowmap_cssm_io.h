#ifndef SHADOWMAP_CSSM_IO_H
#define SHADOWMAP_CSSM_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
#define CSSM_LOCAL 16
#define CSSM_MAX_LEVELS 16     // mip levels: maps up to 32768 texels a side
#define CSSM_FILTER_SAT 0u     // shadows.cssm_filter = sat: 64-bit fixed-point SATs
#define CSSM_FILTER_MIPMAP 1u  // shadows.cssm_filter = mipmap: 2x2 box pyramids (float)
#define CSSM_MAX_LAYERS 65     // 4M + 1 for M <= 16 (shadows.cssm_order's range)
#define CSSM_CHUNKS 8          // the layers are spread over up to 8 buffers (storage range)
#define CSSM_NARROW_MARGIN 1.7  // a narrowed blocker search's radius over its cone's (cssm.cpp)
// Convolution soft shadow maps (thesis ch. 5). The basis images are layers of one buffer, in
// this order, for k = 1..M and c_k = π(2k − 1) (eq. 5.10, Annen07):
//   [0, M) cos(c_k ζ), [M, 2M) sin(c_k ζ)          CSM (eq. 5.2-5.3)
//   [2M, 3M) z·cos(c_k ζ), [3M, 4M) z·sin(c_k ζ)   CSM-Z (eq. 5.11)
//   4M: z                                          the z/2 term of eq. 5.11
// with z ∈ [0, 1] the map depth normalised over [zmin, zmin + zrange] (background: 1) and
// ζ = s_z·z the argument of the expansion (s_z = 1 − 2·x0 keeps the shifted step off the
// expansion's period boundary). Each layer (its SAT, 2 uints an entry, or its whole mip chain,
// 1 float a texel) is layer_elems uints; chunk c holds layers [c·chunk_layers, ...) one after
// the other. Read from a storage buffer (std430, no padding).
struct CssmParams {
  uint order, prefilter, layers, levels;  // M, CSSM_FILTER_*, 4M + 1, mip levels (1 for SAT)
  float zmin, zrange, s_z, x0;         // depth normalisation; step shift (ringing, §5.2.3)
  float alpha;                         // ringing scale about 1/2 (§5.2.3, Fig. 5.2c)
  float sharpen_a, sharpen_b;          // A, B of eq. 5.9
  float sat_scale;                     // SAT fixed point: integer units per unit of value
  uint chunk_layers, layer_elems;      // layers a buffer, uints a layer
  uint basis_shift;                    // basis texels are 2^basis_shift map texels a side
  uint max_split;                      // shadows.cssm_split: most sub-kernels a side
  uint narrow;                         // shadows.cssm_narrow: narrowed blocker searches
  uint level_w[CSSM_MAX_LEVELS], level_h[CSSM_MAX_LEVELS];
  uint level_off[CSSM_MAX_LEVELS];  // first element of each mip level within a layer
};
// Basis: width, height = the map (the basis, level_w/h[0], is it in blocks); mip: the level
// built (its size from CssmParams).
struct CssmPush {
  uint width, height, level, pad0;
};
ISG_IO_END
#endif
