// Executes a plan on a GPU context: uploads what the plan declares, has each pass recorded by
// its effect's recorder in one sequence, reads back the products and writes the contract's
// output channels into the image. A Runner lives for the job: the recorders (and through the
// context, the kernels) are built once, and each frame or tile only re-records.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "effects/recorder.h"
#include "gpu/gpu.h"
#include "io/image.h"
#include "io/roles.h"
#include "plan/plan.h"

namespace isg::run {

struct Stats {
  std::vector<gpu::PassTime> passes;  // GPU time per pass (timestamp queries)
  double upload_ms = 0, record_ms = 0, gpu_wall_ms = 0, download_ms = 0;
  // Each effect instance's statistics (Effect::describe puts them in words).
  std::vector<effects::Report> reports;
  // The gather passes' load, for samples/s against the roofline (--timings).
  std::vector<effects::GatherLoad> gathers;
  int tiles = 0;  // large plates: tiles the frame was processed in (0: one piece)
  std::set<std::string> warnings;  // one line each, naming the file (e.g. NaN depths in a map)
  double gpu_ms() const;
  const effects::Report* report(const std::string& key) const;
  // Large plates: a tile's figures into the frame's (times and counts add up).
  void add_tile(const Stats& tile);
};

class Runner {
 public:
  explicit Runner(gpu::Context& ctx) : ctx_(ctx) {}
  gpu::Context& context() { return ctx_; }
  // Adds R G B A (the composite; an input beauty named R G B A is kept as input.R/G/B/A) and
  // each effect's new channels (L.softshadow, ...) to `img`.
  Stats execute(const plan::Plan& plan, const io::Roles& roles, io::Image& img);

 private:
  effects::Recorder& recorder(const std::string& effect);
  gpu::Context& ctx_;
  std::map<std::string, std::unique_ptr<effects::Recorder>> recorders_;
};

// A one-off run (a Runner for this plan only).
Stats execute(gpu::Context& ctx, const plan::Plan& plan, const io::Roles& roles, io::Image& img);

}  // namespace isg::run
