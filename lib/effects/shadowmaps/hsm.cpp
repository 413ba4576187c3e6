#include "effects/shadowmaps/hsm.h"

#include <algorithm>
#include <cmath>

#include "isg/shaders/shadowmap_hsm.spv.h"
#include "shadowmap_io.h"

namespace isg::effects::detail {

HsmLevels hsm_levels(const ShadowmapData& map) {
  HsmLevels v;
  double far = 0;
  for (float z : map.z)
    if (z > 0.0f && z < ISG_BACKGROUND_DEPTH) far = std::max(far, double(z));
  if (far <= 0) far = 1.0;
  v.far_z = double(float(far));
  int w = map.width, h = map.height;
  for (;;) {
    v.off.push_back(v.texels);
    v.w.push_back(w);
    v.h.push_back(h);
    v.texels += size_t(w) * size_t(h);
    if ((w == 1 && h == 1) || int(v.w.size()) == HSM_MAX_LEVELS) break;
    w = (w + 1) / 2;
    h = (h + 1) / 2;
  }
  return v;
}

shaders::HsmLevelsGpu hsm_levels_gpu(const HsmLevels& v) {
  shaders::HsmLevelsGpu g{};
  g.levels = uint32_t(v.w.size());
  g.far_z = float(v.far_z);
  const size_t base = v.off.size() > 1 ? v.off[1] : 0;
  for (size_t L = 0; L < v.w.size(); ++L) {
    g.off[L] = L == 0 ? 0u : uint32_t(v.off[L] - base);
    g.w[L] = uint32_t(v.w[L]);
    g.h[L] = uint32_t(v.h[L]);
  }
  return g;
}

HsmRef::HsmRef(const ShadowmapData& map, const HsmLevels& v) : v_(v), t_(v.texels) {
  for (size_t i = 0; i < map.z.size(); ++i) {
    const float z = std::min(map.z[i], float(v.far_z));
    t_[i] = {z, z};
  }
  for (size_t L = 1; L < v.w.size(); ++L)
    for (int y = 0; y < v.h[L]; ++y)
      for (int x = 0; x < v.w[L]; ++x) {
        std::array<float, 2> r{1e30f, -1e30f};
        for (int yy = 2 * y; yy < std::min(2 * y + 2, v.h[L - 1]); ++yy)
          for (int xx = 2 * x; xx < std::min(2 * x + 2, v.w[L - 1]); ++xx) {
            const auto& c = t_[v.off[L - 1] + size_t(yy) * v.w[L - 1] + xx];
            r = {std::min(r[0], c[0]), std::max(r[1], c[1])};
          }
        t_[v.off[L] + size_t(y) * v.w[L] + x] = r;
      }
}

std::array<double, 2> HsmRef::range(std::array<double, 2> flo, std::array<double, 2> fhi) const {
  const int lx = int(std::floor(flo[0])), ly = int(std::floor(flo[1]));
  const int hx = std::max(int(std::ceil(fhi[0])), lx + 1), hy = std::max(int(std::ceil(fhi[1])), ly + 1);
  const int size = std::max(hx - lx, hy - ly);
  size_t L = 0;
  while ((1 << L) < size && L + 1 < v_.w.size()) ++L;
  std::array<double, 2> r{1e30, -1e30};
  for (int y = ly >> L; y <= (hy - 1) >> L; ++y)
    for (int x = lx >> L; x <= (hx - 1) >> L; ++x) {
      const auto& c = t_[v_.off[L] + size_t(y) * v_.w[L] + x];
      r = {std::min(r[0], double(c[0])), std::max(r[1], double(c[1]))};
    }
  return r;
}

HsmPass::HsmPass(gpu::Context& ctx, const HsmLevels& v)
    : v_(v),
      k_(ctx, "shadows.hsm", isg_spv_shadowmap_hsm, {gpu::Slot::buffer, gpu::Slot::buffer},
         sizeof(shaders::HsmPush), HSM_LOCAL, HSM_LOCAL) {
  const size_t base = v_.off.size() > 1 ? v_.off[1] : 0;
  hsm_ = gpu::Buffer(ctx, std::max<size_t>(v_.texels - base, 1) * 8, "shadowmap.hsm");
}

void HsmPass::record(gpu::Sequence& seq, const gpu::Buffer& map, const std::string& label) {
  const size_t base = v_.off.size() > 1 ? v_.off[1] : 0;
  for (size_t L = 1; L < v_.w.size(); ++L) {
    shaders::HsmPush hp{};
    hp.dst_off = uint32_t(v_.off[L] - base);
    hp.dst_w = uint32_t(v_.w[L]);
    hp.dst_h = uint32_t(v_.h[L]);
    hp.from_map = L == 1 ? 1u : 0u;
    hp.far_z = float(v_.far_z);
    hp.src_off = L == 1 ? 0u : uint32_t(v_.off[L - 1] - base);
    hp.src_w = uint32_t(v_.w[L - 1]);
    hp.src_h = uint32_t(v_.h[L - 1]);
    seq.dispatch(k_, {gpu::Binding::of(map), gpu::Binding::of(hsm_)}, hp, hp.dst_w, hp.dst_h,
                 label + ".hsm" + std::to_string(L));
  }
}

}  // namespace isg::effects::detail
