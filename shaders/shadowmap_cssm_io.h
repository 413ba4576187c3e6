#ifndef SHADOWMAP_CSSM_IO_H
#define SHADOWMAP_CSSM_IO_H
#include "isg_io.h"
#include "shadowmap_hsm_io.h"
ISG_IO_BEGIN
#define CSSM_LOCAL 16
#define CSSM_BASIS_ROW 256u     // shadows.cssm.basis (SAT): lanes a dispatch row
#define CSSM_MAX_LEVELS 16     // mip levels: maps up to 32768 texels a side
#define CSSM_FILTER_SAT 0u     // shadows.cssm_filter = sat: 32-bit integer SATs (§7.5.4's format)
#define CSSM_FILTER_MIPMAP 1u  // shadows.cssm_filter = mipmap: 2x2 box pyramids (float)
#define CSSM_MAX_ORDER 16      // shadows.cssm_order's range
#define CSSM_NARROW_MARGIN 1.7  // a narrowed blocker search's radius over its cone's (cssm.cpp)
// Convolution soft shadow maps (thesis ch. 5). The 4M + 1 basis images, for k = 1..M and
// c_k = π(2k − 1) (eq. 5.10, Annen07):
//   cos(c_k ζ), sin(c_k ζ)            CSM (eq. 5.2-5.3)
//   z·cos(c_k ζ), z·sin(c_k ζ)        CSM-Z (eq. 5.11)
//   z                                 the z/2 term of eq. 5.11
// with z ∈ [0, 1] the map depth normalised over [zmin, zmin + zrange] (background: 1) and
// ζ = s_z·z the argument of the expansion (s_z = 1 − 2·x0 keeps the shifted step off the
// expansion's period boundary). Layout, so that one 16-byte load reads four images at a texel:
// buffer `tab` holds two halves of `groups`/2 uvec4 per texel, the CSM half (texel e's group j
// at e·groups/2 + j: the cos, sin of term 2j, then of term 2j + 1) and after it, from uvec4
// half_texels, the CSM-Z half likewise (a missing last term of odd M is zero); buffer `tz`
// holds the z image, a uint per texel. The passes that write a half bind it alone (a storage
// buffer's range, 128 MiB on lavapipe, holds a half: M = 16 at 1024²); the shading pass reads
// the whole through a texel view (2^27 texels). SAT (CSSM_FILTER_SAT): texel (x, y) is the table's entry
// (x + 1, y + 1) (the zero row and column are implicit), a 32-bit integer, modular: values
// are quantised to sat_scale units, at most 2^30 over the largest rectangle a kernel reads,
// so its sum, taken in wrapping uint arithmetic from four entries, is exact (Lauritzen07's
// integer SATs, which VSSM §7.5.4 adopts). Mipmap: every level of the chain, level l from
// texel level_off[l], as float bits. Read from storage buffers (std430, no padding).
struct CssmParams {
  uint order, prefilter, groups, levels;  // M, CSSM_FILTER_*, uvec4 groups a texel, mip levels
  float zmin, zrange, s_z, x0;         // depth normalisation; step shift (ringing, §5.2.3)
  float alpha;                         // ringing scale about 1/2 (§5.2.3, Fig. 5.2c)
  float sharpen_a, sharpen_b;          // A, B of eq. 5.9
  float sat_scale;                     // SAT fixed point: integer units per unit of value
  uint basis_shift;                    // basis texels are 2^basis_shift map texels a side
  uint max_split;                      // shadows.cssm_split: most sub-kernels a side
  uint narrow;                         // shadows.cssm_narrow: narrowed blocker searches
  uint half_texels;                    // uvec4s in a half of `tab` (the CSM-Z half's first)
  uint level_w[CSSM_MAX_LEVELS], level_h[CSSM_MAX_LEVELS];
  uint level_off[CSSM_MAX_LEVELS];  // first texel of each mip level (0 for the SAT)
  HsmLevelsGpu hsm;                 // the min-max HSM's levels (cssm.cpp: lit and umbra proofs)
};
// Basis: width, height = the map (the basis, level_w/h[0], is it in blocks); mip: the level
// built (its size from CssmParams).
struct CssmPush {
  uint width, height, level, pad0;
};
ISG_IO_END
#endif
