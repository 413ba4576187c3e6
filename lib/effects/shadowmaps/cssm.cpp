// CSSM on the GPU (thesis ch. 5): basis images, prefiltering and shading; the conventions and
// the set-up they share with the double reference (cssm_reference.cpp) are cssm_setup.h's.
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "effects/shadowmaps/hsm.h"
#include "effects/shadowmaps/method.h"
#include "effects/shadowmaps/sat.h"
#include "isg/shaders/shadowmap_cssm.spv.h"
#include "isg/shaders/shadowmap_cssm_basis.spv.h"
#include "isg/shaders/shadowmap_cssm_mip.spv.h"
#include "shadowmap_cssm_io.h"

#include "effects/shadowmaps/cssm_setup.h"

namespace isg::effects {

using detail::Plane;
using detail::V2;
using detail::V3;

using namespace detail::cssm;

namespace detail {
namespace {
// The shading pass's slots: `tab` as a texel view (its whole, beyond a storage buffer's range).
std::vector<gpu::Slot> cssm_slots() {
  std::vector<gpu::Slot> s(12, gpu::Slot::buffer);
  s[8] = gpu::Slot::texels;
  return s;
}

// CSSM on the GPU: basis images (one dispatch for all 4M + 1), prefiltering (the 32-bit SAT
// scans, or one dispatch per mip level), then the shading kernel.
class Cssm final : public ShadowmapMethod {
 public:
  Cssm(gpu::Context& ctx, const ShadowmapSettings& s, const ShadowmapData& map, uint32_t w,
       uint32_t h, bool has_position)
      : basis_(ctx, "shadows.cssm.basis", isg_spv_shadowmap_cssm_basis,
               std::vector<gpu::Slot>(5, gpu::Slot::buffer), sizeof(shaders::CssmPush),
               CSSM_LOCAL, CSSM_LOCAL, {0u, s.cssm_filter == "mipmap" ? 1u : 0u}),
        shade_(ctx, "shadows.cssm", isg_spv_shadowmap_cssm,
               cssm_slots(), sizeof(shaders::ShadowmapPush),
               SHADOWMAP_LOCAL, SHADOWMAP_LOCAL, {0u, s.cssm_filter == "mipmap" ? 1u : 0u}),
        // The pixels the search finds blockers for (shadowmap_common.h's sm_pixel_of).
        own_k_(ctx, "shadows.cssm.own", isg_spv_shadowmap_cssm,
               cssm_slots(), sizeof(shaders::ShadowmapPush),
               SHADOWMAP_LOCAL, SHADOWMAP_LOCAL, {1u, s.cssm_filter == "mipmap" ? 1u : 0u}),
        own_(ctx, w, h),
        hsm_levels_(detail::hsm_levels(map)),
        hsm_(ctx, hsm_levels_),
        w_(w),
        h_(h),
        map_w_(uint32_t(map.width)),
        map_h_(uint32_t(map.height)) {
    Setup u = make_setup(map, s);
    const uint32_t groups = 2u * uint32_t((u.M + 1) / 2);
    // The basis's texels: `groups` uvec4 each in one storage buffer; where the device's range
    // cannot hold them, the basis is block-averaged further (as shadows.cssm_max_basis does).
    auto texels_of = [](const Setup& v) {
      const Levels L = mip_levels(v.bw, v.bh, v.sat);
      uint64_t n = 0;
      for (size_t l = 0; l < L.w.size(); ++l) n += uint64_t(L.w[l]) * uint64_t(L.h[l]);
      return n;
    };
    // A half of `tab` within a storage buffer's range, the whole within a texel view's
    // (shadowmap_cssm_io.h).
    auto fits = [&](const Setup& v) {
      const uint64_t half = texels_of(v) * (groups / 2u);
      return half * 16u <= ctx.info().max_storage_buffer_range &&
             2u * half <= ctx.info().max_texel_buffer_elements;
    };
    while (!fits(u) && u.bw * u.bh > 1) {
      ++u.shift;
      u.bw = (map.width + (1 << u.shift) - 1) >> u.shift;
      u.bh = (map.height + (1 << u.shift) - 1) >> u.shift;
    }
    const Levels L = mip_levels(u.bw, u.bh, u.sat);
    if (L.w.size() > CSSM_MAX_LEVELS) throw std::invalid_argument("cssm: shadow map too large");
    shaders::CssmParams c{};
    c.order = uint32_t(u.M);
    if (u.M > CSSM_MAX_ORDER) throw std::invalid_argument("cssm: order above 16");
    c.prefilter = u.sat ? CSSM_FILTER_SAT : CSSM_FILTER_MIPMAP;
    c.groups = groups;
    c.basis_shift = uint32_t(u.shift);
    c.max_split = uint32_t(u.split);
    c.narrow = uint32_t(u.narrow);
    c.levels = uint32_t(L.w.size());
    c.zmin = float(u.zmin);
    c.zrange = float(u.zrange);
    c.s_z = float(u.s_z);
    c.x0 = float(u.x0);
    c.alpha = float(u.alpha);
    c.sharpen_a = float(s.cssm_a);
    c.sharpen_b = float(s.cssm_b);
    c.sat_scale = float(sat_scale(u, s));
    c.hsm = hsm_levels_gpu(hsm_levels_);
    uint64_t texels = 0;
    for (size_t l = 0; l < L.w.size(); ++l) {
      c.level_w[l] = uint32_t(L.w[l]);
      c.level_h[l] = uint32_t(L.h[l]);
      c.level_off[l] = uint32_t(texels);
      texels += uint64_t(L.w[l]) * uint64_t(L.h[l]);
    }
    // The CSM-Z half from a 256-byte boundary (any device's storage-buffer offset alignment).
    c.half_texels = uint32_t((texels * (groups / 2u) + 15u) / 16u * 16u);
    half_bytes_ = uint64_t(c.half_texels) * 16u;
    cparams_ = c;
    const shaders::ShadowmapParams p = shadowmap_params(s, map, w, h, has_position, 0u);
    params_ = gpu::Buffer(ctx, sizeof(p), "shadowmap.params");
    params_.upload(&p, sizeof(p));
    cssm_params_ = gpu::Buffer(ctx, sizeof(c), "shadowmap.cssm.params");
    cssm_params_.upload(&c, sizeof(c));
    tab_ = gpu::Buffer(ctx, 2u * half_bytes_, u.sat ? "shadowmap.cssm.sat" : "shadowmap.cssm.mip");
    tz_ = gpu::Buffer(ctx, texels * 4u, u.sat ? "shadowmap.cssm.sat_z" : "shadowmap.cssm.mip_z");
    if (u.sat)
      scan_.emplace(ctx);
    else
      mip_.emplace(ctx, "shadows.cssm.mip", isg_spv_shadowmap_cssm_mip,
                   std::vector<gpu::Slot>(4, gpu::Slot::buffer), sizeof(shaders::CssmPush),
                   CSSM_LOCAL, CSSM_LOCAL);
    stats_ = zeroed_stats(ctx);
  }

