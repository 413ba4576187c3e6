#include "options.h"

#include "effects/params.h"
#include "run/install.h"

#ifndef ISG_VERSION
#define ISG_VERSION "0.0.0"
#endif
// The relative path from the module's folder to the install prefix
// (python/CMakeLists.txt: lib/python3/dist-packages -> ../../..).
#ifndef ISG_PYTHON_TO_PREFIX
#define ISG_PYTHON_TO_PREFIX "../../.."
#endif

namespace isg::python {

namespace {

// Where the module finds presets and isg-exrcheck: by its own file, as the CLI does by its
// executable (run/install.h).
run::Layout module_layout() {
  static const int anchor = 0;
  return run::layout_of(run::object_file_of(&anchor), ISG_PYTHON_TO_PREFIX);
}

}  // namespace

run::JobConfig make_job(const Options& o) {
  auto p = effects::default_params();
  if (!o.preset.empty()) p.load_preset(o.preset, module_layout().preset_dirs);
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
  l.checker = module_layout().exrcheck.string();
  job.write = {job.params.choice("output.compression"), o.no_clobber};
  return job;
}

}  // namespace isg::python
