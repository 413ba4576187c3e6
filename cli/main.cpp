// The `isg` executable: argument parsing and printing only; the work is in lib/.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <future>
#include <memory>
#include <optional>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "effects/params.h"
#include "farm.h"
#include "gpu/gpu.h"
#include "io/color.h"
#include "io/image.h"
#include "io/roles.h"
#include "io/scene.h"
#include "metrics/compare.h"
#include "plan/plan.h"
#include "roofline/roofline.h"
#include "run/job.h"
#include "run/run.h"

#ifndef ISG_VERSION
#define ISG_VERSION "0.0.0"
#endif
#ifndef ISG_SOURCE_PRESETS
#define ISG_SOURCE_PRESETS ""
#endif

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// Shipped presets: $ISG_PRESET_PATH (colon-separated), <exe>/../share/isg/presets, the source tree.
std::vector<fs::path> preset_dirs() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("ISG_PRESET_PATH")) {
    std::stringstream ss(env);
    std::string d;
    while (std::getline(ss, d, ':'))
      if (!d.empty()) dirs.emplace_back(d);
  }
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(exe.parent_path().parent_path() / "share" / "isg" / "presets");
  if (std::string(ISG_SOURCE_PRESETS).size()) dirs.emplace_back(ISG_SOURCE_PRESETS);
  return dirs;
}

struct Common {
  std::string scene;
  std::string preset;
  std::vector<std::string> sets;
  std::vector<std::string> channels;
  std::string layer;
};

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
  l.max_pixels = int64_t(p.number("limits.max_megapixels") * 1e6);
  l.max_channels = int(p.integer("limits.max_channels"));
  l.max_bytes = int64_t(p.integer("limits.max_memory_mb")) << 20;
  l.check_seconds = p.number("limits.check_seconds");
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) l.checker = (exe.parent_path() / "isg-exrcheck").string();
  return l;
}

std::string join(const std::vector<std::string>& v, const char* sep = " ") {
  std::string s;
  for (const auto& e : v) s += (s.empty() ? "" : sep) + e;
  return s;
}

// ---- isg run ----

// Exit status a farm manager can act on.
enum Exit { kOk = 0, kError = 1, kUsage = 2, kSomeFramesFailed = 3 };

struct RunArgs {
  Common common;
  std::string input, output, device, compression, preview, input_colorspace, frames;
  bool require_gpu = false, timings = false, dry_run = false, print_preset = false;
  bool no_clobber = false, validation = false, skip_existing = false, keep_going = false;
};

isg::run::JobConfig make_job(const RunArgs& a, isg::params::Params p) {
  isg::run::JobConfig job{load_scene(a.common), a.common.scene, std::move(p), {}, {}, {}, a.input_colorspace, ISG_VERSION};
  job.request = role_request(a.common, job.params, job.scene);
  job.limits = limits_of(job.params);
  job.write = {job.params.choice("output.compression"), a.no_clobber};
  return job;
}

isg::gpu::Context make_context(const RunArgs& a) {
  isg::gpu::ContextOptions copt;
  copt.device = a.device;
  copt.require_gpu = a.require_gpu;
  copt.validation = a.validation;
  copt.pipeline_cache = isg::gpu::default_pipeline_cache();
  copt.on_message = [](const std::string& m) { std::cerr << "isg: vulkan: " << m << "\n"; };
  return isg::gpu::Context(copt);
}

void warn_nonfinite(const isg::run::LoadedFrame& f) {
  for (const auto& nf : f.nonfinite) {
    std::cerr << "isg: warning: " << f.input << ": channel " << nf.channel << " had " << nf.count
              << " NaN/Inf values, set to 0\n";
  }
}

