#include <iostream>
#include <sstream>

#include "cli.h"
#include "effects/output_params.h"
#include "effects/params.h"
#include "run/install.h"
#include "run/options.h"

namespace isg::cli {

namespace fs = std::filesystem;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

std::vector<fs::path> preset_dirs() { return isg::run::executable_layout().preset_dirs; }

void add_common(CLI::App* app, Common& c) {
  app->add_option("--scene", c.scene, "scene file (JSON, AOV_CONTRACT.md input 3)");
  app->add_option("--preset", c.preset, "preset name (see `isg presets`) or TOML file");
  app->add_option("--set", c.sets, "override a parameter: section.key=value (repeatable)");
  app->add_option("--channel", c.channels, "map a role to channels: ROLE=NAME (repeatable)");
  app->add_option("--layer", c.layer, "Blender view layer to read");
}

isg::run::JobOptions job_options(const Common& c, const std::string& compression) {
  isg::run::JobOptions o;
  o.scene = c.scene;
  o.preset = c.preset;
  o.sets = c.sets;
  o.layer = c.layer;
  o.compression = compression;
  for (const auto& s : c.channels) {
    auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size()) {
      throw isg::io::IoError("--channel " + s + ": expected ROLE=NAME");
    }
    o.channels.emplace_back(s.substr(0, eq), s.substr(eq + 1));
  }
  return o;
}

isg::io::ReadLimits limits_of(const isg::params::Params& p) {
  return isg::run::read_limits(p, isg::run::executable_layout());
}

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const auto& e : v) s += (s.empty() ? "" : sep) + e;
  return s;
}


}  // namespace isg::cli
