// The whole EXR reading path isg runs: structure walk, OIIO's header walk, then decoding with
// OpenEXR in a child process (ISG_EXRCHECK names the isg-exrcheck binary; unset: in-process).
#include <cstdlib>

#include "fuzz_common.h"
#include "io/image.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path = fuzz_input_file(data, size, ".exr");
  isg::io::ReadLimits limits;
  limits.max_pixels = 1 << 22;
  limits.max_channels = 256;
  limits.max_bytes = int64_t(256) << 20;
  if (const char* c = std::getenv("ISG_EXRCHECK")) {
    limits.checker = c;
    limits.check_seconds = 5;
  }
  try {
    auto img = isg::io::read_exr(path, limits);
    isg::io::sanitize(img);
  } catch (const isg::io::IoError&) {
    // The expected outcome for damaged input: a one-line error.
  }
  return 0;
}
