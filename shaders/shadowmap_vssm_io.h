#ifndef SHADOWMAP_VSSM_IO_H
#define SHADOWMAP_VSSM_IO_H
#include "isg_io.h"
#include "shadowmap_hsm_io.h"
ISG_IO_BEGIN
#define VSSM_NARROW_MARGIN 1.0  // a narrowed blocker search's box over its cone's (vssm.cpp)
// VSSM (thesis ch. 7): what the shading pass reads besides ShadowmapParams (std430: scalars
// and uint arrays only).
struct VssmParams {
  uint m;          // blocker search: m x m uniform sub-kernels (§7.4.2)
  uint tree_h;     // shadow: quad-tree height H (Algorithm 3)
  uint leaf_grid;  // PCF taps per non-planar leaf: leaf_grid² (0: the leaf is taken as lit)
  float flat_var;  // variance below it: planar (Threshold of §7.5.5, absolute)
  float contact;   // d − z_avg below it: contact PCF (ε of §7.5.4, absolute)
  float z0;        // the SAT of (z − z0)²: z0, the map's mean depth
  float off1, scale1, off2, scale2;  // fixed point of the two SATs (sat_io.h)
  uint narrow;                       // shadows.vssm_narrow: narrowed blocker searches
  uint m_first;  // the first search's split (shadows.vssm_m_wide where narrowed ones follow)
  uint pad1, pad2;
  HsmLevelsGpu hsm;  // the min-max HSM; its far_z: the map's farthest surface (depths clamped)
};
ISG_IO_END
#endif
