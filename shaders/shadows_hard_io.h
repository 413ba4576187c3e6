#ifndef SHADOWS_HARD_IO_H
#define SHADOWS_HARD_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
#define SHADOWS_HARD_LOCAL 16
// Placeholder soft-shadow method `hard`: L.softshadow = L.shadow.
struct ShadowsHardPush {
  uint width;
  uint height;
};
ISG_IO_END
#endif
