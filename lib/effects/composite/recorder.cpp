// The composite's recorder: pass foreground, every effect's composite_term, and the composite
// written back as R G B A (an input beauty named R G B A is kept as input.R/G/B/A).
#include "effects/composite/composite.h"
#include "effects/recorder.h"

namespace isg::effects {

namespace {
class CompositeRecorder final : public Recorder {
 public:
  explicit CompositeRecorder(gpu::Context& ctx) : foreground_(ctx), term_(ctx) {}
  void record(gpu::Sequence& seq, const Pass& p, const Instance&, const Bindings& b) override {
    if (p.name == "foreground") {
      foreground_.record(seq, b.at("composite"), b.beauty_has_alpha(), b.find("depth"), b.at("fg"),
                         b.w, b.h);
    } else {
      // reads = {composite, W, X, Y, fg}
      const auto& X = b.at(p.reads.at(2));
      term_.record(seq, b.at("composite"), b.at(p.reads.at(1)), X, b.at(p.reads.at(3)),
                   uint32_t(X.size() / (b.pixels() * sizeof(float))), b.at("fg"), b.w, b.h,
                   p.label);
    }
  }
  void finish(const Instance&, const Bindings& b, io::Image& img, RunOutputs&) override {
    const size_t n = b.pixels();
    const io::RoleBinding* beauty = b.roles().get("beauty");
    const bool beauty_is_rgba = beauty->how == "contract name";
    const bool has_alpha = beauty->components() == 4;
    const char* comp[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < (has_alpha ? 4 : 3); ++c) {
      io::Storage s = io::Storage::f32;
      if (const io::Channel* in = img.find(beauty->terms.front()[size_t(c)])) s = in->storage;
      if (beauty_is_rgba) {
        io::Channel* orig = img.find(comp[c]);
        orig->name = std::string("input.") + comp[c];
      }
      std::vector<float> v(n);
      b.at("composite").download(v.data(), n * sizeof(float), size_t(c) * n * sizeof(float));
      img.set(comp[c], std::move(v), s);
    }
  }

 private:
  ForegroundPass foreground_;
  CompositeTermPass term_;
};
}  // namespace

std::unique_ptr<Recorder> composite_recorder(gpu::Context& ctx) {
  return std::make_unique<CompositeRecorder>(ctx);
}

}  // namespace isg::effects
