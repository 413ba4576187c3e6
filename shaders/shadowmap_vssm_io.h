#ifndef SHADOWMAP_VSSM_IO_H
#define SHADOWMAP_VSSM_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
#define VSSM_MAX_LEVELS 16
#define HSM_LOCAL 16
#define VSSM_NARROW_MARGIN 1.0  // a narrowed blocker search's box over its cone's (vssm.cpp)
// VSSM (thesis ch. 7): what the shading pass reads besides ShadowmapParams (std430: scalars
// and uint arrays only).
struct VssmParams {
  uint m;          // blocker search: m x m uniform sub-kernels (§7.4.2)
  uint tree_h;     // shadow: quad-tree height H (Algorithm 3)
  uint leaf_grid;  // PCF taps per non-planar leaf: leaf_grid² (0: the leaf is taken as lit)
  uint levels;     // min-max HSM levels (level 0: the map)
  float flat_var;  // variance below it: planar (Threshold of §7.5.5, absolute)
  float contact;   // d − z_avg below it: contact PCF (ε of §7.5.4, absolute)
  float far_z;     // depths clamped to it (the map's farthest surface; background behind it)
  float z0;        // the SAT of (z − z0)²: z0, the map's mean depth
  float off1, scale1, off2, scale2;  // fixed point of the two SATs (sat_io.h)
  uint narrow;                       // shadows.vssm_narrow: narrowed blocker searches
  uint level_off[VSSM_MAX_LEVELS];   // HSM level k: first texel, width, height
  uint level_w[VSSM_MAX_LEVELS];
  uint level_h[VSSM_MAX_LEVELS];
};
// One HSM level from the one below (level 0 from the map, clamped to far_z).
struct HsmPush {
  uint src_off, dst_off, src_w, src_h;
  uint dst_w, dst_h, from_map;
  float far_z;
};
ISG_IO_END
#endif
