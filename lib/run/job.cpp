#include "run/job.h"

#include "effects/composite/effect.h"
#include "effects/output_params.h"
#include "effects/view.h"
#include "io/color.h"
#include "run/positions.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <new>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace isg::run {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// input.positions (issue 19): positions from P, or from Z and the camera. P's float32 step
// (2^-23 of its magnitude rounded down to a power of two, which far from the world origin is the
// eye's) wider than a pixel at a scene radius from the camera misplaces positions by pixels
// (1e6 m from the origin, 6.25 cm against 1.9 cm at 480x270), and past a 16th of one
// (kRefitShare) it tilts the receiver planes the effects take from screen neighbours: there P is
// refitted (run/positions.h) into a planar depth that every effect then takes, with the camera,
// for its positions, depth and foreground. Under that share P stays as it is. Own Cycles renders
// of contact at 480x270,
// ratio to doing nothing from P as stored / P refitted / Z as stored (isg, pcss, vssm, cssm):
// 1e6 m from the origin 0.62 / 0.56 / 0.58, 0.82 / 0.57 / 0.77, 0.82 / 0.56 / 0.76, 0.79 / 0.72 /
// 0.69; the contact case translated by 1e6 (its map exact; at the origin 0.35, 0.23, 0.24, 0.27)
// 0.48 / 0.35 / 0.35, 0.50 / 0.23 / 0.23, 0.44 / 0.24 / 0.24, 0.56 / 0.27 / 0.27 (before the
// narrowed searches); 1e5 m away (step 0.0078 m, 0.41 pixel) the same four from P as stored
// 0.371, 0.249, 0.243, 0.302 and refitted 0.366, 0.249, 0.244, 0.295 (over its whole mask; where
// Cycles does not self-shadow, positions.h). Z (input.positions=Z, or an input without P) is
// refitted the same way where the same step is over that share (below). Said in the output's
// isg:positions (prepare_pixels: the header read here is replaced by the pixels).
void choose_positions(const JobConfig& job, LoadedFrame& f) {
  f.refit_radius = 0;
  f.refit_position.reset();
  f.refit_depth.reset();
  const bool has_p = f.roles.has("position"), has_z = f.roles.has("depth");
  if (!f.camera || (!has_p && !has_z)) return;
  const std::string how = job.params.get(effects::output_keys::positions);
  const auto view = effects::PinholeView::of(*f.camera, std::max(f.img.height, 1));
  const auto& eye = view.eye;
  const double m_p = std::max({std::abs(eye[0]), std::abs(eye[1]), std::abs(eye[2])}) +
                     job.scene.scene_radius;
  const double step = effects::float32_step(m_p);
  const double pixel = job.scene.scene_radius / view.f_px;
  const bool from_z = has_z && (how == "Z" || !has_p);
  std::ostringstream note;
  if (!(step > kRefitShare * pixel)) {
    if (!from_z || !has_p) return;
    f.roles.found.erase("position");
    note << "Z and the camera (input.positions=Z; P's float32 step " << step << " m, a pixel "
         << pixel << " m at a scene radius, Z's step "
         << effects::float32_step(2.0 * job.scene.scene_radius) << " m)";
    f.positions = note.str();
    return;
  }
  // Refitted: from Z as well, which a renderer computes from float32 world positions (Cycles
  // 1e6 m away, isg, pcss, vssm, cssm from Z as stored 0.58, 0.77, 0.76, 0.69 of doing nothing,
  // refitted 0.56, 0.57, 0.56, 0.73; the translated case's exact Z stays: 0.35, 0.23, 0.24, 0.27).
  f.refit_radius = refit_radius(step, pixel);
  if (!from_z) f.refit_position = *f.roles.get("position");
  if (has_z) f.refit_depth = *f.roles.get("depth");
  const char* what = from_z ? "Z" : "P";
  f.roles.found.erase("position");
  f.roles.found["depth"] =
      io::RoleBinding{"depth", {{effects::kRefitChannel}}, std::string(what) + " refitted"};
  const int side = 2 * f.refit_radius + 1;
  note << what << " refitted into a planar depth over " << side << "x" << side
       << " pixels, with the camera (input.positions=" << how
       << "; the float32 step of world positions there " << step << " m, a pixel " << pixel
       << " m at a scene radius)";
  f.positions = note.str();
}

