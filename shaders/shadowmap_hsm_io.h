#ifndef SHADOWMAP_HSM_IO_H
#define SHADOWMAP_HSM_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
#define HSM_MAX_LEVELS 16
#define HSM_LOCAL 16
// The min-max HSM (lib/effects/shadowmaps/hsm.h) as the shading passes read it: level 0 is the map
// itself (depths clamped to far_z), levels 1... a vec2 (min, max) per texel from offset 0.
struct HsmLevelsGpu {
  uint levels;
  float far_z;
  uint pad0, pad1;
  uint off[HSM_MAX_LEVELS];
  uint w[HSM_MAX_LEVELS];
  uint h[HSM_MAX_LEVELS];
};
// One level from the one below (level 1 from the map, clamped to far_z).
struct HsmPush {
  uint src_off, dst_off, src_w, src_h;
  uint dst_w, dst_h, from_map;
  float far_z;
};
ISG_IO_END
#endif
