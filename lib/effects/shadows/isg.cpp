// The shadows.isg passes on the GPU (isg.h); their double reference is isg_reference.cpp.
#include "effects/shadows/isg.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>

#include "effects/sampling.h"
#include "effects/view.h"
#include "isg/shaders/shadows_isg.spv.h"
#include "isg/shaders/shadows_isg_tiles.spv.h"
#include "isg/shaders/shadows_isg_list.spv.h"
#include "isg/shaders/shadows_isg_own.spv.h"
#include "isg/shaders/shadows_isg_quads.spv.h"
#include "isg/shaders/shadows_isg_reach.spv.h"
#include "shadows_isg_io.h"

namespace isg::effects {

namespace {
// The bindings of shadows.isg's four dispatches (shaders/shadows_isg.h): the taps' texels,
// L.occluder, the tiles buffer, L.softshadow, the lattices, L.shadow.
std::vector<gpu::Slot> isg_slots() {
  return {gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::buffer,
          gpu::Slot::buffer, gpu::Slot::texels, gpu::Slot::texels};
}
}  // namespace

ShadowsIsgPass::ShadowsIsgPass(gpu::Context& ctx, uint32_t part_lanes)
    : ctx_(ctx),
      tiles_kernel_(ctx, "shadows.isg.tiles", isg_spv_shadows_isg_tiles,
                    {gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels,
                     gpu::Slot::buffer, gpu::Slot::buffer},
                    sizeof(shaders::ShadowsIsgTilesPush),
                    SHADOWS_ISG_TILE, SHADOWS_ISG_TILE),
      list_kernel_(ctx, "shadows.isg.list", isg_spv_shadows_isg_list,
                   {gpu::Slot::texels, gpu::Slot::buffer},
                   sizeof(shaders::ShadowsIsgListPush), SHADOWS_ISG_LIST_LOCAL, 1),
      reach_kernel_(ctx, "shadows.isg.reach", isg_spv_shadows_isg_reach, isg_slots(),
                    sizeof(shaders::ShadowsIsgPush), SHADOWS_ISG_TILE, SHADOWS_ISG_TILE),
      // .quads and .own: part_lanes_ lanes a sum (the local size's y; both run indirect).
      quads_kernel_(ctx, "shadows.isg.quads", isg_spv_shadows_isg_quads, isg_slots(),
                    sizeof(shaders::ShadowsIsgPush), SHADOWS_ISG_TILE * SHADOWS_ISG_TILE / 4, 1),
      kernel_(ctx, "shadows.isg", isg_spv_shadows_isg, isg_slots(), sizeof(shaders::ShadowsIsgPush),
              SHADOWS_ISG_TILE, SHADOWS_ISG_TILE),
      own_kernel_(ctx, "shadows.isg.own", isg_spv_shadows_isg_own, isg_slots(),
                  sizeof(shaders::ShadowsIsgPush), SHADOWS_ISG_OWN_LOCAL, 1),
      part_lanes_(part_lanes != 0 ? part_lanes
                  : ctx.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU
                      ? 1u
                      : std::min(SHADOWS_ISG_PART_LANES, ctx.info().subgroup_size)) {
  // A sum's lanes lie within one subgroup (shaders/shadows_isg.h).
  if (part_lanes_ == 0 || (part_lanes_ & (part_lanes_ - 1)) != 0 ||
      part_lanes_ > std::max(ctx.info().subgroup_size, 1u))
    throw gpu::GpuError("shadows.isg: " + std::to_string(part_lanes_) +
                        " lanes a sum is not a power of two up to the subgroup size (" +
                        std::to_string(ctx.info().subgroup_size) + ")");
}

ShadowsIsgPass::~ShadowsIsgPass() = default;

// The search lattice then the gather lattice, (x, y) on the unit disk: the concentric map
// evaluated once on the host rather than per tap. One table per pair of grids, kept for the
// pass's life (a sequence may still read an earlier light's).
const gpu::Buffer& ShadowsIsgPass::samples(int grid_search, int grid_gather) {
  auto& b = samples_[{grid_search, grid_gather}];
  if (!b) {
    std::vector<float> t;
    for (int grid : {grid_search, grid_gather})
      for (int k = 0; k < grid * grid; ++k) {
        const auto c = concentric(k, grid);
        t.push_back(float(c[0]));
        t.push_back(float(c[1]));
      }
    b = std::make_unique<gpu::Buffer>(ctx_, t.size() * sizeof(float), "shadows.isg.samples");
    b->upload(std::span<const float>(t));
  }
  return *b;
}

void ShadowsIsgPass::record(gpu::Sequence& seq, const ShadowSettings& s, const gpu::Buffer& shadow,
                            const gpu::Buffer& occluder, const gpu::Buffer& geo, bool has_position,
                            const gpu::Buffer& fg, gpu::Buffer& tiles, const gpu::Buffer& pack,
                            const gpu::Buffer& soft, uint32_t w, uint32_t h,
                            const std::string& label) {
  if (uint64_t(w) * h > SHADOWS_ISG_OWN_BORROW)  // the pixels' list keeps two flags in an index
    throw gpu::GpuError("shadows.isg: a window of " + std::to_string(uint64_t(w) * h) +
                        " pixels is over the pass's limit of 2^30");
  shaders::ShadowsIsgPush pc{};
  pc.width = w;
  pc.height = h;
  pc.grids = uint32_t(s.grid_search) | (uint32_t(s.grid_gather) << 16);
  pc.origin = s.window.packed_origin();
  pc.cx = float(s.window.cx(int(w)));
  pc.cy = float(s.window.cy(int(h)));
  pc.light_size = float(s.light_size);
  pc.inv_sigma = float(1.0 / s.sigma);
  pc.inv_scene_radius = float(1.0 / s.scene_radius);
  pc.max_radius = float(s.max_radius);
  pc.f_px = float(s.f_px);
  // The shaders work relative to the camera: the light's offset is formed in double.
  pc.light_x = float(s.light[0] - s.eye[0]);
  pc.light_y = float(s.light[1] - s.eye[1]);
  pc.light_z = float(s.light[2] - s.eye[2]);
  pc.light_nx = float(s.light_normal[0]);
  pc.light_ny = float(s.light_normal[1]);
  pc.light_nz = float(s.light_normal[2]);
  const auto& m = s.rot;
  set_rotation(pc, m);

  shaders::ShadowsIsgTilesPush tp{};
  tp.width = w;
  tp.height = h;
  tp.origin = pc.origin;
  tp.cx = pc.cx;
  tp.cy = pc.cy;
  tp.f_px = pc.f_px;
  set_split_eye(tp, s.eye);
  set_rotation(tp, m);

  const uint32_t tx = (w + SHADOWS_ISG_TILE - 1) / SHADOWS_ISG_TILE, nt = shadows_isg_tiles(w, h);
  shaders::ShadowsIsgListPush lp{};
  lp.width = w;
  lp.height = h;
  lp.flags = s.tile_skip ? SHADOWS_ISG_TILE_SKIP : 0u;
  lp.light_size = pc.light_size;
  lp.max_radius = pc.max_radius;
  lp.f_px = pc.f_px;
  lp.light_x = pc.light_x;
  lp.light_y = pc.light_y;
  lp.light_z = pc.light_z;
  lp.r20 = pc.r20;
  lp.r21 = pc.r21;
  lp.r22 = pc.r22;

  // The statistics are accumulated with atomics: start from zero, the dispatch of the listed
  // tiles from tiles_x by no rows by 1, that of the listed pixels from SHADOWS_ISG_OWN_ROW by no
  // rows by 1 (the quads' records and the pixels' list need no clearing: what is read was written
  // in the same run).
  // A tile starts from the whole frame's d_max (eq. 8), as the one-piece run would end with.
  std::vector<uint32_t> init(SHADOWS_ISG_AT_QUADS(nt), 0u);
  const float dm = float(s.d_max_floor);
  std::memcpy(&init[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_DMAX], &dm, sizeof dm);
  init[SHADOWS_ISG_AT_ARGS(nt)] = tx;
  init[SHADOWS_ISG_AT_ARGS(nt) + 2] = 1u;
  init[SHADOWS_ISG_AT_OWN_ARGS(nt)] = SHADOWS_ISG_OWN_ROW;
  init[SHADOWS_ISG_AT_OWN_ARGS(nt) + 2] = 1u;
  tiles.upload(std::span<const uint32_t>(init));
  seq.dispatch(tiles_kernel_.at({has_position ? SHADOWS_ISG_HAS_POSITION : 0u}),
               {gpu::Binding::floats(shadow), gpu::Binding::floats(occluder),
                gpu::Binding::floats(geo), gpu::Binding::floats(fg), gpu::Binding::of(tiles),
                gpu::Binding::of(pack)},
               tp, w, h, label + ".tiles");
  seq.dispatch(list_kernel_, {gpu::Binding::float4s(pack), gpu::Binding::of(tiles)}, lp, nt, 1,
               label + ".list");
  // Tiles left out of the list keep the hard shadow (the cheap path's result).
  seq.copy(shadow, soft, uint64_t(w) * h * sizeof(float), label + ".copy");
  // The settings that choose code paths, as specialization constant 0.
  const uint32_t flags = (s.rotate ? SHADOWS_ISG_ROTATE : 0u) |
                         (s.search_reach ? SHADOWS_ISG_SEARCH_REACH : 0u) |
                         (s.tile_skip ? SHADOWS_ISG_TILE_SKIP : 0u) |
                         (s.oriented ? SHADOWS_ISG_ORIENTED : 0u);
  const std::vector<gpu::Binding> bind = {
      gpu::Binding::float4s(pack), gpu::Binding::floats(occluder), gpu::Binding::of(tiles),
      gpu::Binding::of(soft),
      gpu::Binding::texels(samples(s.grid_search, s.grid_gather), VK_FORMAT_R32G32_SFLOAT),
      gpu::Binding::floats(shadow)};
  // Four dispatches, barriers in the first only (issue 18, as reflections.isg): the tiles' reach,
  // the quads' searches and wide gathers, the pixels, the pixels' own list.
  const VkDeviceSize tiles_args = uint64_t(SHADOWS_ISG_AT_ARGS(nt)) * 4;
  seq.dispatch_indirect(reach_kernel_.at({flags}), bind, pc, tiles, tiles_args, label + ".reach");
  seq.dispatch_indirect(quads_kernel_.at({flags, part_lanes_}), bind, pc, tiles, tiles_args,
                        label + ".quads");
  seq.dispatch_indirect(kernel_.at({flags}), bind, pc, tiles, tiles_args, label);
  seq.dispatch_indirect(own_kernel_.at({flags, part_lanes_}), bind, pc, tiles,
                        uint64_t(SHADOWS_ISG_AT_OWN_ARGS(nt)) * 4, label + ".own");
}

ShadowIsgStats ShadowsIsgPass::stats(const gpu::Buffer& tiles, uint32_t w, uint32_t h) {
  const uint32_t nt = shadows_isg_tiles(w, h);
  auto t = tiles.download_as<uint32_t>(SHADOWS_ISG_AT_QUADS(nt));  // not the records or the list
  ShadowIsgStats st;
  size_t k = 0;
  for (uint32_t j = 0; j < nt; ++j) k += t[2 * nt + j] != 0 ? 1 : 0;
  st.skipped_fraction = nt ? double(k) / nt : 0.0;
  st.dispatched_fraction = nt ? double(t[SHADOWS_ISG_AT_COUNT(nt)]) / nt : 0.0;
  float d;
  std::memcpy(&d, &t[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_DMAX], sizeof d);
  st.d_max = d;
  st.clamped_pixels = t[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_CLAMPED];
  st.full_pixels = t[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_FULL];
  st.searches = t[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_SEARCHES];
  st.borrowed = t[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_BORROWED];
  st.gathers = t[SHADOWS_ISG_AT_STATS(nt) + SHADOWS_ISG_STAT_GATHERS];
  return st;
}

}  // namespace isg::effects
