#include <iostream>
#include <sstream>

#include "cli.h"
#include "effects/output_params.h"
#include "effects/params.h"
#include "run/install.h"

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

isg::params::Params build_params(const Common& c, const std::string& compression) {
  auto p = isg::effects::default_params();
  if (!c.preset.empty()) p.load_preset(c.preset, preset_dirs());
  if (!compression.empty()) p.set_text("output.compression", compression, "--compression");
  for (const auto& s : c.sets) {
    auto eq = s.find('=');
    if (eq == std::string::npos) throw isg::params::ParamError("--set " + s + ": expected KEY=VALUE");
    p.set_text(s.substr(0, eq), s.substr(eq + 1), "--set");
  }
  return p;
}

isg::io::Scene load_scene(const Common& c) {
  if (c.scene.empty()) return isg::io::Scene{};
  return isg::io::read_scene(c.scene);
}

isg::io::RoleRequest role_request(const Common& c, const isg::params::Params& p,
                                  const isg::io::Scene& scene) {
  isg::io::RoleRequest req;
  for (const auto& l : scene.lights) req.light_names.push_back(l.name);
  req.layer = c.layer;
  for (const auto& [role, e] : p.channels()) {
    req.overrides[role] = e.name;
    req.override_how[role] = "[channels] " + e.where;
  }
  for (const auto& s : c.channels) {
    auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size()) {
      throw isg::io::IoError("--channel " + s + ": expected ROLE=NAME");
    }
    req.overrides[s.substr(0, eq)] = s.substr(eq + 1);
    req.override_how[s.substr(0, eq)] = "--channel";
  }
  return req;
}

void check_override_roles(const isg::io::RoleRequest& req, const isg::io::Roles& roles) {
  for (const auto& [role, name] : req.overrides) {
    if (!isg::io::is_known_role(role, roles.lights)) {
      auto how = req.override_how.find(role);
      throw isg::io::IoError((how == req.override_how.end() ? "--channel" : how->second) + ": " +
                             role + "=" + name + ": unknown role " + role);
    }
  }
}

isg::io::ReadLimits limits_of(const isg::params::Params& p) {
  isg::io::ReadLimits l;
  l.max_pixels = int64_t(p.get(isg::effects::output_keys::max_megapixels) * 1e6);
  l.max_channels = int(p.get(isg::effects::output_keys::max_channels));
  l.max_bytes = int64_t(p.get(isg::effects::output_keys::max_memory_mb)) << 20;
  l.check_seconds = p.get(isg::effects::output_keys::check_seconds);
  l.checker = isg::run::executable_layout().exrcheck.string();
  return l;
}

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const auto& e : v) s += (s.empty() ? "" : sep) + e;
  return s;
}


}  // namespace isg::cli
