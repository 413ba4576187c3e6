#ifndef FOREGROUND_IO_H
#define FOREGROUND_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
#define FOREGROUND_LOCAL 16
// fg = 0 on background pixels (alpha 0, depth <= 0 or depth >= 1e9), 1 elsewhere.
struct ForegroundPush {
  uint width;
  uint height;
  uint has_alpha;    // beauty has an A plane, at plane index 3 of binding 0
  uint has_depth;    // binding 1 holds Z
};
ISG_IO_END
#endif