void print_timings(isg::gpu::Context& ctx, const isg::run::LoadedFrame& f,
                   const isg::run::Stats& st, double init_ms, double write_ms, double total_ms) {
  std::cout << std::fixed << std::setprecision(3);
  std::cout << "device: " << ctx.info().name << " (" << ctx.info().type_name << ")\n";
  std::cout << "GPU time per pass (timestamp queries):\n";
  for (const auto& t : st.passes)
    std::cout << "  " << std::left << std::setw(std::max(28, int(t.name.size()) + 1)) << t.name << t.ms << " ms\n";
  std::cout << "  " << std::setw(28) << "total" << st.gpu_ms() << " ms\n";
  std::cout << "wall: read " << f.read_ms << " ms, device init " << init_ms << " ms, upload "
            << st.upload_ms << " ms, record " << st.record_ms << " ms, submit+wait "
            << st.gpu_wall_ms << " ms, download " << st.download_ms << " ms, write " << write_ms
            << " ms, total " << total_ms << " ms\n";
  std::cout << "GPU memory for the plan: " << f.plan.gpu_bytes() / 1024 << " KiB";
  if (st.tiles > 0)
    std::cout << " (one piece; processed in " << st.tiles << " tiles: "
              << f.img.attributes.get_string("isg:tiles") << ")";
  std::cout << "\n";
  const auto& mem = ctx.memory_use();
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  std::cout << "memory peak: GPU " << double(mem.device_peak) / 1048576.0
            << " MiB device-local + " << double(mem.staging_peak) / 1048576.0
            << " MiB staging (all allocations, measured); host " << double(ru.ru_maxrss) / 1024.0
            << " MiB resident\n";
  if (st.refl_skipped_fraction >= 0)
    std::cout << "reflections: " << st.refl_skipped_fraction * 100.0
              << "% of tiles had nothing glossy (cheap path)\n";
  if (st.dof_cheap_fraction >= 0)
    std::cout << "dof: " << st.dof_cheap_fraction * 100.0 << "% of tiles took the cheap path\n";
  for (const auto& sh : st.shadows) {
    std::cout << "shadows[" << sh.light << "]: " << sh.skipped_fraction * 100.0
              << "% of tiles skipped (no shadow boundary within reach), " << sh.full_pixels
              << " pixels searched and gathered, " << sh.clamped_pixels
              << " needed a radius over shadows.max_radius (clamped)\n";
  }
  // The gather passes against the roofline (a plain cross-bilateral gather, `isg roofline`),
  // measured now on the same device at the frame's size.
  double roof = 0;
  if (!st.gathers.empty())
    roof = isg::roofline::roofline_taps_per_second(ctx, std::max(f.img.width, 64), std::max(f.img.height, 64));
  for (const auto& g : st.gathers) {
    double ms = 0;
    for (const auto& t : st.passes) ms += t.name == g.pass ? t.ms : 0.0;
    const double rate = ms > 0 ? double(g.samples) / (ms * 1e-3) : 0.0;
    std::cout << g.pass << ": " << g.pixels << " pixels, " << g.samples << " samples ("
              << (g.pixels ? double(g.samples) / double(g.pixels) : 0.0) << " a pixel), "
              << rate * 1e-6 << " M samples/s = " << (roof > 0 ? 100.0 * rate / roof : 0.0)
              << "% of the roofline (" << roof * 1e-6 << " M taps/s, isg roofline)\n";
  }
  for (const auto& sm : st.shadowmaps) {
    std::cout << "shadows[" << sm.light << "] (" << sm.method << "): " << sm.skipped_fraction * 100.0
              << "% of " << sm.pixels << " pixels in the shadow map skipped the filter (fully lit "
              << "or umbra), " << sm.clamped_pixels << " clamped to shadows.smap_max_radius; "
              << double(sm.gpu_bytes) / 1048576.0 << " MiB of the method's own GPU buffers\n";
  }
}

