// The soft shadows' recorder: each light's passes against the plan's resources, its
// L.softshadow channel and its statistics. The shadow map was read in the load stage; here it
// is only uploaded into the plan's L.shadowmap.
#include <map>

#include "effects/recorder.h"
#include "effects/shadowmaps/derive.h"
#include "effects/shadows/hard.h"
#include "effects/shadows/instance.h"
#include "effects/shadows/isg.h"
#include "effects/shadowmaps/shadowmap.h"

namespace isg::effects {

namespace {

class ShadowsRecorder final : public Recorder {
 public:
  explicit ShadowsRecorder(gpu::Context& ctx) : ctx_(ctx), hard_(ctx), isg_(ctx) {}

  void record(gpu::Sequence& seq, const Pass& p, const Instance& i, const Bindings& b) override {
    const auto& inst = static_cast<const ShadowsInstance&>(i);
    auto& f = frame_[&inst];
    if (p.name == "shadows.hard") {
      hard_.record(seq, b.at(p.reads.at(0)), b.at(p.writes.at(0)), b.w, b.h, p.label);
    } else if (p.name == "shadows.isg") {
      isg_.record(seq, inst.isg.value(), b.at(p.reads.at(0)), b.at(p.reads.at(1)),
                  b.at(p.reads.at(2)), p.reads.at(2) == "position", b.at("fg"),
                  b.at(p.writes.at(1)), b.at(p.writes.at(2)), b.at(p.writes.at(0)), b.w, b.h,
                  p.label);
      f.isg_label = p.label;
    } else if (p.name == "shadows.derive") {
      // reads = {position|depth, fg, L.shadowmap}; writes = {L.occluder[, L.shadow]}.
      gpu::Buffer& mb = b.at(p.reads.at(2));
      mb.upload(std::span<const float>(inst.map->z));
      f.derive = std::make_unique<ShadowmapDerivePass>(ctx_, inst.derived.value(), *inst.map, b.w,
                                                       b.h, p.reads.at(0) == "position");
      const bool write_shadow = p.writes.size() > 1;
      f.derive->record(seq, b.at(p.reads.at(0)), b.at(p.reads.at(1)), mb,
                       b.at(write_shadow ? p.writes.at(1) : inst.light + ".shadow"), write_shadow,
                       b.at(p.writes.at(0)), p.label);
    } else {
      // A shadow-map method; reads = {L.shadow, position|depth, fg, L.shadowmap}.
      gpu::Buffer& mb = b.at(p.reads.at(3));
      mb.upload(std::span<const float>(inst.map->z));
      f.smap = std::make_unique<ShadowmapPass>(ctx_, inst.smap.value(), *inst.map, b.w, b.h,
                                               p.reads.at(1) == "position");
      f.smap->record(seq, b.at(p.reads.at(1)), b.at(p.reads.at(2)), b.at(p.reads.at(0)), mb,
                     b.at(p.writes.at(0)), p.label);
    }
  }

  void finish(const Instance& i, const Bindings& b, io::Image& img, RunOutputs& out) override {
    const auto& inst = static_cast<const ShadowsInstance&>(i);
    const std::string soft = inst.light + ".softshadow";
    img.set(soft, b.at(soft).download_as<float>(b.pixels()), io::Storage::f32);
    auto f = std::move(frame_[&inst]);
    frame_.erase(&inst);
    if (f.smap) {
      const auto t = f.smap->stats();
      Report r{"shadows", inst.key + " (" + inst.smap->method + ")", {}, {}};
      r.sum("pixels", double(t.pixels));
      r.sum("skipped", double(t.skipped));
      r.sum("clamped", double(t.clamped));
      r.max("gpu_bytes", double(f.smap->gpu_bytes()));
      out.reports.push_back(r);
    }
    if (inst.isg) {
      const auto t = ShadowsIsgPass::stats(b.at(inst.light + ".shadow.tiles"), b.w, b.h);
      Report r{"shadows", inst.key, {}, {}};
      r.sum("tiles", 1.0);  // fractions are averaged over the tiles of a large plate
      r.sum("skipped", t.skipped_fraction);
      r.sum("dispatched", t.dispatched_fraction);
      r.sum("full_pixels", double(t.full_pixels));
      r.sum("clamped_pixels", double(t.clamped_pixels));
      r.sum("borrowed", double(t.borrowed));
      out.reports.push_back(r);
      const auto& s = *inst.isg;
      out.gathers.push_back({f.isg_label, t.full_pixels,
                             t.searches * uint64_t(s.grid_search * s.grid_search) +
                                 t.gathers * uint64_t(s.grid_gather * s.grid_gather),
                             4,  // bilinear: four texels, each with its range weight
                             {f.isg_label + ".reach", f.isg_label + ".quads", f.isg_label + ".own"}});
    }
  }

 private:
  struct Frame {
    std::unique_ptr<ShadowmapPass> smap;  // its buffers live until the frame's statistics
    std::unique_ptr<ShadowmapDerivePass> derive;
    std::string isg_label;
  };
  gpu::Context& ctx_;
  ShadowsHardPass hard_;
  ShadowsIsgPass isg_;  // keeps its sample tables for the job
  std::map<const Instance*, Frame> frame_;
};

}  // namespace

std::unique_ptr<Recorder> shadows_recorder(gpu::Context& ctx) {
  return std::make_unique<ShadowsRecorder>(ctx);
}

}  // namespace isg::effects
