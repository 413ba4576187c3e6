#include "run/options.h"

#include "effects/output_params.h"
#include "effects/params.h"

namespace isg::run {

params::Params job_params(const JobOptions& o, const Layout& layout) {
  auto p = effects::default_params();
  if (!o.preset.empty()) p.load_preset(o.preset, layout.preset_dirs);
  if (!o.compression.empty()) p.set_text("output.compression", o.compression, o.compression_label);
  for (const auto& s : o.sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos) throw params::ParamError(o.set_label + " " + s + ": expected KEY=VALUE");
    p.set_text(s.substr(0, eq), s.substr(eq + 1), o.set_label);
  }
  return p;
}

io::ReadLimits read_limits(const params::Params& p, const Layout& layout) {
  io::ReadLimits l;
  l.max_pixels = int64_t(p.get(effects::output_keys::max_megapixels) * 1e6);
  l.max_channels = int(p.get(effects::output_keys::max_channels));
  l.max_bytes = int64_t(p.get(effects::output_keys::max_memory_mb)) << 20;
  l.check_seconds = p.get(effects::output_keys::check_seconds);
  l.checker = layout.exrcheck.string();
  return l;
}

JobConfig make_job(const JobOptions& o, const Layout& layout, const std::string& version) {
  JobConfig job{o.scene.empty() ? io::Scene{} : io::read_scene(o.scene), o.scene, job_params(o, layout),
                {}, {}, {}, o.input_colorspace, version};
  auto& req = job.request;
  for (const auto& l : job.scene.lights) req.light_names.push_back(l.name);
  req.layer = o.layer;
  for (const auto& [role, e] : job.params.channels()) {
    req.overrides[role] = e.name;
    req.override_how[role] = "[channels] " + e.where;
  }
  for (const auto& [role, name] : o.channels) {
    if (role.empty() || name.empty())
      throw io::IoError(o.channel_label + " " + role + "=" + name + ": expected ROLE=NAME");
    req.overrides[role] = name;
    req.override_how[role] = o.channel_label;
  }
  job.limits = read_limits(job.params, layout);
  job.write = {job.params.get(effects::output_keys::compression), o.no_clobber};
  return job;
}

}  // namespace isg::run
