#ifndef COMPOSITE_TERM_IO_H
#define COMPOSITE_TERM_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
#define COMPOSITE_TERM_LOCAL 16
// Lanes are laid out in rows of this many (a multiple of COMPOSITE_TERM_LOCAL): lane (x, y) takes
// texel y * COMPOSITE_TERM_ROW + x of each plane.
#define COMPOSITE_TERM_ROW 512u
// One term of the contract's composite: C.rgb += W.rgb * (X - Y) on foreground pixels,
//   shadows:     W = L.direct,     X = L.softshadow, Y = L.shadow
//   reflections: W = refl.weight,  X = refl.glossy,  Y = refl
// X and Y have x_planes planes (1: broadcast to RGB, or 3).
struct CompositeTermPush {
  uint width;
  uint height;
};
ISG_IO_END
#endif