// Roles, camera and plan of f.img (its header at least), whose file or name is f.input.
void plan_image(const JobConfig& job, LoadedFrame& f) {
  // The scene file's lights, unless the caller named them.
  io::RoleRequest req = job.request;
  if (req.light_names.empty())
    for (const auto& l : job.scene.lights) req.light_names.push_back(l.name);
  f.roles = io::resolve_roles(f.img.channel_names(), req, f.input);
  for (const auto& [role, name] : job.request.overrides) {
    if (!io::is_known_role(role, f.roles.lights)) {
      auto how = job.request.override_how.find(role);
      throw io::IoError((how == job.request.override_how.end() ? "--channel" : how->second) +
                        ": " + role + "=" + name + ": unknown role " + role);
    }
  }
  f.camera = job.scene.camera;
  if (!f.camera) f.camera = io::camera_from_header(f.img);
  choose_positions(job, f);
  f.plan = plan::make_plan(f.roles, job.scene, job.params, f.img.width, f.img.height,
                           f.camera ? &*f.camera : nullptr, {}, f.choices.empty() ? nullptr : &f.choices);
}

// The load stage of the effects: files they read besides the input, once per frame.
void load_effects(LoadedFrame& f) {
  for (auto& i : f.plan.instances) effects::effect_named(i->effect).load(*i, f.warnings);
}

void check_missing(const LoadedFrame& f) {
  if (!f.plan.missing.empty()) {
    throw io::IoError(f.input + ": missing required channels for role " + f.plan.missing.front());
  }
}

// Settings left to the pixels (shadows.method = auto): chosen once from the whole frame, which
// is then planned again with them.
void choose_from_pixels(const JobConfig& job, LoadedFrame& f) {
  f.choices = plan::choose_from_pixels(f.roles, job.scene, job.params, f.img, f.camera ? &*f.camera : nullptr);
  if (f.choices.empty()) return;
  plan_image(job, f);
  check_missing(f);
}

// Pixels as the passes take them: NaN/Inf to 0, the beauty scene-linear.
void prepare_pixels(const JobConfig& job, LoadedFrame& f) {
  f.nonfinite = io::sanitize(f.img);
  refit_positions(f);
  choose_from_pixels(job, f);
  if (!f.positions.empty()) f.img.attributes.attribute("isg:positions", f.positions);
  load_effects(f);
  if (!job.input_colorspace.empty()) {
    const auto& rgb = f.roles.get("beauty")->terms.front();
    io::to_scene_linear(f.img, {rgb[0], rgb[1], rgb[2]}, job.input_colorspace);
    f.img.attributes.attribute("isg:input_colorspace", job.input_colorspace);
  }
}

}  // namespace

// The refitted planar depth (choose_positions) into effects::kRefitChannel: on the foreground as
// the input's own roles give it; the input's depth, else a background depth, elsewhere.
void refit_positions(LoadedFrame& f) {
  if (f.refit_radius == 0) return;
  const auto t = Clock::now();
  io::Roles given = f.roles;
  if (f.refit_position) given.found["position"] = *f.refit_position;
  given.found.erase("depth");
  if (f.refit_depth) given.found["depth"] = *f.refit_depth;
  const std::vector<float> fg = effects::foreground_of(f.img, given);
  std::vector<float> z;
  if (f.refit_depth) z = io::gather_role(f.img, *f.refit_depth, 1);
  const auto view = effects::PinholeView::of(*f.camera, std::max(f.img.height, 1));
  const float* bg = z.empty() ? nullptr : z.data();
  const int w = f.img.width, h = f.img.height, r = f.refit_radius;
  if (f.refit_position) {
    const std::vector<float> P = io::gather_role(f.img, *f.refit_position, 3);
    f.img.set(effects::kRefitChannel, refit_depth(P.data(), fg.data(), w, h, r, view, bg));
  } else {
    f.img.set(effects::kRefitChannel, refit_depth_z(z.data(), fg.data(), w, h, r, view, bg));
  }
  f.refit_ms = std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

namespace {

// An allocation that fails in a stage names the input and the stage (issue 54): "out of memory"
// alone sent users to the output, or nowhere.
template <class F>
auto naming_oom(const std::string& input, const char* stage, F&& f) {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    throw io::IoError(input + ": out of memory while " + stage);
  }
}

}  // namespace

