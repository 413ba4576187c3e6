// The reflections passes on the GPU (reflections.h); their double reference is
// reflections_reference.cpp.
#include "effects/reflections/reflections.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "effects/sampling.h"
#include "effects/view.h"
#include "isg/shaders/reflections_cells.spv.h"
#include "isg/shaders/reflections_isg.spv.h"
#include "isg/shaders/reflections_isg_search.spv.h"
#include "isg/shaders/reflections_isg_wide.spv.h"
#include "isg/shaders/reflections_isg_own.spv.h"
#include "isg/shaders/reflections_list.spv.h"
#include "isg/shaders/reflections_pack.spv.h"
#include "reflections_isg_io.h"

namespace isg::effects {

namespace {
// The search lattice then the gather lattice as (x, y, |c|, |c|²): the concentric map evaluated
// once on the host rather than per tap.
std::vector<float> sample_table(int grid_search, int grid_gather) {
  std::vector<float> t;
  for (int grid : {grid_search, grid_gather}) {
    for (int k = 0; k < grid * grid; ++k) {
      const auto c = concentric(k, grid);
      const double r2 = c[0] * c[0] + c[1] * c[1];
      t.insert(t.end(), {float(c[0]), float(c[1]), float(std::sqrt(r2)), float(r2)});
    }
  }
  return t;
}
// The slots of reflections.isg's four dispatches (shaders/reflections_isg.h).
std::vector<gpu::Slot> isg_slots() {
  return {gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels,
          gpu::Slot::buffer, gpu::Slot::buffer, gpu::Slot::texels};
}
}  // namespace

ReflectionsPass::ReflectionsPass(gpu::Context& ctx, const ReflSettings& s)
    : s_(s),
      pack_(ctx, "reflections.pack", isg_spv_reflections_pack,
            {gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels,
             gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::buffer, gpu::Slot::buffer,
             gpu::Slot::buffer, gpu::Slot::buffer},
            sizeof(shaders::ReflIsgPush),
            REFL_PACK_LOCAL, 1),
      cells_(ctx, "reflections.pack.cells", isg_spv_reflections_cells,
             {gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::buffer}, sizeof(shaders::ReflIsgPush),
             REFL_PACK_LOCAL, 1),
      list_(ctx, "reflections.list", isg_spv_reflections_list,
            {gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::buffer}, sizeof(shaders::ReflIsgPush),
            REFL_LIST_LOCAL, 1),
      search_(ctx, "reflections.isg.search", isg_spv_reflections_isg_search, isg_slots(),
              sizeof(shaders::ReflIsgPush), REFL_QUADS, REFL_QUADS),
      wide_(ctx, "reflections.isg.wide", isg_spv_reflections_isg_wide, isg_slots(),
            sizeof(shaders::ReflIsgPush), REFL_BLOCKS, REFL_BLOCKS),
      kernel_(ctx, "reflections.isg", isg_spv_reflections_isg, isg_slots(),
              sizeof(shaders::ReflIsgPush), REFL_TILE, REFL_TILE),
      own_(ctx, "reflections.isg.own", isg_spv_reflections_isg_own, isg_slots(),
           sizeof(shaders::ReflIsgPush), REFL_OWN_LOCAL, 1) {
  const auto table = sample_table(s_.grid_search, s_.grid_gather);
  samples_ = std::make_unique<gpu::Buffer>(ctx, table.size() * sizeof(float), "refl.samples");
  samples_->upload(std::span<const float>(table));
}

ReflectionsPass::~ReflectionsPass() = default;

uint32_t ReflectionsPass::flags(bool has_position, bool has_rough) const {
  return (s_.search_reach ? REFL_SEARCH_REACH : 0u) | (s_.anisotropic ? REFL_ANISOTROPIC : 0u) |
         (s_.search_misses ? REFL_SEARCH_MISSES : 0u) | (s_.masking ? REFL_MASKING : 0u) |
         (has_position ? REFL_HAS_POSITION : 0u) | (has_rough ? REFL_HAS_ROUGHNESS : 0u);
}

shaders::ReflIsgPush ReflectionsPass::push(uint32_t w, uint32_t h) const {
  shaders::ReflIsgPush pc{};
  pc.width = w;
  pc.height = h;
  pc.grids = uint32_t(s_.grid_search) | (uint32_t(s_.grid_gather) << 16);
  pc.origin = s_.window.packed_origin();
  pc.cx = float(s_.window.cx(int(w)));
  pc.cy = float(s_.window.cy(int(h)));
  pc.roughness = float(s_.roughness);
  pc.tan_h_factor = float(ggx_cone_tan(1.0, s_.energy));
  pc.max_radius = float(s_.max_radius);
  pc.blur_radius = float(s_.blur_radius);
  pc.a = float(s_.a);
  pc.b = float(s_.b);
  pc.inv_sigma = float(1.0 / s_.sigma);
  pc.inv_scene_radius = float(1.0 / s_.scene_radius);
  pc.f_px = float(s_.f_px);
  set_split_eye(pc, s_.eye);
  const auto& m = s_.rot;
  set_rotation(pc, m);
  return pc;
}

void ReflectionsPass::record(gpu::Sequence& seq, const ReflBuffers& b, uint32_t w, uint32_t h,
                             const std::string& label) {
  record_pack(seq, b, w, h, "reflections.pack");
  record_gather(seq, b, w, h, label);
}

void ReflectionsPass::record_pack(gpu::Sequence& seq, const ReflBuffers& b, uint32_t w,
                                  uint32_t h, const std::string& label) {
  const auto pc = push(w, h);
  // Two storage ranges of each buffer: the pixels' texels, and the coarse cells' from
  // REFL_COARSE_BASE (each within the device's storage-buffer range).
  const VkDeviceSize pixels = VkDeviceSize(w) * h * 16, cells = VkDeviceSize(REFL_COARSE_BASE(w, h)) * 16;
  // Each pass is specialised on the flags it reads: reflections.pack on P.
  seq.dispatch(pack_.at({b.has_position ? REFL_HAS_POSITION : 0u}),
               {gpu::Binding::floats(b.refl), gpu::Binding::floats(b.dist),
                gpu::Binding::floats(b.weight), gpu::Binding::floats(b.normal),
                gpu::Binding::floats(b.geo), gpu::Binding::floats(b.fg),
                gpu::Binding::part(b.pack_geo, 0, pixels), gpu::Binding::part(b.pack_color, 0, pixels),
                gpu::Binding::part(b.pack_geo, cells, 0), gpu::Binding::part(b.pack_color, cells, 0)},
               pc, w, h, label);
  // Method isg's far gather taps read the cells' colours, prefiltered (reflections_cells.comp).
  if (s_.method == "isg")
    seq.dispatch(cells_.at({}),
                 {gpu::Binding::texels(b.pack_geo, VK_FORMAT_R32G32B32A32_UINT),
                  gpu::Binding::float4s(b.pack_color), gpu::Binding::part(b.pack_color, cells, 0)},
                 pc, (w + REFL_COARSE - 1) / REFL_COARSE, (h + REFL_COARSE - 1) / REFL_COARSE,
                 label + ".cells");
}

void ReflectionsPass::record_gather(gpu::Sequence& seq, const ReflBuffers& b, uint32_t w,
                                    uint32_t h, const std::string& label) {
  const bool has_rough = b.rough && !s_.roughness_override;
  const auto pc = push(w, h);
  // Without a roughness channel the slot is bound to refl.dist and never read.
  const gpu::Buffer& rb = has_rough ? *b.rough : b.dist;
  // reflections.list: the tiles with a glossy pixel, dispatched tiles_x wide by the rows the
  // list fills (the statistics of the tiles left out it writes itself); the others keep refl.
  const uint32_t tx = (w + REFL_TILE - 1) / REFL_TILE, nt = refl_tiles(w, h);
  // The statistics (zero: the dispatches add to them) and the list's header; the records are
  // written before they are read (the blocks of the tiles left out by reflections.list).
  std::vector<uint32_t> init(refl_tiles_words(w, h, false), 0u);
  init[REFL_AT_ARGS(nt)] = tx;
  init[REFL_AT_ARGS(nt) + 2] = 1u;
  init[REFL_AT_OWN_ARGS(nt)] = REFL_OWN_ROW;
  init[REFL_AT_OWN_ARGS(nt) + 2] = 1u;
  b.tiles.upload(std::span<const uint32_t>(init));
  const auto names = dispatches(s_, label);  // empty for method blur
  const bool isg = !names.empty();
  seq.dispatch(list_.at({has_rough ? REFL_HAS_ROUGHNESS : 0u, isg ? REFL_MODE_ISG : REFL_MODE_BLUR}),
               {gpu::Binding::float4s(b.pack_color), gpu::Binding::floats(rb),
                gpu::Binding::of(b.tiles)},
               pc, nt, 1, label + ".list");
  seq.copy(b.refl, b.glossy, 3 * uint64_t(w) * h * sizeof(float), label + ".copy");
  // Method isg: the quads' searches, then the blocks' wide gathers, then the pixels, over the
  // listed tiles (a lane per quad, block and pixel); then the pixels the pixel dispatch listed, a
  // lane each (shaders/reflections_isg.h). Method blur: the pixel dispatch alone.
  const std::vector<gpu::Binding> bind = {
      gpu::Binding::texels(b.pack_geo, VK_FORMAT_R32G32B32A32_UINT), gpu::Binding::float4s(b.pack_color),
      gpu::Binding::floats(rb), gpu::Binding::float4s(*samples_), gpu::Binding::of(b.glossy),
      gpu::Binding::of(b.tiles), gpu::Binding::texels(b.tiles, VK_FORMAT_R32G32B32A32_UINT)};
  const uint64_t args = uint64_t(REFL_AT_ARGS(nt)) * 4;
  const uint32_t fl = flags(b.has_position, has_rough);
  if (isg) {
    seq.dispatch_indirect(search_.at({fl}), bind, pc, b.tiles, args, names[0]);
    seq.dispatch_indirect(wide_.at({fl}), bind, pc, b.tiles, args, names[1]);
  }
  seq.dispatch_indirect(kernel_.at({fl, isg ? REFL_MODE_ISG : REFL_MODE_BLUR}), bind, pc, b.tiles,
                        args, label);
  if (isg)
    seq.dispatch_indirect(own_.at({fl}), bind, pc, b.tiles, uint64_t(REFL_AT_OWN_ARGS(nt)) * 4, names[2]);
}

std::vector<std::string> ReflectionsPass::dispatches(const ReflSettings& s, const std::string& label) {
  if (s.method != "isg") return {};
  return {label + ".search", label + ".wide", label + ".own"};
}

ReflTileStats ReflectionsPass::stats(const gpu::Buffer& tiles, uint32_t w, uint32_t h) {
  const uint32_t nt = refl_tiles(w, h);
  auto t = tiles.download_as<uint32_t>(2 * size_t(nt));
  ReflTileStats st;
  size_t k = 0;
  for (uint32_t j = nt; j < 2 * nt; ++j) st.gathers += t[j];
  t.resize(nt);
  for (uint32_t v : t) {
    k += v == REFL_TILE_CHEAP ? 1 : 0;
    const uint64_t c = v == REFL_TILE_CHEAP ? 0 : v;
    st.glossy_pixels += c % REFL_STATS_SEARCHES;
    st.searches += c / REFL_STATS_SEARCHES;
  }
  st.skipped_fraction = nt ? double(k) / nt : 0.0;
  return st;
}

}  // namespace isg::effects