int run_single(const RunArgs& a, isg::run::JobConfig& job) {
  auto t_start = Clock::now();
  if (a.dry_run) {
    auto f = isg::run::plan_frame(job, a.input);
    std::cout << f.plan.describe();
    return f.plan.missing.empty() ? kOk : kError;
  }
  isg::io::check_writable(a.output, job.write);
  if (!a.preview.empty()) isg::io::check_writable(a.preview, job.write);
  auto f = isg::run::load_frame(job, a.input);
  warn_nonfinite(f);
  auto t_gpu = Clock::now();
  auto ctx = make_context(a);
  double init_ms = ms_since(t_gpu);
  auto st = isg::run::process_frame(ctx, job, f);
  for (const auto& w : st.warnings) std::cerr << "isg: warning: " << w << "\n";
  double write_ms = isg::run::write_frame(job, f, a.output);
  std::cout << "wrote " << a.output << " (" << f.img.width << "x" << f.img.height << ", "
            << f.img.channels.size() << " channels)\n";
  if (!a.preview.empty()) {
    auto pic = isg::io::display_picture(f.img, {"R", "G", "B"}, {});
    isg::io::write_picture(a.preview, f.img.width, f.img.height, pic, a.no_clobber);
    std::cout << "wrote " << a.preview << " (display picture, OpenColorIO "
              << isg::io::color_config_description() << ")\n";
  }
  if (a.timings) print_timings(ctx, f, st, init_ms, write_ms, ms_since(t_start));
  return kOk;
}

// Progress on a terminal (one line, redrawn) or plain lines for logs.
class Progress {
 public:
  explicit Progress(size_t total) : total_(total), tty_(::isatty(2)), start_(Clock::now()) {}
  void frame(const std::string& what, bool done_one) {
    if (done_one) ++done_;
    double s = ms_since(start_) / 1000.0;
    double rate = s > 0 ? double(done_) / s : 0;
    double eta = rate > 0 ? double(total_ - done_ - skipped_ - failed_) / rate : 0;
    std::ostringstream line;
    line << std::fixed << std::setprecision(2) << done_ + skipped_ + failed_ << "/" << total_
         << " frames, " << rate << " fps, ETA " << std::setprecision(0) << eta << " s";
    if (tty_) {
      size_t n = done_ + skipped_ + failed_;
      int width = 30, filled = total_ ? int(width * n / total_) : width;
      std::cerr << "\r[" << std::string(filled, '=') << std::string(width - filled, ' ') << "] "
                << line.str() << "  " << what << "\x1b[K" << std::flush;
    } else {
      std::cerr << what << " (" << line.str() << ")\n";
    }
  }
  void skipped(const std::string& what) {
    ++skipped_;
    frame(what, false);
  }
  void failed(const std::string& msg) {
    ++failed_;
    if (tty_) std::cerr << "\r\x1b[K";
    std::cerr << "isg: error: " << msg << "\n";
  }
  void finish() {
    if (tty_) std::cerr << "\n";
  }
  size_t done() const { return done_; }
  size_t failed_count() const { return failed_; }
  size_t skipped_count() const { return skipped_; }
  double seconds() const { return ms_since(start_) / 1000.0; }

 private:
  size_t total_, done_ = 0, skipped_ = 0, failed_ = 0;
  bool tty_;
  Clock::time_point start_;
};

