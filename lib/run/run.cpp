#include "run/run.h"

#include <chrono>
#include <map>
#include <memory>

#include "effects/composite/composite.h"
#include "effects/dof/dof.h"
#include "effects/reflections/reflections.h"
#include "effects/shadows/derive.h"
#include "effects/shadows/hard.h"
#include "effects/shadows/isg.h"
#include "effects/shadows/shadowmap.h"

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
    gpu::Buffer b(ctx, r.bytes, r.name, r.upload ? gpu::Buffer::Init::none : gpu::Buffer::Init::zero);
    if (r.upload) {
      const std::string role = r.name == "composite" ? "beauty" : r.name;
      const io::RoleBinding* rb = roles.get(role);
      if (!rb) throw io::IoError(img.path.string() + ": missing channels for role " + role);
      b.upload_with(r.bytes, [&](void* dst) { io::gather_role_into(img, *rb, r.planes, static_cast<float*>(dst)); });
    }
    buf.emplace(r.name, std::move(b));
  }
  st.upload_ms = ms_since(t0);

  // Passes, created only when the plan uses them.
  t0 = Clock::now();
  std::unique_ptr<effects::ForegroundPass> foreground;
  std::unique_ptr<effects::ShadowsHardPass> hard;
  std::unique_ptr<effects::ShadowsIsgPass> soft_isg;
  std::map<std::string, std::unique_ptr<effects::ShadowmapPass>> smap_pass;  // per light
  std::unique_ptr<effects::CompositeTermPass> term;
  std::unique_ptr<effects::DofPass> dof;
  std::unique_ptr<effects::ReflectionsPass> refl;
  gpu::Sequence seq(ctx);
  const io::RoleBinding* beauty = roles.get("beauty");
  // A light's shadow map, read on the host from its own EXR into the plan's L.shadowmap.
  auto upload_map = [&st](const effects::ShadowmapSettings& s, gpu::Buffer& mb) {
    auto map = effects::load_shadowmap(s);
    if (map.nonfinite > 0)
      st.warnings.insert(s.file.string() + ": " + std::to_string(map.nonfinite) +
                         " NaN/Inf depths, each replaced by its farthest finite neighbour");
    if (uint64_t(map.z.size()) * 4 != mb.size())
      throw io::IoError(s.file.string() + ": shadow map is " + std::to_string(map.width) + "x" +
                        std::to_string(map.height) + ", not the scene file's size");
    mb.upload(std::span<const float>(map.z));
    return map;
  };
  std::vector<std::unique_ptr<effects::ShadowmapDerivePass>> derive;
  for (const auto& p : plan.passes) {
    if (p.name == "foreground") {
      if (!foreground) foreground = std::make_unique<effects::ForegroundPass>(ctx);
      auto d = buf.find("depth");
      foreground->record(seq, buf.at("composite"), beauty->components() == 4,
                         d == buf.end() ? nullptr : &d->second, buf.at("fg"), w, h);
    } else if (p.name == "shadows.hard") {
      if (!hard) hard = std::make_unique<effects::ShadowsHardPass>(ctx);
      hard->record(seq, buf.at(p.reads.at(0)), buf.at(p.writes.at(0)), w, h, p.label);
    } else if (p.name == "shadows.isg") {
      if (!soft_isg) soft_isg = std::make_unique<effects::ShadowsIsgPass>(ctx);
      soft_isg->record(seq, plan.shadows.at(p.light), buf.at(p.reads.at(0)), buf.at(p.reads.at(1)),
                       buf.at(p.reads.at(2)), p.reads.at(2) == "position", buf.at("fg"),
                       buf.at(p.writes.at(1)), buf.at(p.writes.at(2)), buf.at(p.writes.at(0)), w,
                       h, p.label);
    } else if (plan.shadowmaps.count(p.light) && p.name == "shadows." + plan.shadowmaps.at(p.light).method) {
      // The light's shadow map: read on the host from its own EXR, uploaded into the plan's
      // L.shadowmap; reads = {L.shadow, position|depth, fg, L.shadowmap}.
      const auto& s = plan.shadowmaps.at(p.light);
      gpu::Buffer& mb = buf.at(p.reads.at(3));
      const auto map = upload_map(s, mb);
      auto& pass = smap_pass[p.light];
      pass = std::make_unique<effects::ShadowmapPass>(ctx, s, map, w, h, p.reads.at(1) == "position");
      pass->record(seq, buf.at(p.reads.at(1)), buf.at(p.reads.at(2)), buf.at(p.reads.at(0)), mb,
                   buf.at(p.writes.at(0)), p.label);
    } else if (p.name == "shadows.derive") {
      // reads = {position|depth, fg, L.shadowmap}; writes = {L.occluder[, L.shadow]}.
      gpu::Buffer& mb = buf.at(p.reads.at(2));
      const auto map = upload_map(plan.derived.at(p.light), mb);
      derive.push_back(std::make_unique<effects::ShadowmapDerivePass>(
          ctx, plan.derived.at(p.light), map, w, h, p.reads.at(0) == "position"));
      const bool write_shadow = p.writes.size() > 1;
      derive.back()->record(seq, buf.at(p.reads.at(0)), buf.at(p.reads.at(1)), mb,
                            buf.at(write_shadow ? p.writes.at(1) : p.light + ".shadow"),
                            write_shadow, buf.at(p.writes.at(0)), p.label);
    } else if (p.name == "composite_term") {
      if (!term) term = std::make_unique<effects::CompositeTermPass>(ctx);
      const auto& X = buf.at(p.reads.at(2));
      term->record(seq, buf.at("composite"), buf.at(p.reads.at(1)), X, buf.at(p.reads.at(3)),
                   uint32_t(X.size() / (n * sizeof(float))), buf.at("fg"), w, h, p.label);
    } else if (p.name == "reflections.pack") {
      // Recorded by reflections.isg, which owns both kernels.
    } else if (p.name == "reflections.isg") {
      if (!refl) refl = std::make_unique<effects::ReflectionsPass>(ctx, plan.refl.value());
      const bool has_p = buf.count("position") != 0;
      auto rough = buf.find("roughness");
      refl->record(seq,
                   {buf.at("refl"), buf.at("refl.dist"), buf.at("refl.weight"), buf.at("normal"),
                    buf.at(has_p ? "position" : "depth"), has_p,
                    rough == buf.end() ? nullptr : &rough->second, buf.at("fg"),
                    buf.at("refl.pack.geo"), buf.at("refl.pack.color"), buf.at("refl.glossy"),
                    buf.at("refl.tiles")},
                   w, h, p.label);
    } else if (p.name.starts_with("dof.")) {
      if (!dof) dof = std::make_unique<effects::DofPass>(ctx, plan.dof.value());
      if (p.name == "dof.coc") {
        dof->record_coc(seq, buf.at("composite"), beauty->components() == 4, buf.at("depth"),
                        buf.at("dof.coc"), buf.at("dof.input"), w, h);
      } else if (p.name == "dof.tiles") {
        dof->record_tiles(seq, buf.at("dof.coc"), buf.at("dof.tiles"), w, h);
      } else if (p.name == "dof.search") {
        dof->record_search(seq, buf.at("dof.coc"), buf.at("dof.tiles"), buf.at("dof.radius"), w, h);
      } else if (p.name == "dof.gather") {
        dof->record_gather(seq, buf.at("dof.input"), buf.at("dof.coc"), buf.at("dof.tiles"),
                           buf.at("dof.radius"), buf.at("composite"), w, h);
      } else if (p.name == "dof.layered") {
        dof->record_layered(seq, buf.at("dof.input"), buf.at("dof.coc"), buf.at("dof.tiles"),
                            buf.at("composite"), w, h);
      } else {
        throw std::logic_error("planner produced unknown pass " + p.name);
      }
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
  // Each plane straight into its channel's array (one copy, no intermediate).
  auto plane = [n](const gpu::Buffer& b, size_t c) {
    std::vector<float> v(n);
    b.download(v.data(), n * sizeof(float), c * n * sizeof(float));
    return v;
  };
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
    img.set(comp[c], plane(buf.at("composite"), size_t(c)), s);
  }
  for (const auto& l : plan.soft_lights) {
    const std::string soft = l + ".softshadow";
    img.set(soft, buf.at(soft).download_as<float>(n), io::Storage::f32);
    if (smap_pass.count(l)) {
      auto t = smap_pass.at(l)->stats();
      st.shadowmaps.push_back({l, plan.shadowmaps.at(l).method, t.skipped_fraction(), t.pixels,
                              t.clamped, smap_pass.at(l)->gpu_bytes()});
    }
    if (plan.shadows.count(l)) {
      auto t = effects::ShadowsIsgPass::stats(buf.at(l + ".shadow.tiles"), w, h);
      st.shadows.push_back({l, t.skipped_fraction, t.clamped_pixels, t.full_pixels});
      const auto& ss = plan.shadows.at(l);
      st.gathers.push_back({"shadows.isg[" + l + "]", t.full_pixels,
                            t.full_pixels * uint64_t(ss.grid_search * ss.grid_search +
                                                     ss.grid_gather * ss.grid_gather)});
    }
  }
  if (plan.refl) {
    const char* rgb[3] = {"refl.glossy.R", "refl.glossy.G", "refl.glossy.B"};
    for (size_t c = 0; c < 3; ++c) img.set(rgb[c], plane(buf.at("refl.glossy"), c), io::Storage::f32);
    const auto rt = effects::ReflectionsPass::stats(buf.at("refl.tiles"), w, h);
    st.refl_skipped_fraction = rt.skipped_fraction;
    const auto& rs = plan.refl.value();
    st.gathers.push_back({"reflections." + rs.method, rt.glossy_pixels,
                          rt.searches * uint64_t(rs.grid_search * rs.grid_search) +
                              rt.glossy_pixels * uint64_t(rs.grid_gather * rs.grid_gather)});
  }
  if (plan.dof) {
    img.set("dof.coc", buf.at("dof.coc").download_as<float>(n), io::Storage::f32);
    st.dof_cheap_fraction = effects::DofPass::cheap_fraction(buf.at("dof.tiles"), w, h);
  }
  st.download_ms = ms_since(t0);
  return st;
}

}  // namespace isg::run
