#include "run/run.h"

#include <chrono>
#include <map>
#include <memory>

#include "effects/composite/composite.h"
#include "effects/shadows/hard.h"

namespace isg::run {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
}  // namespace

double Stats::gpu_ms() const {
  double s = 0;
  for (const auto& p : passes) s += p.ms;
  return s;
}

Stats execute(gpu::Context& ctx, const plan::Plan& plan, const io::Roles& roles, io::Image& img) {
  if (!plan.missing.empty()) {
    throw io::IoError(img.path.string() + ": missing required channels for role " + plan.missing.front());
  }
  Stats st;
  const uint32_t w = uint32_t(plan.width), h = uint32_t(plan.height);
  const size_t n = img.pixels();

  // Resources: exactly those the plan declares.
  auto t0 = Clock::now();
  std::map<std::string, gpu::Buffer> buf;
  for (const auto& r : plan.resources) {
    gpu::Buffer b(ctx, r.bytes, r.name);
    if (r.upload) {
      const std::string role = r.name == "composite" ? "beauty" : r.name;
      const io::RoleBinding* rb = roles.get(role);
      if (!rb) throw io::IoError(img.path.string() + ": missing channels for role " + role);
      auto planes = io::gather_role(img, *rb, r.planes);
      b.upload(std::span<const float>(planes));
    }
    buf.emplace(r.name, std::move(b));
  }
  st.upload_ms = ms_since(t0);

  // Passes, created only when the plan uses them.
  t0 = Clock::now();
  std::unique_ptr<effects::ForegroundPass> foreground;
  std::unique_ptr<effects::ShadowsHardPass> hard;
  std::unique_ptr<effects::CompositeTermPass> term;
  gpu::Sequence seq(ctx);
  const io::RoleBinding* beauty = roles.get("beauty");
  for (const auto& p : plan.passes) {
    if (p.name == "foreground") {
      if (!foreground) foreground = std::make_unique<effects::ForegroundPass>(ctx);
      auto d = buf.find("depth");
      foreground->record(seq, buf.at("composite"), beauty->components() == 4,
                         d == buf.end() ? nullptr : &d->second, buf.at("fg"), w, h);
    } else if (p.name == "shadows.hard") {
      if (!hard) hard = std::make_unique<effects::ShadowsHardPass>(ctx);
      hard->record(seq, buf.at(p.reads.at(0)), buf.at(p.writes.at(0)), w, h, p.label);
    } else if (p.name == "composite_term") {
      if (!term) term = std::make_unique<effects::CompositeTermPass>(ctx);
      const auto& X = buf.at(p.reads.at(2));
      term->record(seq, buf.at("composite"), buf.at(p.reads.at(1)), X, buf.at(p.reads.at(3)),
                   uint32_t(X.size() / (n * sizeof(float))), buf.at("fg"), w, h, p.label);
    } else {
      throw std::logic_error("planner produced unknown pass " + p.name);
    }
  }
  st.record_ms = ms_since(t0);
  t0 = Clock::now();
  st.passes = seq.submit();
  st.gpu_wall_ms = ms_since(t0);

  // Outputs.
  t0 = Clock::now();
  auto C = buf.at("composite").download_as<float>(4 * n);
  const bool beauty_is_rgba = beauty->how == "contract name";
  const bool has_alpha = beauty->components() == 4;
  const char* comp[4] = {"R", "G", "B", "A"};
  for (int c = 0; c < (has_alpha ? 4 : 3); ++c) {
    io::Storage s = io::Storage::f32;
    if (const io::Channel* in = img.find(beauty->terms.front()[c])) s = in->storage;
    if (beauty_is_rgba) {
      io::Channel* orig = img.find(comp[c]);
      orig->name = std::string("input.") + comp[c];
    }
    img.set(comp[c], std::vector<float>(C.begin() + c * n, C.begin() + (c + 1) * n), s);
  }
  for (const auto& l : plan.soft_lights) {
    const std::string soft = l + ".softshadow";
    img.set(soft, buf.at(soft).download_as<float>(n), io::Storage::f32);
  }
  st.download_ms = ms_since(t0);
  return st;
}

}  // namespace isg::run
