#ifndef SHADOWMAP_HSM_IO_H
#define SHADOWMAP_HSM_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
#define HSM_MAX_LEVELS 16
#define HSM_LOCAL 16
// Min-max hierarchical shadow map (thesis §7.5.1, mipmap variant), shared by VSSM and CSSM:
// level 0 is the map itself (depths clamped to far_z where read, not stored); levels 1... are
// stored from offset 0 of their own buffer, each texel the (min, max) of the up to 2x2 below.
struct HsmLevels {
  uint levels;  // level 0 included
  float far_z;  // depths clamped to it (the map's farthest surface; background behind it)
  uint pad0, pad1;
  uint off[HSM_MAX_LEVELS];  // level k: first texel in the buffer (0 for level 0, the map)
  uint w[HSM_MAX_LEVELS];
  uint h[HSM_MAX_LEVELS];
};
// One HSM level from the one below (level 1 from the map, clamped to far_z).
struct HsmPush {
  uint src_off, dst_off, src_w, src_h;
  uint dst_w, dst_h, from_map;
  float far_z;
};
ISG_IO_END
#endif
