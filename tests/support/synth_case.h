// An isg-synth scene generated into a test's temporary folder (for tests linking isg_synth).
#pragma once

#include <filesystem>
#include <string>

#include "support/images.h"
#include "synth.h"

namespace isg::test {

struct SynthCase {
  std::string scene;
  int width = 192, height = 108;
  int ref_spp = 64;  // 0: no ref/
  int aov_spp = 1;
  int shadowmap_size = 64;
};

// Writes the case into temp_dir(tag) (2 threads) and returns that folder.
inline std::filesystem::path synth_case(const SynthCase& c, const std::string& tag) {
  const auto dir = temp_dir(tag);
  synth::Options o;
  o.scene = c.scene;
  o.width = c.width;
  o.height = c.height;
  o.ref_spp = c.ref_spp > 0 ? c.ref_spp : 1;
  o.refs = c.ref_spp > 0;
  o.aov_spp = c.aov_spp;
  o.shadowmap_size = c.shadowmap_size;
  o.threads = 2;
  synth::generate(o, dir);
  return dir;
}

}  // namespace isg::test
