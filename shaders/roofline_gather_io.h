#ifndef ROOFLINE_GATHER_IO_H
#define ROOFLINE_GATHER_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
// Workgroup shape: 8x8 was at the top with 16x16 of those tried on lavapipe (lib/roofline/roofline.h
// has the figures); 4x4 is clearly slower, the rest within the shared machine's noise.
#define ROOFLINE_LOCAL_X 8
#define ROOFLINE_LOCAL_Y 8
// The roofline gather (issue 18): dst = Σ w·src.rgb / Σ w, Σ w over `taps` integer offsets,
// w = exp(−(src.w − centre.w)² · falloff).
struct RooflinePush {
  uint width;
  uint height;
  uint taps;
  float falloff;  // 1 / (2σ²) of the depth range weight
};
ISG_IO_END
#endif
