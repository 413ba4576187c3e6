// Executes a plan on a GPU context: uploads what the plan declares, records its passes in one
// sequence, reads back the products and writes the contract's output channels into the image.
#pragma once

#include <string>
#include <vector>

#include "gpu/gpu.h"
#include "io/image.h"
#include "io/roles.h"
#include "plan/plan.h"

namespace isg::run {

struct Stats {
  std::vector<gpu::PassTime> passes;  // GPU time per pass (timestamp queries)
  double upload_ms = 0, record_ms = 0, gpu_wall_ms = 0, download_ms = 0;
  double gpu_ms() const;
};

// Adds R G B A (the composite; an input beauty named R G B A is kept as input.R/G/B/A) and each
// effect's new channels (L.softshadow, ...) to `img`.
Stats execute(gpu::Context& ctx, const plan::Plan& plan, const io::Roles& roles, io::Image& img);

}  // namespace isg::run