LoadedFrame plan_frame(const JobConfig& job, const std::string& input) {
  LoadedFrame f;
  f.input = input;
  f.img = io::read_exr_header(input, job.limits);
  plan_image(job, f);
  return f;
}

LoadedFrame load_frame(const JobConfig& job, const std::string& input) {
  LoadedFrame f = plan_frame(job, input);
  check_missing(f);
  auto t = Clock::now();
  f.img = io::read_exr(input, job.limits);
  f.read_ms = std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  naming_oom(input, "preparing its pixels", [&] { prepare_pixels(job, f); });
  return f;
}

LoadedFrame plan_image_frame(const JobConfig& job, io::Image img, const std::string& name) {
  LoadedFrame f;
  f.input = name;
  f.img = std::move(img);
  plan_image(job, f);
  return f;
}

LoadedFrame load_image_frame(const JobConfig& job, io::Image img, const std::string& name) {
  LoadedFrame f = plan_image_frame(job, std::move(img), name);
  check_missing(f);
  prepare_pixels(job, f);
  return f;
}

namespace {

// Pixels [x, x + w) x [y, y + h) of every channel.
io::Image crop(const io::Image& img, int x, int y, int w, int h) {
  io::Image c;
  c.path = img.path;
  c.width = w;
  c.height = h;
  c.x0 = img.x0 + x;
  c.y0 = img.y0 + y;
  c.full_x0 = img.full_x0;
  c.full_y0 = img.full_y0;
  c.full_w = img.full_w;
  c.full_h = img.full_h;
  c.parts = img.parts;
  c.attributes = img.attributes;
  for (const auto& ch : img.channels) {
    io::Channel cc{ch.name, ch.storage, std::vector<float>(size_t(w) * size_t(h))};
    for (int r = 0; r < h; ++r)
      std::copy_n(ch.data.begin() + ptrdiff_t(size_t(y + r) * size_t(img.width) + size_t(x)), w,
                  cc.data.begin() + ptrdiff_t(size_t(r) * size_t(w)));
    c.channels.push_back(std::move(cc));
  }
  return c;
}

// The tile edge for this frame: limits.tile_size, or when the plan does not fit the device
// (its memory budget, or its largest storage buffer or texel view) the largest that does; 0: one
// piece.
int tile_edge(const gpu::Context& ctx, const JobConfig& job, const LoadedFrame& f) {
  const int W = f.img.width, H = f.img.height;
  int64_t t = job.params.get(effects::output_keys::tile_size);
  if (t == 0) {
    const auto& info = ctx.info();
    uint64_t largest = 0, largest_range = 0;
    for (const auto& r : f.plan.resources) {
      largest = std::max(largest, r.bytes);
      largest_range = std::max(largest_range, r.range ? r.range : r.bytes);
    }
    const double px = double(W) * double(H);
    // A discrete GPU's memory is shared with the display and other processes: half of it. On
    // unified memory the heap is host memory as the driver states it (lavapipe: a nominal 2 GiB)
    // and the plan may take all of it: a 4K default plan (1.3 GB) then runs in one piece
    // instead of four tiles whose aprons cost half again the GPU time.
    const double share = ctx.unified_memory() ? 1.0 : 0.5;
    const double budget = info.device_local_bytes ? share * double(info.device_local_bytes) : 1e300;
    // The largest range a pass binds as a storage buffer, and the largest buffer as a texel view
    // of 4-byte texels (the gathers read their planes through texel views: gpu.h's Slot::texels).
    const double range = info.max_storage_buffer_range ? double(info.max_storage_buffer_range) : 1e300;
    const double texels = info.max_texel_buffer_elements ? 4.0 * double(info.max_texel_buffer_elements) : 1e300;
    const double fit = std::min({budget / (double(f.plan.gpu_bytes()) / px),
                                 range / (double(largest_range) / px), texels / (double(largest) / px)});
    if (fit >= px) return 0;
    // A piece is the tile and its aprons, each apron the reach in whole 16-pixel steps
    // (execute_tiled): the tile's edge rounds down so that the piece stays within the fit.
    const int64_t apron = (int64_t(f.plan.reach) + 15) / 16 * 16;
    t = std::max<int64_t>(64, (int64_t(std::sqrt(fit)) - 2 * apron) / 16 * 16);
  }
  t = (t + 15) / 16 * 16;
  return t >= std::max(W, H) ? 0 : int(t);
}

// Large plates: tiles of `edge` pixels, each run with its apron (the plan's reach, in whole
// 16-pixel steps so tile grids line up with the frame's) as a window of the frame; the inner
// pixels of every output channel are copied back. GPU times add up per pass; skipped fractions
// are weighted by pixels.
Stats execute_tiled(Runner& runner, const JobConfig& job, LoadedFrame& f, int edge) {
  const int W = f.img.width, H = f.img.height;
  const int apron = (f.plan.reach + 15) / 16 * 16;
  // What a tile needs from the whole frame, effect by effect (shadows.isg: the frame's d_max).
  for (auto& i : f.plan.instances) effects::effect_named(i->effect).prepare_tiles(*i, f.img, f.roles);
  std::map<std::string, io::Channel> out;
  std::vector<std::string> order;
  Stats total;
  int tiles = 0;
  for (int ty = 0; ty < H; ty += edge) {
    for (int tx = 0; tx < W; tx += edge) {
      const int x0 = std::max(0, tx - apron), y0 = std::max(0, ty - apron);
      const int x1 = std::min(W, tx + edge + apron), y1 = std::min(H, ty + edge + apron);
      io::Image piece = crop(f.img, x0, y0, x1 - x0, y1 - y0);
      plan::Plan plan = plan::make_plan(f.roles, job.scene, job.params, x1 - x0, y1 - y0,
                                        f.camera ? &*f.camera : nullptr,
                                        effects::Window{x0, y0, W, H},
                                        f.choices.empty() ? nullptr : &f.choices);
      for (auto& t : plan.instances)
        if (const effects::Instance* fi = f.plan.instance(t->key))
          effects::effect_named(t->effect).from_frame(*t, *fi);
      Stats st = runner.execute(plan, f.roles, piece);
      ++tiles;
      total.add_tile(st);
      // The inner pixels of every channel.
      const int iw = std::min(tx + edge, W) - tx, ih = std::min(ty + edge, H) - ty;
      for (const auto& ch : piece.channels) {
        auto it = out.find(ch.name);
        if (it == out.end()) {
          order.push_back(ch.name);
          it = out.emplace(ch.name, io::Channel{ch.name, ch.storage, std::vector<float>(f.img.pixels())}).first;
        }
        for (int r = 0; r < ih; ++r)
          std::copy_n(ch.data.begin() + ptrdiff_t(size_t(ty - y0 + r) * size_t(x1 - x0) + size_t(tx - x0)),
                      iw, it->second.data.begin() + ptrdiff_t(size_t(ty + r) * size_t(W) + size_t(tx)));
      }
    }
  }
  // Replace the image's channels by the assembled ones, in the order one piece writes them.
  f.img.channels.clear();
  for (const auto& name : order) f.img.channels.push_back(std::move(out.at(name)));
  f.img.attributes.attribute("isg:tiles", std::to_string(tiles) + " tiles of " +
                                              std::to_string(edge) + " px, apron " +
                                              std::to_string(apron) + " px");
  total.tiles = tiles;
  return total;
}
}  // namespace

Stats process_frame(gpu::Context& ctx, const JobConfig& job, LoadedFrame& f) {
  Runner runner(ctx);
  return process_frame(runner, job, f);
}

Stats process_frame(Runner& runner, const JobConfig& job, LoadedFrame& f) {
  gpu::Context& ctx = runner.context();
  load_effects(f);  // a frame from plan_frame: nothing loaded yet (a no-op after load_frame)
  const int edge = tile_edge(ctx, job, f);
  Stats st = naming_oom(f.input, "processing it", [&] {
    return edge > 0 ? execute_tiled(runner, job, f, edge) : runner.execute(f.plan, f.roles, f.img);
  });
  // The refitted depth was the effects' (choose_positions), not an output.
  std::erase_if(f.img.channels, [](const io::Channel& c) { return c.name == effects::kRefitChannel; });
  st.warnings.insert(f.warnings.begin(), f.warnings.end());
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

}  // namespace isg::run
