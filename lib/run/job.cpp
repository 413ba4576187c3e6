#include "run/job.h"

#include "io/color.h"

#include <chrono>
#include <cstdio>
#include <regex>
#include <stdexcept>

namespace isg::run {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

LoadedFrame plan_frame(const JobConfig& job, const std::string& input) {
  LoadedFrame f;
  f.input = input;
  auto header = io::read_exr_header(input, job.limits);
  // The scene file's lights, unless the caller named them.
  io::RoleRequest req = job.request;
  if (req.light_names.empty())
    for (const auto& l : job.scene.lights) req.light_names.push_back(l.name);
  f.roles = io::resolve_roles(header.channel_names(), req, input);
  for (const auto& [role, name] : job.request.overrides) {
    if (!io::is_known_role(role, f.roles.lights)) {
      auto how = job.request.override_how.find(role);
      throw io::IoError((how == job.request.override_how.end() ? "--channel" : how->second) +
                        ": " + role + "=" + name + ": unknown role " + role);
    }
  }
  f.camera = job.scene.camera;
  if (!f.camera) f.camera = io::camera_from_header(header);
  f.plan = plan::make_plan(f.roles, job.scene, job.params, header.width, header.height,
                           f.camera ? &*f.camera : nullptr);
  f.img = std::move(header);
  return f;
}

LoadedFrame load_frame(const JobConfig& job, const std::string& input) {
  LoadedFrame f = plan_frame(job, input);
  if (!f.plan.missing.empty()) {
    throw io::IoError(input + ": missing required channels for role " + f.plan.missing.front());
  }
  auto t = Clock::now();
  f.img = io::read_exr(input, job.limits);
  f.read_ms = std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  f.nonfinite = io::sanitize(f.img);
  if (!job.input_colorspace.empty()) {
    const auto& rgb = f.roles.get("beauty")->terms.front();
    io::to_scene_linear(f.img, {rgb[0], rgb[1], rgb[2]}, job.input_colorspace);
    f.img.attributes.attribute("isg:input_colorspace", job.input_colorspace);
  }
  return f;
}

Stats process_frame(gpu::Context& ctx, const JobConfig& job, LoadedFrame& f) {
  Stats st = execute(ctx, f.plan, f.roles, f.img);
  // Provenance: tool version, device, preset, every parameter.
  auto& a = f.img.attributes;
  a.attribute("isg:version", job.version);
  a.attribute("isg:device", ctx.info().name + " (" + ctx.info().type_name + ")");
  a.attribute("isg:preset", job.params.preset_name());
  for (const auto& d : job.params.defs()) a.attribute("isg:param:" + d.key, job.params.text(d.key));
  a.attribute("isg:input", fs::absolute(f.input).string());
  if (!job.scene_path.empty()) a.attribute("isg:scene", fs::absolute(job.scene_path).string());
  return st;
}

double write_frame(const JobConfig& job, const LoadedFrame& f, const std::string& output) {
  auto t = Clock::now();
  std::error_code ec;
  if (fs::exists(output, ec) && fs::equivalent(f.input, output, ec)) {
    throw io::IoError(output + ": is the input file; isg never overwrites its input");
  }
  io::write_exr(output, f.img, job.write);
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

namespace {
const std::regex kHashes("#+");
const std::regex kPrintf("%0?([0-9]*)d");
}  // namespace

bool is_sequence_pattern(const std::string& path) {
  std::string name = fs::path(path).filename().string();
  return std::regex_search(name, kHashes) || std::regex_search(name, kPrintf);
}

std::string expand_pattern(const std::string& pattern, int frame) {
  std::smatch m;
  std::string out = pattern;
  auto pad = [&](int width) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%0*d", width, frame);
    return std::string(buf);
  };
  if (std::regex_search(pattern, m, kHashes)) {
    out = m.prefix().str() + pad(int(m.length(0))) + m.suffix().str();
  } else if (std::regex_search(pattern, m, kPrintf)) {
    int width = m[1].length() ? std::stoi(m[1].str()) : 0;
    out = m.prefix().str() + pad(width) + m.suffix().str();
  }
  return out;
}

std::vector<int> parse_frames(const std::string& spec) {
  std::vector<int> frames;
  static const std::regex item(R"(\s*(-?\d+)(?:\s*-\s*(-?\d+)(?:x(\d+))?)?\s*)");
  size_t start = 0;
  while (start <= spec.size()) {
    size_t comma = spec.find(',', start);
    std::string part = spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    std::smatch m;
    if (!std::regex_match(part, m, item)) {
      throw std::invalid_argument("--frames " + spec + ": '" + part + "' is not N, A-B or A-BxS");
    }
    int a = std::stoi(m[1].str());
    int b = m[2].matched ? std::stoi(m[2].str()) : a;
    int step = m[3].matched ? std::stoi(m[3].str()) : 1;
    if (b < a || step < 1) throw std::invalid_argument("--frames " + spec + ": '" + part + "' is empty");
    if ((int64_t(b) - a) / step > 1000000) throw std::invalid_argument("--frames " + spec + ": too many frames");
    for (int f = a; f <= b; f += step) frames.push_back(f);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return frames;
}

}  // namespace isg::run
