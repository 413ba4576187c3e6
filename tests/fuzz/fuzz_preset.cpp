#include "effects/params.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path = fuzz_input_file(data, size, ".toml");
  auto p = isg::effects::default_params();
  try {
    p.load_preset(path, {});
    p.to_toml();
  } catch (const isg::params::ParamError&) {
  }
  return 0;
}
