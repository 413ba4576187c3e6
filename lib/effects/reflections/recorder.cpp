// The reflections' recorder: reflections.pack and reflections.isg against the plan's
// resources, refl.glossy, and the statistics.
#include <map>

#include "effects/recorder.h"
#include "effects/reflections/instance.h"
#include "effects/reflections/reflections.h"

namespace isg::effects {

namespace {

class ReflRecorder final : public Recorder {
 public:
  explicit ReflRecorder(gpu::Context& ctx) : ctx_(ctx) {}

  void record(gpu::Sequence& seq, const Pass& p, const Instance& i, const Bindings& b) override {
    const auto& inst = static_cast<const ReflInstance&>(i);
    auto& f = frame_[&inst];
    if (!f.pass) f.pass = std::make_unique<ReflectionsPass>(ctx_, inst.s);
    const bool has_p = b.find("position") != nullptr;
    const ReflBuffers rb{b.at("refl"), b.at("refl.dist"), b.at("refl.weight"), b.at("normal"),
                         b.at(has_p ? "position" : "depth"), has_p, b.find("roughness"),
                         b.at("fg"), b.at("refl.pack.geo"), b.at("refl.pack.color"),
                         b.at("refl.glossy"), b.at("refl.tiles")};
    if (p.name == "reflections.pack") {
      f.pass->record_pack(seq, rb, b.w, b.h, p.label);
    } else {
      f.pass->record_gather(seq, rb, b.w, b.h, p.label);
      f.label = p.label;
    }
  }

  void finish(const Instance& i, const Bindings& b, io::Image& img, RunOutputs& out) override {
    const auto& inst = static_cast<const ReflInstance&>(i);
    const size_t n = b.pixels();
    const char* rgb[3] = {"refl.glossy.R", "refl.glossy.G", "refl.glossy.B"};
    for (size_t c = 0; c < 3; ++c) {
      std::vector<float> v(n);
      b.at("refl.glossy").download(v.data(), n * sizeof(float), c * n * sizeof(float));
      img.set(rgb[c], std::move(v), io::Storage::f32);
    }
    const auto rt = ReflectionsPass::stats(b.at("refl.tiles"), b.w, b.h);
    Report r{"reflections", inst.key, {}, {}};
    r.sum("tiles", 1.0);  // fractions are averaged over the tiles of a large plate
    r.sum("skipped", rt.skipped_fraction);
    out.reports.push_back(r);
    const auto& s = inst.s;
    const std::string& label = frame_[&inst].label;
    out.gathers.push_back({label, rt.glossy_pixels,
                           rt.searches * uint64_t(s.grid_search * s.grid_search) +
                               rt.gathers * uint64_t(s.grid_gather * s.grid_gather),
                           1, ReflectionsPass::dispatches(s, label)});
    frame_.erase(&inst);
  }

 private:
  struct Frame {
    std::unique_ptr<ReflectionsPass> pass;  // this frame's settings (window) and sample table
    std::string label;
  };
  gpu::Context& ctx_;
  std::map<const Instance*, Frame> frame_;
};

}  // namespace

std::unique_ptr<Recorder> reflections_recorder(gpu::Context& ctx) {
  return std::make_unique<ReflRecorder>(ctx);
}

}  // namespace isg::effects
