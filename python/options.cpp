#include "options.h"

#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "effects/params.h"

#ifndef ISG_VERSION
#define ISG_VERSION "0.0.0"
#endif
#ifndef ISG_SOURCE_PRESETS
#define ISG_SOURCE_PRESETS ""
#endif
#ifndef ISG_EXRCHECK
#define ISG_EXRCHECK ""
#endif

namespace isg::python {

namespace fs = std::filesystem;

namespace {

// As the CLI looks for presets, less the executable's own folder: $ISG_PRESET_PATH
// (colon-separated), then the source tree the module was built from.
std::vector<fs::path> preset_dirs() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("ISG_PRESET_PATH")) {
    std::stringstream ss(env);
    std::string d;
    while (std::getline(ss, d, ':'))
      if (!d.empty()) dirs.emplace_back(d);
  }
  if (std::string(ISG_SOURCE_PRESETS).size()) dirs.emplace_back(ISG_SOURCE_PRESETS);
  return dirs;
}

}  // namespace

run::JobConfig make_job(const Options& o) {
  auto p = effects::default_params();
  if (!o.preset.empty()) p.load_preset(o.preset, preset_dirs());
  if (!o.compression.empty()) p.set_text("output.compression", o.compression, "compression");
  for (const auto& s : o.sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos) throw params::ParamError("set " + s + ": expected KEY=VALUE");
    p.set_text(s.substr(0, eq), s.substr(eq + 1), "set");
  }
  run::JobConfig job{o.scene.empty() ? io::Scene{} : io::read_scene(o.scene),
                     o.scene,
                     std::move(p),
                     {},
                     {},
                     {},
                     o.input_colorspace,
                     ISG_VERSION};
  for (const auto& l : job.scene.lights) job.request.light_names.push_back(l.name);
  job.request.layer = o.layer;
  for (const auto& [role, e] : job.params.channels()) {
    job.request.overrides[role] = e.name;
    job.request.override_how[role] = "[channels] " + e.where;
  }
  for (const auto& [role, name] : o.channels) {
    if (role.empty() || name.empty())
      throw io::IoError("channels: " + role + "=" + name + ": expected ROLE=NAME");
    job.request.overrides[role] = name;
    job.request.override_how[role] = "channels";
  }
  auto& l = job.limits;
  l.max_pixels = int64_t(job.params.number("limits.max_megapixels") * 1e6);
  l.max_channels = int(job.params.integer("limits.max_channels"));
  l.max_bytes = int64_t(job.params.integer("limits.max_memory_mb")) << 20;
  l.check_seconds = job.params.number("limits.check_seconds");
  // Pixels are decoded in the isg-exrcheck child where it is (as the CLI does); the same bits
  // either way.
  std::error_code ec;
  if (const char* env = std::getenv("ISG_EXRCHECK"); env && fs::exists(env, ec)) {
    l.checker = env;
  } else if (fs::exists(ISG_EXRCHECK, ec)) {
    l.checker = ISG_EXRCHECK;
  }
  job.write = {job.params.choice("output.compression"), o.no_clobber};
  return job;
}

}  // namespace isg::python
