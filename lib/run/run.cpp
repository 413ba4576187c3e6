#include "run/run.h"

#include <chrono>


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

const effects::Report* Stats::report(const std::string& key) const {
  for (const auto& r : reports)
    if (r.key == key) return &r;
  return nullptr;
}

void Stats::add_tile(const Stats& st) {
  for (const auto& p : st.passes) {
    auto it = std::find_if(passes.begin(), passes.end(), [&](const auto& q) { return q.name == p.name; });
    if (it == passes.end()) passes.push_back(p);
    else it->ms += p.ms;
  }
  upload_ms += st.upload_ms;
  record_ms += st.record_ms;
  gpu_wall_ms += st.gpu_wall_ms;
  download_ms += st.download_ms;
  // Counts add up; aprons are counted in each tile that reads them.
  for (const auto& r : st.reports) {
    auto it = std::find_if(reports.begin(), reports.end(), [&](const auto& q) { return q.key == r.key; });
    if (it == reports.end()) reports.push_back(r);
    else it->merge(r);
  }
  for (const auto& g : st.gathers) {
    auto it = std::find_if(gathers.begin(), gathers.end(), [&](const auto& q) { return q.pass == g.pass; });
    if (it == gathers.end()) gathers.push_back(g);
    else it->pixels += g.pixels, it->samples += g.samples;
  }
  warnings.insert(st.warnings.begin(), st.warnings.end());
  ++tiles;
}

effects::Recorder& Runner::recorder(const std::string& effect) {
  auto& r = recorders_[effect];
  if (!r) r = effects::make_recorder(effect, ctx_);
  return *r;
}

Stats Runner::execute(const plan::Plan& plan, const io::Roles& roles, io::Image& img) {
  if (!plan.missing.empty()) {
    throw io::IoError(img.path.string() + ": missing required channels for role " + plan.missing.front());
  }
  Stats st;
  const uint32_t w = uint32_t(plan.width), h = uint32_t(plan.height);

  // Resources: exactly those the plan declares.
  auto t0 = Clock::now();
  std::map<std::string, gpu::Buffer> buf;
  for (const auto& r : plan.resources) {
    gpu::Buffer b(ctx_, r.bytes, r.name, r.upload ? gpu::Buffer::Init::none : gpu::Buffer::Init::zero);
    if (r.upload) {
      const std::string role = r.name == "composite" ? "beauty" : r.name;
      const io::RoleBinding* rb = roles.get(role);
      if (!rb) throw io::IoError(img.path.string() + ": missing channels for role " + role);
      b.upload_with(r.bytes, [&](void* dst) { io::gather_role_into(img, *rb, r.planes, static_cast<float*>(dst)); });
    }
    buf.emplace(r.name, std::move(b));
  }
  st.upload_ms = ms_since(t0);

  // Passes: each by its effect's recorder, against the named resources.
  t0 = Clock::now();
  const effects::Bindings b(buf, roles, w, h);
  gpu::Sequence seq(ctx_);
  for (const auto& p : plan.passes) {
    recorder(p.effect).record(seq, p, *plan.instances.at(size_t(p.instance)), b);
  }
  st.record_ms = ms_since(t0);
  t0 = Clock::now();
  st.passes = seq.submit();
  st.gpu_wall_ms = ms_since(t0);

  // Outputs and statistics, effect by effect in plan order.
  t0 = Clock::now();
  effects::RunOutputs out;
  for (const auto& i : plan.instances) recorder(i->effect).finish(*i, b, img, out);
  st.reports = std::move(out.reports);
  st.gathers = std::move(out.gathers);
  st.download_ms = ms_since(t0);
  return st;
}

Stats execute(gpu::Context& ctx, const plan::Plan& plan, const io::Roles& roles, io::Image& img) {
  Runner r(ctx);
  return r.execute(plan, roles, img);
}

}  // namespace isg::run
