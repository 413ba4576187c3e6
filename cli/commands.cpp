// `isg info`, `compare`, `roofline`, `devices`, `params`, `presets`: parse and print.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "cli.h"
#include "isg_version.h"
#include "effects/params.h"
#include "gpu/gpu.h"
#include "io/color.h"
#include "metrics/compare.h"
#include "plan/plan.h"
#include "run/job.h"

namespace isg::cli {

using json = nlohmann::json;

// ---- isg info ----

int cmd_info(const Common& c, const std::string& input, bool as_json) {
  // The file's roles (listed), and those `isg run` takes (input.positions: P refitted far from
  // the origin, or Z; what can run and what auto picks).
  const auto job = isg::run::make_job(job_options(c, ""), isg::run::executable_layout(), ISG_VERSION);
  const auto& scene = job.scene;
  auto f = isg::run::plan_frame(job, input);  // checks the --channel roles
  auto& img = f.img;
  const std::vector<std::string> channels = img.channel_names();
  const auto& roles = f.roles;
  const std::optional<isg::io::Camera>& cam = f.camera;
  auto caps = isg::plan::capabilities(f.roles, scene, cam.has_value());
  // What `auto` would pick, and why, for every parameter that offers it (shadows.method, issue
  // 19), through the effects' own Effect::choose with those parameters set to auto (issue 56):
  // from the pixels, so they are read only where an effect of such a parameter's section runs.
  struct Pick {
    std::string key, method, why;
  };
  auto p_auto = job.params;
  std::vector<std::string> auto_keys;
  for (const auto& d : p_auto.defs())
    if (d.type == isg::params::Type::choice && std::find(d.choices.begin(), d.choices.end(), "auto") != d.choices.end()) {
      p_auto.set_text(d.key, "auto", "isg info");
      auto_keys.push_back(d.key);
    }
  auto section_of = [](const std::string& key) { return key.substr(0, key.find('.')); };
  std::map<std::string, Pick> picks;
  bool read = false;
  for (const auto& e : caps)
    for (const auto& k : auto_keys)
      read = read || (e.runs && e.effect.rfind(section_of(k), 0) == 0);
  if (read) {
    img = isg::io::read_exr(input, job.limits);
    isg::run::refit_positions(f);
    const auto choices = isg::plan::choose_from_pixels(f.roles, scene, p_auto, img, cam ? &*cam : nullptr);
    for (const auto& e : caps) {
      auto it = choices.find(e.effect);
      if (!e.runs || it == choices.end()) continue;
      std::string key;
      for (const auto& k : auto_keys)
        if (e.effect.rfind(section_of(k), 0) == 0) key = k;
      auto why = choices.find(e.effect + "/why");
      picks[e.effect] = {key, it->second, why == choices.end() ? "" : why->second};
    }
  }

  std::vector<std::string> all_roles = isg::io::global_roles();
  for (const auto& l : roles.lights)
    for (const auto& s : isg::io::light_role_suffixes()) all_roles.push_back(l + "." + s);

  if (as_json) {
    json j;
    j["file"] = input;
    j["width"] = img.width;
    j["height"] = img.height;
    j["parts"] = img.parts;
    j["channels"] = channels;
    j["layer"] = roles.layer;
    j["lights"] = roles.lights;
    for (const auto& l : scene.lights) j["scene_lights"][l.name] = isg::io::describe(l);
    j["camera"] = cam ? json(cam->source) : json(nullptr);
    j["positions"] = !f.positions.empty()         ? f.positions
                     : f.roles.has("position")    ? std::string("P")
                     : f.roles.has("depth") && cam ? std::string("Z and the camera")
                                                   : std::string("none");
    for (const auto& r : all_roles) {
      const auto* b = roles.get(r);
      j["roles"][r] = b ? json{{"channels", b->terms}, {"how", b->how}} : json(nullptr);
    }
    for (const auto& e : caps) j["effects"][e.effect] = {{"can_run", e.runs}, {"why", e.why}};
    for (const auto& [k, a] : picks) j["effects"][k]["auto"] = {{"method", a.method}, {"why", a.why}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << input << ": " << img.width << "x" << img.height << ", " << img.parts << " part"
            << (img.parts > 1 ? "s" : "") << ", " << channels.size() << " channels\n";
  if (!roles.layer.empty()) std::cout << "view layer: " << roles.layer << "\n";
  std::cout << "roles:\n";
  for (const auto& r : all_roles) {
    const auto* b = roles.get(r);
    std::cout << "  " << std::left << std::setw(14) << r;
    if (!b) {
      std::cout << "-\n";
      continue;
    }
    std::string chans;
    for (const auto& t : b->terms) chans += (chans.empty() ? "" : " + ") + join(t, ",");
    std::cout << chans << "  (" << b->how << ")\n";
  }
  std::cout << "camera: " << (cam ? cam->source : std::string("none")) << "\n";
  if (!scene.lights.empty()) std::cout << "scene lights:\n";
  for (const auto& l : scene.lights) std::cout << "  " << std::left << std::setw(14) << l.name << isg::io::describe(l) << "\n";
  if (!f.positions.empty()) std::cout << "positions: " << f.positions << "\n";
  std::cout << "effects:\n";
  for (const auto& e : caps) {
    std::cout << "  " << std::left << std::setw(14) << e.effect
              << (e.runs ? (e.why.empty() ? "can run" : "can run: " + e.why) : "cannot run: " + e.why) << "\n";
    if (auto it = picks.find(e.effect); it != picks.end())
      std::cout << "  " << std::setw(14) << "" << it->second.key << "=auto picks " << it->second.method << ": "
                << it->second.why << "\n";
  }
  return 0;
}

// ---- isg compare ----

int cmd_compare(const std::string& a_path, const std::string& b_path, const std::string& mask_name,
                const std::vector<std::string>& channels, bool as_json,
                const std::string& heatmap_path, double heatmap_max) {
  auto limits = limits_of(isg::effects::default_params());
  auto a = isg::io::read_exr(a_path, limits);
  auto b = isg::io::read_exr(b_path, limits);
  std::vector<float> mask;
  if (!mask_name.empty()) {
    // CHANNEL (looked up in B, then A) or FILE:CHANNEL (a third image, e.g. a case's mask).
    auto colon = mask_name.rfind(':');
    if (colon != std::string::npos && colon > 0) {
      auto m = isg::io::read_exr(mask_name.substr(0, colon), limits);
      const isg::io::Channel* c = m.find(mask_name.substr(colon + 1));
      if (!c) throw isg::io::IoError(mask_name.substr(0, colon) + ": no channel " + mask_name.substr(colon + 1) + " (--mask)");
      if (m.width != a.width || m.height != a.height) {
        throw isg::io::IoError(mask_name.substr(0, colon) + ": mask size differs from " + a_path);
      }
      mask = c->data;
    } else {
      const isg::io::Channel* m = b.find(mask_name);
      if (!m) m = a.find(mask_name);
      if (!m) throw isg::io::IoError("--mask " + mask_name + ": neither " + a_path + " nor " + b_path + " has that channel");
      mask = m->data;
    }
  }
  auto r = isg::metrics::compare(a, b, channels, mask);
  if (!heatmap_path.empty()) {
    std::vector<std::string> names;
    for (const auto& m : r.channels) names.push_back(m.channel);
    auto h = isg::metrics::heatmap(a, b, names, mask, heatmap_max);
    isg::io::write_picture(heatmap_path, h.width, h.height, h.rgb);
    std::cerr << "heat-map " << heatmap_path << ": mean |error| over " << join(names, ",")
              << ", scale 0 (black) to " << h.max_error << " (yellow)\n";
  }
  if (as_json) {
    json j;
    auto row = [](const isg::metrics::Metrics& m) {
      return json{{"channel", m.channel}, {"pixels", m.pixels}, {"rmse", m.rmse},
                  {"psnr", std::isfinite(m.psnr) ? json(m.psnr) : json("inf")},
                  {"mean_abs", m.mean_abs}, {"max_abs", m.max_abs}, {"ssim", m.ssim}};
    };
    for (const auto& m : r.channels) j["channels"].push_back(row(m));
    j["all"] = row(r.all);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << std::left << std::setw(20) << "channel" << std::right << std::setw(10) << "pixels"
            << std::setw(12) << "RMSE" << std::setw(10) << "PSNR" << std::setw(12) << "mean abs"
            << std::setw(12) << "max abs" << std::setw(10) << "SSIM" << "\n";
  auto print = [](const isg::metrics::Metrics& m) {
    std::cout << std::left << std::setw(20) << m.channel << std::right << std::setw(10) << m.pixels
              << std::setw(12) << std::setprecision(6) << std::fixed << m.rmse << std::setw(10)
              << std::setprecision(2) << m.psnr << std::setw(12) << std::setprecision(6)
              << m.mean_abs << std::setw(12) << m.max_abs << std::setw(10) << std::setprecision(4)
              << m.ssim << "\n";
  };
  for (const auto& m : r.channels) print(m);
  print(r.all);
  return 0;
}

// ---- isg roofline ----

int cmd_roofline(const isg::roofline::Options& opt, const std::string& device, bool as_json) {
  isg::roofline::check(opt);
  isg::gpu::ContextOptions copt;
  copt.device = device;
  copt.on_message = [](const std::string& m) { std::cerr << "isg: vulkan: " << m << "\n"; };
  isg::gpu::Context ctx(copt);
  auto line = [](const isg::roofline::Row& r) {
    std::ostringstream o;
    o << std::right << std::setw(5) << r.taps << std::setw(8) << r.radius << std::setw(12)
      << std::fixed << std::setprecision(1) << r.taps_per_second / 1e6 << std::setw(12)
      << std::setprecision(2) << r.best_ms;
    return o.str();
  };
  if (!as_json) {
    std::cout << "device: " << ctx.info().name << " (" << ctx.info().type_name << ")\n"
              << "roofline gather, " << opt.width << "x" << opt.height << ", best of "
              << opt.repeats << " dispatches after a warm-up\n"
              << " taps  radius  Mtaps/s     GPU ms\n";
  }
  auto rep = isg::roofline::measure(ctx, opt, [&](const isg::roofline::Row& r) {
    if (!as_json) std::cout << line(r) << std::endl;
  });
  if (!as_json) {
    std::cout << "workgroup " << rep.local_x << "x" << rep.local_y << "; "
              << (rep.timestamps ? "GPU time from timestamp queries" : "no timestamps: wall time per submission") << "\n";
    return kOk;
  }
  json j{{"device", rep.device}, {"device_type", rep.device_type}, {"width", rep.width},
         {"height", rep.height}, {"workgroup", {rep.local_x, rep.local_y}},
         {"timing", rep.timestamps ? "timestamp queries" : "wall time per submission"},
         {"repeats", opt.repeats}, {"rows", json::array()}};
  for (const auto& r : rep.rows) {
    j["rows"].push_back({{"taps", r.taps}, {"radius", r.radius}, {"ms", r.ms},
                         {"best_ms", r.best_ms}, {"taps_per_second", r.taps_per_second}});
  }
  std::cout << j.dump(2) << "\n";
  return kOk;
}

// `isg --version`: the first line for help2man and bug reports, then the Vulkan devices that a
// run would choose from (the first is the default), as `isg devices` lists them.
std::string version_text() {
  std::ostringstream o;
  o << "isg " << ISG_VERSION << " (commit " << ISG_COMMIT << ")\n";
  try {
    auto devs = isg::gpu::list_devices();
    if (devs.empty()) o << "Vulkan: no devices (install a driver: mesa-vulkan-drivers)";
    for (size_t k = 0; k < devs.size(); ++k) {
      const auto& d = devs[k];
      o << (k ? "\n" : "") << "Vulkan device " << d.index << ": " << d.name << " (" << d.type_name << ", Vulkan "
        << VK_API_VERSION_MAJOR(d.api_version) << "." << VK_API_VERSION_MINOR(d.api_version) << ")";
    }
  } catch (const std::exception& e) {
    o << "Vulkan: unavailable (" << e.what() << ")";
  }
  return o.str();
}

int cmd_devices() {
  auto devs = isg::gpu::list_devices();
  for (const auto& d : devs) {
    std::cout << d.index << ": " << d.name << " (" << d.type_name << ", Vulkan "
              << VK_API_VERSION_MAJOR(d.api_version) << "." << VK_API_VERSION_MINOR(d.api_version)
              << ", " << (d.device_local_bytes >> 20) << " MiB, timestamps "
              << (d.timestamps ? "yes" : "no") << ", float64 " << (d.float64 ? "yes" : "no") << ")\n";
  }
  if (devs.empty()) std::cout << "no Vulkan devices\n";
  return 0;
}

// Every parameter from the one table: key, type, default, range, unit, help.
int cmd_params(bool markdown) {
  auto p = isg::effects::default_params();
  auto range = [](const isg::params::Def& d) {
    std::ostringstream r;
    switch (d.type) {
      case isg::params::Type::boolean: return std::string("true, false");
      case isg::params::Type::choice: return join(d.choices, ", ");
      default: r << d.lo << " to " << d.hi; return r.str();
    }
  };
  if (markdown) {
    std::cout << "# Parameters\n\nGenerated by `isg params --markdown` from the parameter table "
                 "(each effect's lib/effects/<effect>/effect.cpp; [output] and [limits]: lib/effects/params.cpp). Set them in a preset's `[section]` or with "
                 "`--set section.key=value`.\n\n| key | default | range | unit | meaning |\n|---|---|---|---|---|\n";
    for (const auto& d : p.defs()) {
      std::cout << "| `" << d.key << "` | " << d.def << " | " << range(d) << " | " << d.unit << " | "
                << d.help << " |\n";
    }
    return kOk;
  }
  for (const auto& d : p.defs()) {
    std::cout << std::left << std::setw(30) << d.key << std::setw(10) << d.def << range(d)
              << (d.unit.empty() ? "" : " " + d.unit) << "\n    " << d.help << "\n";
  }
  return kOk;
}

int cmd_presets() {
  for (const auto& p : isg::params::list_presets(preset_dirs())) {
    std::cout << std::left << std::setw(20) << p.name << p.description << "\n";
  }
  return 0;
}


}  // namespace isg::cli
