#ifndef ROOFLINE_GATHER_IO_H
#define ROOFLINE_GATHER_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
// Workgroup shape: fastest of 8x8, 16x16, 32x1, 64x1, 8x4, 4x4 on lavapipe (see
// lib/roofline/roofline.h for the figures).
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
