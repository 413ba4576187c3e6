// Large plates (limits.tile_size): an image processed in tiles, each with the apron its passes
// read, gives what one piece gives, channel for channel.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "effects/params.h"
#include "run/job.h"
#include "support/gpu_fixture.h"
#include "support/synth_case.h"

namespace {
class Tiles : public isg::test::GpuTest {};

struct Diff {
  double max = 0;
  size_t channels = 0;
};
// Runs `input` whole and in tiles of `edge` pixels with `sets`; the largest difference over
// every output channel.
Diff tiled_against_whole(isg::gpu::Context& ctx, const std::filesystem::path& dir, int edge,
                         const std::vector<std::pair<std::string, std::string>>& sets,
                         int* tiles) {
  isg::run::JobConfig job{isg::io::read_scene(dir / "scene.json"), "", isg::effects::default_params()};
  for (const auto& [k, v] : sets) job.params.set_text(k, v, "test");
  auto whole = isg::run::load_frame(job, (dir / "aovs.exr").string());
  isg::run::process_frame(ctx, job, whole);
  job.params.set_text("limits.tile_size", std::to_string(edge), "test");
  auto tiled = isg::run::load_frame(job, (dir / "aovs.exr").string());
  *tiles = isg::run::process_frame(ctx, job, tiled).tiles;
  Diff d;
  EXPECT_EQ(whole.img.channel_names(), tiled.img.channel_names());
  for (const auto& ch : whole.img.channels) {
    const auto* t = tiled.img.find(ch.name);
    if (!t) continue;
    ++d.channels;
    for (size_t i = 0; i < ch.data.size(); ++i) {
      const double e = std::abs(double(ch.data[i]) - t->data[i]);
      if (e > d.max) d.max = e;
    }
  }
  return d;
}
}  // namespace

// Soft shadows (isg), glossy reflections and depth of field (isg) on isg-synth `contact`:
// 192 x 108 in 48-pixel tiles (each with its apron of the passes' reach).
TEST_F(Tiles, ImageSpaceEffectsInTilesEqualOnePiece) {
  const auto dir = isg::test::synth_case({"contact", 192, 108, 0}, "tiles-contact");
  for (const char* dof : {"none", "isg", "layered"}) {
    int tiles = 0;
    const Diff d = tiled_against_whole(ctx(), dir, 48,
                                       {{"dof.method", dof}, {"reflections.max_radius", "24"},
                                        {"shadows.max_radius", "24"}, {"dof.max_coc", "6"}},
                                       &tiles);
    std::printf("dof %s: %d tiles, %zu channels, largest difference %.3g\n", dof, tiles,
                d.channels, d.max);
    EXPECT_GT(tiles, 1);
    EXPECT_GT(d.channels, 10u);
    EXPECT_EQ(d.max, 0.0);  // bitwise: the same arithmetic on the same pixels
  }
}

// Glossy reflections with wide lobes: reflections.max_radius 80 takes footprints past
// REFL_REUSE_RADIUS (the 4x4 blocks' gathers blended across tile borders) and gather taps past
// REFL_COARSE_GATHER (the prefiltered coarse cells). Pieces start at multiples of 16 pixels, so
// the block and cell grids are the frame's: 320 x 180 in 64-pixel tiles.
TEST_F(Tiles, WideGlossyLobesInTilesEqualOnePiece) {
  const auto dir = isg::test::synth_case({"contact", 320, 180, 0}, "tiles-contact-320");
  int tiles = 0;
  const Diff d = tiled_against_whole(
      ctx(), dir, 64, {{"shadows.method", "hard"}, {"reflections.max_radius", "80"}}, &tiles);
  std::printf("%d tiles, %zu channels, largest difference %.3g\n", tiles, d.channels, d.max);
  EXPECT_GT(tiles, 4);
  EXPECT_GT(d.channels, 10u);
  EXPECT_EQ(d.max, 0.0);
}

// The shadow-map methods (receiver plane from the screen neighbours, pixel-hash rotation).
TEST_F(Tiles, ShadowMapMethodsInTilesEqualOnePiece) {
  const auto dir = isg::test::synth_case({"contact", 192, 108, 0, 1, 128}, "tiles-smap");
  for (const char* m : {"pcss", "vssm"}) {
    int tiles = 0;
    const Diff d = tiled_against_whole(ctx(), dir, 64, {{"shadows.method", m}}, &tiles);
    std::printf("%s: %d tiles, largest difference %.3g\n", m, tiles, d.max);
    EXPECT_GT(tiles, 1);
    EXPECT_EQ(d.max, 0.0);
  }
}