// A frame range: one device for all frames; frame i+1 is read and frame i−1 written while
// frame i is on the device.
int run_sequence(const RunArgs& a, isg::run::JobConfig& job) {
  if (a.frames.empty()) throw isg::io::IoError(a.input + ": a frame pattern needs --frames A-B");
  if (!isg::run::is_sequence_pattern(a.output)) {
    throw isg::io::IoError(a.output + ": -o needs a frame pattern (#### or %04d) for a sequence");
  }
  std::vector<int> frames;
  try {
    frames = isg::run::parse_frames(a.frames);
  } catch (const std::invalid_argument& e) {
    throw isg::io::IoError(e.what());
  }
  if (a.dry_run) {
    auto f = isg::run::plan_frame(job, isg::run::expand_pattern(a.input, frames.front()));
    std::cout << frames.size() << " frames; first frame's " << f.plan.describe();
    return f.plan.missing.empty() ? kOk : kError;
  }
  isg::io::check_writable(isg::run::expand_pattern(a.output, frames.front()), {job.write.compression, false});
  std::vector<int> todo;
  Progress progress(frames.size());
  for (int fr : frames) {
    std::string out = isg::run::expand_pattern(a.output, fr);
    std::error_code ec;
    if (a.skip_existing && fs::exists(out, ec) && fs::file_size(out, ec) > 0) {
      progress.skipped("frame " + std::to_string(fr) + ": " + out + " exists, skipped");
    } else {
      todo.push_back(fr);
    }
  }
  if (todo.empty()) {
    progress.finish();
    std::cout << "nothing to do: all " << frames.size() << " outputs exist\n";
    return kOk;
  }
  auto ctx = make_context(a);
  auto load = [&](int fr) {
    return std::async(std::launch::async, [&job, &a, fr] {
      return isg::run::load_frame(job, isg::run::expand_pattern(a.input, fr));
    });
  };
  std::future<isg::run::LoadedFrame> next = load(todo.front());
  std::future<void> writing;
  std::string write_error;
  double gpu_ms = 0;
  auto finish_write = [&] {
    if (!writing.valid()) return;
    try {
      writing.get();
    } catch (const std::exception& e) {
      write_error = e.what();
    }
  };
  for (size_t i = 0; i < todo.size(); ++i) {
    const int fr = todo[i];
    const std::string out = isg::run::expand_pattern(a.output, fr);
    std::optional<isg::run::LoadedFrame> f;
    std::string error;
    try {
      f.emplace(next.get());
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (i + 1 < todo.size()) next = load(todo[i + 1]);
    if (f) {
      try {
        warn_nonfinite(*f);
        const auto st = isg::run::process_frame(ctx, job, *f);
        for (const auto& w : st.warnings) std::cerr << "isg: warning: " << w << "\n";
        gpu_ms += st.gpu_ms();
      } catch (const std::exception& e) {
        error = e.what();
        f.reset();
      }
    }
    finish_write();
    if (!write_error.empty()) {
      progress.failed(write_error);
      write_error.clear();
      if (!a.keep_going) break;
    }
    if (!error.empty()) {
      progress.failed("frame " + std::to_string(fr) + ": " + error);
      if (!a.keep_going) break;
      continue;
    }
    auto shared = std::make_shared<isg::run::LoadedFrame>(std::move(*f));
    writing = std::async(std::launch::async, [&job, shared, out, fr, &progress] {
      isg::run::write_frame(job, *shared, out);
      progress.frame("frame " + std::to_string(fr) + ": wrote " + out, true);
    });
  }
  finish_write();
  if (!write_error.empty()) progress.failed(write_error);
  if (next.valid()) next.wait();
  progress.finish();
  std::cout << std::fixed << std::setprecision(2) << "frames: " << progress.done() << " written, "
            << progress.skipped_count() << " skipped (existing), " << progress.failed_count()
            << " failed, in " << progress.seconds() << " s ("
            << (progress.seconds() > 0 ? double(progress.done()) / progress.seconds() : 0.0)
            << " fps; GPU " << gpu_ms << " ms)\n";
  if (progress.failed_count() == 0) return kOk;
  return a.keep_going ? kSomeFramesFailed : kError;
}

int cmd_run(const RunArgs& a) {
  auto p = build_params(a.common, a.compression);
  if (a.print_preset) {
    std::cout << p.to_toml();
    return kOk;
  }
  if (a.input.empty()) throw isg::io::IoError("isg run: no input file given");
  if (a.output.empty() && !a.dry_run) throw isg::io::IoError("isg run: no output given (-o FILE)");
  auto job = make_job(a, std::move(p));
  if (isg::run::is_sequence_pattern(a.input) && !fs::exists(a.input)) return run_sequence(a, job);
  if (!a.frames.empty()) throw isg::io::IoError(a.input + ": --frames needs a frame pattern (#### or %04d) in the input");
  if (!a.dry_run) {
    std::error_code ec;
    if (fs::exists(a.output, ec) && fs::equivalent(a.input, a.output, ec)) {
      throw isg::io::IoError(a.output + ": is the input file; isg never overwrites its input");
    }
  }
  return run_single(a, job);
}

// ---- isg info ----

int cmd_info(const Common& c, const std::string& input, bool as_json) {
  auto p = build_params(c, "");
  auto scene = load_scene(c);
  auto img = isg::io::read_exr_header(input, limits_of(p));
  auto req = role_request(c, p, scene);
  auto roles = isg::io::resolve_roles(img.channel_names(), req, input);
  check_override_roles(req, roles);
  std::optional<isg::io::Camera> cam = scene.camera;
  if (!cam) cam = isg::io::camera_from_header(img);
  auto caps = isg::plan::capabilities(roles, scene, cam.has_value());

  std::vector<std::string> all_roles = isg::io::global_roles();
  for (const auto& l : roles.lights)
    for (const auto& s : isg::io::light_role_suffixes()) all_roles.push_back(l + "." + s);

  if (as_json) {
    json j;
    j["file"] = input;
    j["width"] = img.width;
    j["height"] = img.height;
    j["parts"] = img.parts;
    j["channels"] = img.channel_names();
    j["layer"] = roles.layer;
    j["lights"] = roles.lights;
    j["camera"] = cam ? json(cam->source) : json(nullptr);
    for (const auto& r : all_roles) {
      const auto* b = roles.get(r);
      j["roles"][r] = b ? json{{"channels", b->terms}, {"how", b->how}} : json(nullptr);
    }
    for (const auto& e : caps) j["effects"][e.effect] = {{"can_run", e.runs}, {"why", e.why}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << input << ": " << img.width << "x" << img.height << ", " << img.parts << " part"
            << (img.parts > 1 ? "s" : "") << ", " << img.channels.size() << " channels\n";
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
  std::cout << "effects:\n";
  for (const auto& e : caps) {
    std::cout << "  " << std::left << std::setw(14) << e.effect
              << (e.runs ? (e.why.empty() ? "can run" : "can run: " + e.why) : "cannot run: " + e.why) << "\n";
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

int cmd_devices() {
  auto devs = isg::gpu::list_devices();
  for (const auto& d : devs) {
    std::cout << d.index << ": " << d.name << " (" << d.type_name << ", Vulkan "
              << VK_API_VERSION_MAJOR(d.api_version) << "." << VK_API_VERSION_MINOR(d.api_version)
              << ", " << (d.device_local_bytes >> 20) << " MiB, timestamps "
              << (d.timestamps ? "yes" : "no") << ")\n";
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
                 "(lib/effects/params.cpp). Set them in a preset's `[section]` or with "
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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"isg: soft shadows, glossy reflections and depth of field from a renderer's AOVs"};
  app.set_version_flag("--version", ISG_VERSION);
  app.require_subcommand(1);

  RunArgs ra;
  auto* run = app.add_subcommand("run", "process an AOV EXR and write the composite");
  run->add_option("input", ra.input, "input AOV EXR");
  run->add_option("-o,--output", ra.output, "output EXR");
  add_common(run, ra.common);
  run->add_option("--device", ra.device, "device index or name (see `isg devices`)");
  run->add_flag("--require-gpu", ra.require_gpu, "fail when only a CPU Vulkan device exists");
  run->add_flag("--timings", ra.timings, "print GPU time per pass and wall time per stage");
  run->add_flag("--dry-run", ra.dry_run, "print the plan (passes, resources) and stop");
  run->add_flag("--print-preset", ra.print_preset, "print every parameter's value as TOML and stop");
  run->add_option("--compression", ra.compression, "EXR compression (output.compression)");
  run->add_flag("--no-clobber", ra.no_clobber, "fail rather than replace an existing output");
  run->add_flag("--validation", ra.validation, "enable the Khronos validation layer");
  run->add_option("--preview", ra.preview,
                  "also write a display picture (.png/.jpg) of the composite through the "
                  "OpenColorIO view transform ($OCIO, or the built-in sRGB config)");
  run->add_option("--frames", ra.frames,
                  "frame range for a sequence: A-B, A-BxSTEP, or a list (input and -o hold #### or %04d)");
  run->add_flag("--skip-existing", ra.skip_existing, "sequence: leave frames whose output exists (resume)");
  run->add_flag("--keep-going", ra.keep_going,
                "sequence: report a bad frame and go on (exit 3 if any failed)");
  run->add_option("--input-colorspace", ra.input_colorspace,
                  "colour space of a beauty that is not scene-linear (an OpenColorIO name)");

  Common ic;
  std::string info_input;
  bool info_json = false;
  auto* info = app.add_subcommand("info", "roles found, channels, camera, which effects can run");
  info->add_option("input", info_input, "AOV EXR")->required();
  add_common(info, ic);
  info->add_flag("--json", info_json, "machine-readable output");

  std::string ca, cb, cmask;
  std::vector<std::string> cchan;
  bool cjson = false;
  auto* cmp = app.add_subcommand("compare", "error metrics of A against B, per channel");
  cmp->add_option("a", ca, "image")->required();
  cmp->add_option("b", cb, "reference")->required();
  cmp->add_option("--mask", cmask, "CHANNEL (in B, else A) or FILE:CHANNEL selecting the pixels to count");
  cmp->add_option("--channels", cchan, "channels to compare (default: all both have)")->delimiter(',');
  cmp->add_flag("--json", cjson, "machine-readable output");
  std::string cheat;
  double cheat_max = 0;
  cmp->add_option("--heatmap", cheat, "write an error heat-map picture (.png/.jpg)");
  cmp->add_option("--heatmap-max", cheat_max, "error shown as full scale (default: 99th percentile)");

  auto* devices = app.add_subcommand("devices", "list Vulkan devices");
  auto* presets = app.add_subcommand("presets", "list shipped presets");
  bool params_md = false;
  auto* params_cmd = app.add_subcommand("params", "list every parameter with its default, range and help");
  params_cmd->add_flag("--markdown", params_md, "as the Markdown table in docs/parameters.md");

  isg::roofline::Options rl;
  std::string rl_device;
  bool rl_json = false;
  auto* roofline = app.add_subcommand(
      "roofline", "time a plain cross-bilateral gather (the yardstick for the gather passes), in taps/s");
  roofline->add_option("--width", rl.width, "image width")->check(CLI::Range(1, 65536));
  roofline->add_option("--height", rl.height, "image height")->check(CLI::Range(1, 65536));
  roofline->add_option("--taps", rl.taps, "taps per pixel, odd squares (default 49,81)")->delimiter(',');
  roofline->add_option("--radius", rl.radii, "gather radii in pixels (default 4,8,16,32,64)")->delimiter(',');
  roofline->add_option("--repeats", rl.repeats, "timed dispatches per row after a warm-up; the best counts")
      ->check(CLI::Range(1, 1000));
  roofline->add_option("--device", rl_device, "device index or name (see `isg devices`)");
  roofline->add_flag("--json", rl_json, "one JSON object");

  isg::cli::FarmCommand farm(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Any bad command line exits 2 (docs/farm.md), whichever CLI11 error it was.
    return app.exit(e) == 0 ? 0 : kUsage;
  }
  try {
    if (*run) return cmd_run(ra);
    if (*info) return cmd_info(ic, info_input, info_json);
    if (*cmp) return cmd_compare(ca, cb, cmask, cchan, cjson, cheat, cheat_max);
    if (*devices) return cmd_devices();
    if (*presets) return cmd_presets();
    if (*params_cmd) return cmd_params(params_md);
    if (*roofline) return cmd_roofline(rl, rl_device, rl_json);
    if (farm.parsed()) return farm.run();
  } catch (const std::bad_alloc&) {
    std::cerr << "isg: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::string msg = e.what();
    auto nl = msg.find('\n');
    if (nl != std::string::npos) msg.resize(nl);
    std::cerr << "isg: error: " << msg << "\n";
    return 1;
  }
  return 0;
}
