// Decoding an EXR's pixels with OpenEXR straight into planar buffers, one per channel. Shared by
// isg (inputs it trusts: limits.check_seconds = 0) and the isg-exrcheck helper, which runs it in
// a child process for every other input; so this header needs nothing but the standard library.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace isg::io {

// One channel to decode: the part it lives in and its name in that part's channel list.
struct ExrPlane {
  int part = 0;
  std::string name;
};

// What to decode: a window holding every part's data window (their union); plane i goes to the
// i-th buffer, which must hold zeros where its part has no data.
struct ExrDecodeRequest {
  int x0 = 0, y0 = 0, width = 0, height = 0;
  std::vector<ExrPlane> planes;
  size_t pixels() const { return size_t(width) * size_t(height); }
};

// Decodes every plane of `file` into `plane(i)`: width * height 4-byte values, row-major, top row
// first. HALF and FLOAT channels arrive as floats; UINT channels as their raw 32-bit values, for
// the caller to convert. OpenEXR's thread pool decodes the chunks in parallel. Throws
// std::exception on anything wrong: damaged data, a missing channel, a part whose data window
// lies outside the request.
void decode_exr_planes(const std::string& file, const ExrDecodeRequest& req,
                       const std::function<void*(size_t)>& plane);

// The number of threads OpenEXR's global pool should have for whole-frame reads and writes:
// one per core, as OIIO sets it (so raising the pool to it changes nothing OIIO expects).
int exr_thread_count();

}  // namespace isg::io
