// Executes a plan on a GPU context: uploads what the plan declares, records its passes in one
// sequence, reads back the products and writes the contract's output channels into the image.
#pragma once

#include <cstdint>
#include <set>
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
  double dof_cheap_fraction = -1;  // tiles that took dof's cheap path (-1: dof did not run)
  double refl_skipped_fraction = -1;  // tiles with nothing glossy (-1: reflections did not run)
  // Per light where shadows.isg ran: tiles that kept L.shadow (fully lit or umbra), and pixels
  // whose search or gather radius exceeded shadows.max_radius (clamped).
  struct ShadowTiles {
    std::string light;
    double skipped_fraction = 0;
    uint64_t clamped_pixels = 0, full_pixels = 0;
  };
  std::vector<ShadowTiles> shadows;
  // Per light where a shadow-map method ran: of the foreground pixels inside the map, those
  // proven fully lit or in umbra (filter skipped) and those whose kernel was clamped.
  struct ShadowmapSkip {
    std::string light, method;
    double skipped_fraction = 0;
    uint64_t pixels = 0, clamped_pixels = 0;
    uint64_t gpu_bytes = 0;  // the method's own buffers (SATs, basis images, HSM)
  };
  std::vector<ShadowmapSkip> shadowmaps;
  // The gather passes' load, for samples/s against the roofline (--timings): pixels that ran
  // the search and gather, and the lattice samples taken in all (search + gather).
  struct GatherLoad {
    std::string pass;  // its label in `passes`
    uint64_t pixels = 0, samples = 0;
  };
  std::vector<GatherLoad> gathers;
  int tiles = 0;  // large plates: tiles the frame was processed in (0: one piece)
  std::set<std::string> warnings;  // one line each, naming the file (e.g. NaN depths in a map)
  double gpu_ms() const;
};

// Adds R G B A (the composite; an input beauty named R G B A is kept as input.R/G/B/A) and each
// effect's new channels (L.softshadow, ...) to `img`.
Stats execute(gpu::Context& ctx, const plan::Plan& plan, const io::Roles& roles, io::Image& img);

}  // namespace isg::run
