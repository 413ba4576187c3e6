#include "effects/recorder.h"

#include <stdexcept>

#include "effects/registry.h"

namespace isg::effects {

gpu::Buffer& Bindings::at(const std::string& name) const {
  auto it = buffers_.find(name);
  if (it == buffers_.end()) throw std::logic_error("pass reads resource " + name + ", which the plan does not declare");
  return it->second;
}

gpu::Buffer* Bindings::find(const std::string& name) const {
  auto it = buffers_.find(name);
  return it == buffers_.end() ? nullptr : &it->second;
}

bool Bindings::beauty_has_alpha() const {
  const io::RoleBinding* b = roles_.get("beauty");
  return b && b->components() == 4;
}

#define ISG_DECLARE_RECORDER(name) std::unique_ptr<Recorder> name##_recorder(gpu::Context& ctx);
ISG_EFFECTS(ISG_DECLARE_RECORDER)
#undef ISG_DECLARE_RECORDER

std::unique_ptr<Recorder> make_recorder(const std::string& effect, gpu::Context& ctx) {
#define ISG_MAKE_RECORDER(name) \
  if (effect == #name) return name##_recorder(ctx);
  ISG_EFFECTS(ISG_MAKE_RECORDER)
#undef ISG_MAKE_RECORDER
  throw std::logic_error("no recorder for effect " + effect + " (lib/effects/registry.h)");
}

}  // namespace isg::effects
