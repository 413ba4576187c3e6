// VSSM: not built yet.
#include <stdexcept>

#include "effects/shadows/method.h"

namespace isg::effects {

std::vector<float> vssm_reference(const ShadowmapInputs&, const ShadowmapData&,
                                  const ShadowmapSettings&, ShadowmapStats*) {
  throw std::logic_error("shadow-map method vssm not built");
}

namespace detail {
std::unique_ptr<ShadowmapMethod> make_vssm(gpu::Context&, const ShadowmapSettings&,
                                           const ShadowmapData&, uint32_t, uint32_t, bool) {
  throw std::logic_error("shadow-map method vssm not built");
}
}  // namespace detail

}  // namespace isg::effects
