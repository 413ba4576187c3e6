#ifndef SAT_IO_H
#define SAT_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
#define SAT_LOCAL 256  // sat.quantize: invocations a workgroup along x
#define SAT_LINES 64   // sat.scan: lines (invocations) a workgroup
// Summed-area tables in 64-bit fixed point (two uint32: lo, hi, two's complement), so any
// rectangle sum is exact whatever its size: entries are q = floor(((min(v, far) − shift)^power − offset)
// · scale + 0.5) with |q| < 2^31 (offset: the mean, scale from the largest |deviation|), so a
// 4096² table stays below 2^55.
struct SatPush {
  uint width, height, axis, power;  // axis: 0 scans rows, 1 columns (one invocation a line)
  float offset, scale, far_z, shift;  // shift: subtracted before the power (variance)
  uint tables, pad0;  // sat_scan32: uints an entry (several tables interleaved); else 1
};
ISG_IO_END
#endif
