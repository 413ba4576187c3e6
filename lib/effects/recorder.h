// The GPU side of the effect interface: each effect's Recorder records the passes its planner
// declared, against the plan's named resources. A recorder lives for the job (lib/run/run.h's
// Runner): its kernels are built once per process, and each frame or tile only re-records.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "effects/effect.h"
#include "gpu/gpu.h"
#include "io/image.h"

namespace isg::effects {

// The plan's resources on the device, by name, for one frame or tile.
class Bindings {
 public:
  Bindings(std::map<std::string, gpu::Buffer>& buffers, const io::Roles& roles, uint32_t width,
           uint32_t height)
      : buffers_(buffers), roles_(roles), w(width), h(height) {}
  // Throws std::logic_error naming the resource the plan did not declare.
  gpu::Buffer& at(const std::string& name) const;
  gpu::Buffer* find(const std::string& name) const;
  const io::Roles& roles() const { return roles_; }
  bool beauty_has_alpha() const;
  size_t pixels() const { return size_t(w) * size_t(h); }

 private:
  std::map<std::string, gpu::Buffer>& buffers_;
  const io::Roles& roles_;

 public:
  const uint32_t w, h;
};

// What a run gathers besides the image: statistics, gather loads, warnings.
struct RunOutputs {
  std::vector<Report> reports;
  std::vector<GatherLoad> gathers;
};

class Recorder {
 public:
  virtual ~Recorder() = default;
  // Records `pass` (one of this effect's) of `inst` into the sequence.
  virtual void record(gpu::Sequence& seq, const Pass& pass, const Instance& inst,
                      const Bindings& b) = 0;
  // After the sequence ran: the instance's output channels into `img`, and its statistics.
  virtual void finish(const Instance& inst, const Bindings& b, io::Image& img,
                      RunOutputs& out) = 0;
};

// The recorder of the named effect (lib/effects/registry.h), for a context.
std::unique_ptr<Recorder> make_recorder(const std::string& effect, gpu::Context& ctx);

}  // namespace isg::effects
