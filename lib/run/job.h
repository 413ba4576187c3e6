// One frame of `isg run`, split into stages so a frame sequence can overlap them:
// load (read, roles, plan, sanitise) on a reader thread, process on the device, write on a
// writer thread. The device is set up once per job, not per frame.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "gpu/gpu.h"
#include "io/image.h"
#include "io/roles.h"
#include "io/scene.h"
#include "params/params.h"
#include "plan/plan.h"
#include "run/run.h"

namespace isg::run {

struct JobConfig {
  io::Scene scene;
  std::string scene_path;
  params::Params params;
  io::RoleRequest request;
  io::ReadLimits limits;
  io::WriteOptions write;
  std::string input_colorspace;  // empty: the beauty is scene-linear
  std::string version;
};

struct LoadedFrame {
  std::string input;
  io::Image img;
  io::Roles roles;
  plan::Plan plan;
  std::optional<io::Camera> camera;  // the scene file's, else the EXR header's
  std::vector<io::NonFinite> nonfinite;
  std::set<std::string> warnings;  // from the load stage (e.g. NaN depths in a shadow map)
  std::string positions;  // where input.positions took positions from other than P (isg:positions)
  // Positions refitted into a planar depth (run/positions.h; 0: not): the window's radius, and
  // the bindings the refit reads, P's (unset: from Z) and the input's depth (if any); the depth
  // role is then effects::kRefitChannel, added to img by the load stage and taken out again
  // after processing.
  int refit_radius = 0;
  std::optional<io::RoleBinding> refit_position, refit_depth;
  effects::Choices choices;  // the effects' choices from the pixels (shadows.method = auto)
  double read_ms = 0;
  double refit_ms = 0;  // the refit's wall time (refit_radius > 0)
};

// The refitted planar depth (LoadedFrame::refit_radius) into the image, once its pixels are
// read (the load stage does it; `isg info` too): a no-op where nothing is refitted.
void refit_positions(LoadedFrame& f);
// Header, roles and plan only (for --dry-run and for checks before any pixels are read).
LoadedFrame plan_frame(const JobConfig& job, const std::string& input);
// Reads the pixels too, and what the effects read besides (shadow maps): the load stage.
// Throws IoError on anything wrong with the input.
LoadedFrame load_frame(const JobConfig& job, const std::string& input);
// The same for an image already in memory (the Python module's arrays); `name` stands for the
// file in errors and in the isg:input provenance.
LoadedFrame plan_image_frame(const JobConfig& job, io::Image img, const std::string& name);
LoadedFrame load_image_frame(const JobConfig& job, io::Image img, const std::string& name);
// Runs the plan on the device and adds the output channels and provenance to frame.img.
Stats process_frame(Runner& runner, const JobConfig& job, LoadedFrame& frame);
Stats process_frame(gpu::Context& ctx, const JobConfig& job, LoadedFrame& frame);
// Atomic write; returns the wall time in ms.
double write_frame(const JobConfig& job, const LoadedFrame& frame, const std::string& output);



}  // namespace isg::run