  void record(gpu::Sequence& seq, const gpu::Buffer& geo, const gpu::Buffer& fg,
              const gpu::Buffer& hard, const gpu::Buffer& map, const gpu::Buffer& soft,
              const std::string& label) override {
    const auto& c = cparams_;
    hsm_.record(seq, map, label);
    shaders::CssmPush bp{map_w_, map_h_, 0u, 0u};
    const std::vector<gpu::Binding> bb{gpu::Binding::of(cssm_params_), gpu::Binding::of(map),
                                       tab_half(0), tab_half(1), gpu::Binding::of(tz_)};
    if (scan_) {
      // A lane per basis row and part (shadowmap_cssm_basis.comp), the rows summed; then the
      // columns.
      const uint32_t lines = c.level_h[0] * (c.groups / 2u + 1u);
      seq.dispatch(basis_, bb, bp, CSSM_BASIS_ROW, (lines + CSSM_BASIS_ROW - 1) / CSSM_BASIS_ROW,
                   label + ".basis");
      scan_->record(seq, tab_half(0), c.level_w[0], c.level_h[0], 2u * c.groups, label + ".sat", false);
      scan_->record(seq, tab_half(1), c.level_w[0], c.level_h[0], 2u * c.groups, label + ".sat", false);
      scan_->record(seq, gpu::Binding::of(tz_), c.level_w[0], c.level_h[0], 1u, label + ".sat_z", false);
    } else {
      seq.dispatch(basis_, bb, bp, c.level_w[0], c.level_h[0], label + ".basis");
      for (uint32_t l = 1; l < c.levels; ++l) {
        shaders::CssmPush mp{c.level_w[l], c.level_h[l], l, 0u};
        seq.dispatch(*mip_,
                     {gpu::Binding::of(cssm_params_), tab_half(0), tab_half(1), gpu::Binding::of(tz_)},
                     mp, c.level_w[l] * (c.groups + 1u), c.level_h[l], label + ".mip");
      }
    }
    shaders::ShadowmapPush pc{w_, h_};
    const std::vector<gpu::Binding> b{
        gpu::Binding::of(params_), gpu::Binding::of(cssm_params_), gpu::Binding::of(geo),
        gpu::Binding::of(fg), gpu::Binding::of(hard), gpu::Binding::of(map),
        gpu::Binding::of(soft), gpu::Binding::of(stats_),
        gpu::Binding::texels(tab_, VK_FORMAT_R32G32B32A32_UINT),
        gpu::Binding::of(tz_), gpu::Binding::of(hsm_.buffer()), gpu::Binding::of(own_.buffer())};
    own_.reset(seq, label + ".list");
    seq.dispatch(shade_, b, pc, w_, h_, label);
    own_.dispatch(seq, own_k_, b, pc, label + ".own");
  }
  ShadowmapStats stats() const override { return read_stats(stats_); }
  // Half k of `tab` (0: CSM, 1: CSM-Z) as a storage buffer of its own.
  gpu::Binding tab_half(int k) const { return gpu::Binding::part(tab_, k * half_bytes_, half_bytes_); }
  uint64_t gpu_bytes() const override {
    return params_.size() + cssm_params_.size() + stats_.size() + tab_.size() + tz_.size() +
           hsm_.buffer().size() + own_.buffer().size();
  }

 private:
  gpu::Kernel basis_, shade_, own_k_;
  OwnList own_;
  HsmLevels hsm_levels_;
  HsmPass hsm_;
  std::optional<gpu::Kernel> mip_;  // the mipmap filter's
  std::optional<SatScan32> scan_;   // the SAT filter's
  gpu::Buffer params_, cssm_params_, stats_, tab_, tz_;
  shaders::CssmParams cparams_{};
  uint64_t half_bytes_ = 0;
  uint32_t w_, h_, map_w_, map_h_;
};
}  // namespace

std::unique_ptr<ShadowmapMethod> make_cssm(gpu::Context& ctx, const ShadowmapSettings& s,
                                           const ShadowmapData& map, uint32_t w, uint32_t h,
                                           bool has_position) {
  return std::make_unique<Cssm>(ctx, s, map, w, h, has_position);
}
}  // namespace detail

}  // namespace isg::effects
