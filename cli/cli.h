// The `isg` executable's shared pieces: the options every subcommand takes, turned into
// parameters, the scene and role requests (parsing only; the work is in lib/).
#pragma once

#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "io/image.h"
#include "io/roles.h"
#include "io/scene.h"
#include "params/params.h"
#include "roofline/roofline.h"
#include "run/options.h"

#ifndef ISG_VERSION
#define ISG_VERSION "0.0.0"
#endif

namespace isg::cli {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t);

// Exit status a farm manager can act on.
enum Exit { kOk = 0, kError = 1, kUsage = 2, kSomeFramesFailed = 3 };

// Shipped presets: $ISG_PRESET_PATH (colon-separated), <exe>/../share/isg/presets, the source tree.
std::vector<std::filesystem::path> preset_dirs();

struct Common {
  std::string scene;
  std::string preset;
  std::vector<std::string> sets;
  std::vector<std::string> channels;
  std::string layer;
};

void add_common(CLI::App* app, Common& c);
// The options as lib/run assembles a job from them (run::make_job, as the Python module does).
run::JobOptions job_options(const Common& c, const std::string& compression);
io::ReadLimits limits_of(const params::Params& p);
std::string join(const std::vector<std::string>& v, const char* sep = " ");

// ---- isg run ----

struct RunArgs {
  Common common;
  std::string input, output, device, compression, preview, focus_view, input_colorspace, frames;
  bool require_gpu = false, timings = false, dry_run = false, print_preset = false;
  bool no_clobber = false, validation = false, skip_existing = false, keep_going = false;
};
int cmd_run(const RunArgs& a);

// ---- the other subcommands ----

int cmd_info(const Common& c, const std::string& input, bool as_json);
int cmd_compare(const std::string& a_path, const std::string& b_path, const std::string& mask_name,
                const std::vector<std::string>& channels, bool as_json,
                const std::string& heatmap_path, double heatmap_max);
int cmd_roofline(const roofline::Options& opt, const std::string& device, bool as_json);
std::string version_text();
int cmd_devices();
int cmd_params(bool markdown);
int cmd_presets();

}  // namespace isg::cli
