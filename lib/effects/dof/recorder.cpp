// Depth of field's recorder: its passes against the plan's resources, dof.coc, the statistics.
#include <map>

#include "effects/dof/dof.h"
#include "effects/dof/instance.h"
#include "effects/recorder.h"

namespace isg::effects {

namespace {

class DofRecorder final : public Recorder {
 public:
  explicit DofRecorder(gpu::Context& ctx) : ctx_(ctx) {}

  void record(gpu::Sequence& seq, const Pass& p, const Instance& i, const Bindings& b) override {
    const auto& inst = static_cast<const DofInstance&>(i);
    auto& dof = frame_[&inst];
    if (!dof) dof = std::make_unique<DofPass>(ctx_, inst.s);
    if (p.name == "dof.coc") {
      // dof.coc_source = channel: the CoC channel in the depth's place (dof_coc.comp).
      dof->record_coc(seq, b.at("composite"), b.beauty_has_alpha(),
                      b.at(inst.s.coc_source == 1 ? "coc" : "depth"), b.at("dof.coc"), b.at("dof.input"),
                      b.w, b.h);
    } else if (p.name == "dof.tiles") {
      dof->record_tiles(seq, b.at("dof.coc"), b.at("dof.tiles"), b.w, b.h);
    } else if (p.name == "dof.search") {
      dof->record_search(seq, b.at("dof.coc"), b.at("dof.tiles"), b.at("dof.radius"), b.w, b.h);
    } else if (p.name == "dof.gather") {
      dof->record_gather(seq, b.at("dof.input"), b.at("dof.coc"), b.at("dof.tiles"),
                         b.at("dof.radius"), b.at("composite"), b.w, b.h);
    } else {
      dof->record_layered(seq, b.at("dof.input"), b.at("dof.coc"), b.at("dof.tiles"),
                          b.at("composite"), b.w, b.h);
    }
  }

  void finish(const Instance& i, const Bindings& b, io::Image& img, RunOutputs& out) override {
    frame_.erase(&i);
    img.set("dof.coc", b.at("dof.coc").download_as<float>(b.pixels()), io::Storage::f32);
    Report r{"dof", i.key, {}, {}};
    r.sum("tiles", 1.0);  // fractions are averaged over the tiles of a large plate
    r.sum("cheap", DofPass::cheap_fraction(b.at("dof.tiles"), b.w, b.h));
    out.reports.push_back(r);
  }

 private:
  gpu::Context& ctx_;
  std::map<const Instance*, std::unique_ptr<DofPass>> frame_;  // this frame's settings
};

}  // namespace

std::unique_ptr<Recorder> dof_recorder(gpu::Context& ctx) { return std::make_unique<DofRecorder>(ctx); }

}  // namespace isg::effects
