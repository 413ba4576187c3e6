// Glossy reflections (paper §3.2, eq. 4, 10-14): refl.glossy from the renderer's sharp
// reflection refl, its distance refl.dist, P (or Z and the camera), N and roughness.
//   isg:  parameter search over refl.dist within R_p (eq. 4, 10-12), then the gather over refl
//         within R_s (eq. 13) / R_g (eq. 14), the GGX lobe projected into screen space as spatial
//         weight, elongated along the plane of incidence; four dispatches (reflections.isg.search,
//         .wide, reflections.isg, .own: shaders/reflections_isg.h).
//   blur: the naive alternative, a constant-width disk blur of refl (no contact hardening).
// The composite term refl.weight·(refl.glossy − refl) is the shared composite_term pass.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "effects/reflections/settings.h"
#include "gpu/gpu.h"
#include "reflections_isg_io.h"

namespace isg::effects {

// The inputs, as planes of w·h floats (position: 3 planes, or depth: 1 plane; roughness may be
// empty: the preset value; fg: 1 foreground, 0 background).
struct ReflInputs {
  int w = 0, h = 0;
  std::vector<float> refl, dist, weight, normal, position, depth, roughness, fg;
};

struct ReflTileStats {
  double skipped_fraction = 0;  // tiles with nothing glossy
  uint64_t glossy_pixels = 0;   // glossy pixels (in the tiles that were not cheap)
  uint64_t searches = 0;        // parameter searches run (one per quad, more at edges)
  uint64_t gathers = 0;         // gathers run (one per 4×4 block for wide lobes, more at edges)
};

// C++ double-precision reference of pass reflections.isg; returns refl.glossy (3 planes) and,
// in `tiles`, 1 per 16×16 tile that took the cheap path (nothing glossy), else 0; in `stats`,
// what the GPU's statistics count (the searches and gathers of method isg).
std::vector<float> reflections_reference(const ReflInputs& in, const ReflSettings& s,
                                         std::vector<float>* tiles = nullptr,
                                         ReflTileStats* stats = nullptr);

// The buffers pass reflections.isg binds. geo: P (has_position) or Z; rough may be null
// (preset roughness); pack_geo and pack_color (4 planes each) are reflections.pack's products.
struct ReflBuffers {
  const gpu::Buffer &refl, &dist, &weight, &normal, &geo;
  bool has_position;
  const gpu::Buffer* rough;
  const gpu::Buffer &fg, &pack_geo, &pack_color, &glossy;
  gpu::Buffer& tiles;  // set up by the pass (its list)
};


// reflections.pack (the taps' data in two 16-byte texels a pixel) then reflections.isg.
class ReflectionsPass {
 public:
  ReflectionsPass(gpu::Context& ctx, const ReflSettings& s);
  ~ReflectionsPass();
  void record(gpu::Sequence& seq, const ReflBuffers& b, uint32_t w, uint32_t h,
              const std::string& label);
  // The two passes apart (the plan lists both): reflections.pack, then the search and gather.
  void record_pack(gpu::Sequence& seq, const ReflBuffers& b, uint32_t w, uint32_t h,
                   const std::string& label);
  void record_gather(gpu::Sequence& seq, const ReflBuffers& b, uint32_t w, uint32_t h,
                     const std::string& label);
  // The dispatches record_gather adds around the one named `label` (method isg's search, wide
  // gathers and the pixels that search or gather for themselves; none for method blur).
  static std::vector<std::string> dispatches(const ReflSettings& s, const std::string& label);
  // After submit: the tiles that took the cheap path and the pixels that were gathered.
  static ReflTileStats stats(const gpu::Buffer& tiles, uint32_t w, uint32_t h);

 private:
  shaders::ReflIsgPush push(uint32_t w, uint32_t h) const;
  uint32_t flags(bool has_position, bool has_rough) const;  // specialization constant 0
  ReflSettings s_;
  gpu::KernelVariants pack_, cells_, list_, search_, wide_, kernel_, own_;
  std::unique_ptr<gpu::Buffer> samples_;  // the lattice table (sample_table)
};

}  // namespace isg::effects
