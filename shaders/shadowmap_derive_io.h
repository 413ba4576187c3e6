#ifndef SHADOWMAP_DERIVE_IO_H
#define SHADOWMAP_DERIVE_IO_H
// Pass shadows.derive: L.shadow / L.occluder from the shadow map (parameters: ShadowmapParams).
#include "shadowmap_io.h"
ISG_IO_BEGIN
struct ShadowmapDerivePush {
  uint width;
  uint height;
  uint write_shadow;  // 0: L.shadow came from the renderer and is kept
};
ISG_IO_END
#endif
