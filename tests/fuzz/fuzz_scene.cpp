#include "fuzz_common.h"
#include "io/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  try {
    auto s = isg::io::parse_scene(text, "fuzz.json");
    if (s.camera) s.camera->project({1, 2, 3});
  } catch (const isg::io::IoError&) {
  }
  return 0;
}
