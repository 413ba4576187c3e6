#include "effects/shadows/hsm.h"

#include <algorithm>
#include <cmath>

#include "isg/shaders/shadowmap_hsm.spv.h"

namespace isg::effects {

HsmLayout hsm_layout(int w, int h, double far_z) {
  HsmLayout l;
  l.far_z = double(float(far_z));
  for (;;) {
    l.off.push_back(l.texels);
    l.w.push_back(w);
    l.h.push_back(h);
    l.texels += size_t(w) * size_t(h);
    if ((w == 1 && h == 1) || int(l.w.size()) == HSM_MAX_LEVELS) break;
    w = (w + 1) / 2;
    h = (h + 1) / 2;
  }
  return l;
}

shaders::HsmLevels HsmLayout::gpu() const {
  shaders::HsmLevels g{};
  g.levels = uint32_t(w.size());
  g.far_z = float(far_z);
  // On the GPU level 0 is the map itself (not stored): levels 1... from offset 0.
  const size_t base = off.size() > 1 ? off[1] : 0;
  for (size_t L = 0; L < w.size(); ++L) {
    g.off[L] = L == 0 ? 0u : uint32_t(off[L] - base);
    g.w[L] = uint32_t(w[L]);
    g.h[L] = uint32_t(h[L]);
  }
  return g;
}

HsmRef::HsmRef(const ShadowmapData& map, const HsmLayout& layout) : l_(layout) {
  t_.resize(l_.texels);
  for (size_t i = 0; i < map.z.size(); ++i) {
    const float z = std::min(map.z[i], float(l_.far_z));
    t_[i] = {z, z};
  }
  for (size_t L = 1; L < l_.w.size(); ++L)
    for (int y = 0; y < l_.h[L]; ++y)
      for (int x = 0; x < l_.w[L]; ++x) {
        std::array<float, 2> r{1e30f, -1e30f};
        for (int yy = 2 * y; yy < std::min(2 * y + 2, l_.h[L - 1]); ++yy)
          for (int xx = 2 * x; xx < std::min(2 * x + 2, l_.w[L - 1]); ++xx) {
            const auto& c = t_[l_.off[L - 1] + size_t(yy) * l_.w[L - 1] + xx];
            r = {std::min(r[0], c[0]), std::max(r[1], c[1])};
          }
        t_[l_.off[L] + size_t(y) * l_.w[L] + x] = r;
      }
}

std::array<double, 2> HsmRef::range(std::array<double, 2> flo, std::array<double, 2> fhi) const {
  const int lx = int(std::floor(flo[0])), ly = int(std::floor(flo[1]));
  const int hx = std::max(int(std::ceil(fhi[0])), lx + 1), hy = std::max(int(std::ceil(fhi[1])), ly + 1);
  const int size = std::max(hx - lx, hy - ly);
  size_t L = 0;
  while ((1 << L) < size && L + 1 < l_.w.size()) ++L;
  std::array<double, 2> r{1e30, -1e30};
  for (int y = ly >> L; y <= (hy - 1) >> L; ++y)
    for (int x = lx >> L; x <= (hx - 1) >> L; ++x) {
      const auto& c = t_[l_.off[L] + size_t(y) * l_.w[L] + x];
      r = {std::min(r[0], double(c[0])), std::max(r[1], double(c[1]))};
    }
  return r;
}

HsmPass::HsmPass(gpu::Context& ctx)
    : k_(ctx, "shadows.hsm", isg_spv_shadowmap_hsm, {gpu::Slot::buffer, gpu::Slot::buffer},
         sizeof(shaders::HsmPush), HSM_LOCAL, HSM_LOCAL) {}

void HsmPass::record(gpu::Sequence& seq, const gpu::Buffer& map, const gpu::Buffer& hsm,
                     const HsmLayout& l, const std::string& label) {
  // Level by level; level 0 is the map itself (clamped to far_z where read), level 1 is built
  // from it.
  const size_t base = l.off.size() > 1 ? l.off[1] : 0;
  for (size_t L = 1; L < l.w.size(); ++L) {
    shaders::HsmPush hp{};
    hp.dst_off = uint32_t(l.off[L] - base);
    hp.dst_w = uint32_t(l.w[L]);
    hp.dst_h = uint32_t(l.h[L]);
    hp.from_map = L == 1 ? 1u : 0u;
    hp.far_z = float(l.far_z);
    hp.src_off = L == 1 ? 0u : uint32_t(l.off[L - 1] - base);
    hp.src_w = uint32_t(l.w[L - 1]);
    hp.src_h = uint32_t(l.h[L - 1]);
    seq.dispatch(k_, {gpu::Binding::of(map), gpu::Binding::of(hsm)}, hp, hp.dst_w, hp.dst_h,
                 label + ".hsm" + std::to_string(L));
  }
}

}  // namespace isg::effects
