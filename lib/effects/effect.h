// The effect interface (after NRD's per-method dispatch descriptions and Filament's frame
// graph). Each folder under lib/effects/ supplies one Effect: its parameter table, its
// capability check with the reason, and its planner, which adds passes and named resources to
// the plan. The GPU side (effects/recorder.h) records those passes against the named
// resources. The planner (lib/plan), the runner (lib/run), the statistics and the tiling loop
// go through this interface and name no effect. No Vulkan here.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "effects/view.h"
#include "io/roles.h"
#include "io/scene.h"
#include "params/params.h"

namespace isg::io {
struct Image;
}

namespace isg::effects {

// A GPU buffer the passes share, by name: a role ("beauty", "key.shadow") uploaded from the
// input, or a product ("fg", "key.softshadow", "dof.tiles").
struct Resource {
  std::string name;
  int planes = 1;
  bool upload = false;  // filled from the input image
  uint64_t bytes = 0;
  uint64_t range = 0;  // the most bytes a pass binds of it as one storage buffer (0: bytes)
};

struct Pass {
  std::string name;    // kernel stage, e.g. "shadows.hard"
  std::string label;   // name in timings and statistics, e.g. "shadows.hard[key]"
  std::vector<std::string> reads, writes;
  std::string light;   // for per-light passes
  std::string effect;  // the effect whose recorder records it ("composite" for the terms)
  int instance = -1;   // the effect instance (Plan::instances) it belongs to
};

struct EffectStatus {
  std::string effect;  // "shadows[key]", "reflections", "dof"
  bool runs = false;
  std::string method;
  std::string why;     // why it cannot or does not run
};

// One application of an effect in a plan (shadows: one per light): the settings its planner
// resolved, kept for its passes. Each effect derives its own.
struct Instance {
  virtual ~Instance() = default;
  std::string effect;  // registry name
  std::string key;     // status name, e.g. "shadows[key]"; tiles match instances by it
  // How far (pixels) its passes read around a pixel, for the apron of a tile.
  virtual double reach() const { return 0.0; }
  // A tile of a larger frame: the settings take the window.
  virtual void set_window(const Window&) {}
};

template <class T = Instance>
std::shared_ptr<T> make_instance(const std::string& effect, const std::string& key) {
  auto i = std::make_shared<T>();
  i->effect = effect;
  i->key = key;
  return i;
}

// What an effect chose from a frame's pixels for a setting left to it (shadows.method = auto),
// by name (e.g. "shadows[key]" -> "pcss", "shadows[key]/why" -> the reason): made once per frame
// after the pixels are read, and taken by every plan of that frame (its tiles' too).
using Choices = std::map<std::string, std::string>;

// What the planner gives every effect.
struct PlanContext {
  const io::Roles& roles;
  const io::Scene& scene;
  const params::Params& p;
  int width = 0, height = 0;
  const io::Camera* camera = nullptr;  // the given camera, else the scene file's (may be null)
  Window window;
  const Choices* choices = nullptr;  // null until the frame's pixels are read
  const std::string* choice(const std::string& key) const {
    if (!choices) return nullptr;
    auto it = choices->find(key);
    return it == choices->end() ? nullptr : &it->second;
  }
  int view_w() const { return window.whole() ? width : window.frame_w; }
  int view_h() const { return window.whole() ? height : window.frame_h; }
  // "position" when the input has P, else "depth" (with its plane count).
  std::string geo() const { return roles.has("position") ? "position" : "depth"; }
  int geo_planes() const { return roles.has("position") ? 3 : 1; }
};

// What an effect's planner writes into (the plan's resources, passes, statuses, instances).
class PlanOut {
 public:
  PlanOut(std::vector<Resource>& r, std::vector<Pass>& p, std::vector<EffectStatus>& s,
          std::vector<std::shared_ptr<Instance>>& i, uint64_t plane_bytes)
      : resources_(r), passes_(p), statuses_(s), instances_(i), plane_bytes_(plane_bytes) {}
  // An image-sized resource of `planes` planes (once per name).
  void need(const std::string& name, int planes, bool upload);
  // A resource of a given size (tile grids, shadow maps).
  // `range`: the most bytes a pass binds as one storage buffer, where less than all of them.
  void buffer(const std::string& name, uint64_t bytes, uint64_t range = 0);
  void status(EffectStatus s) { statuses_.push_back(std::move(s)); }
  // Adds the instance; returns its index for its passes.
  int add(std::shared_ptr<Instance> inst);
  // A pass recorded by `effect`'s recorder, belonging to instance `inst`.
  void pass(const std::string& effect, int inst, std::string name, std::string label,
            std::vector<std::string> reads, std::vector<std::string> writes,
            std::string light = "");

 private:
  std::vector<Resource>& resources_;
  std::vector<Pass>& passes_;
  std::vector<EffectStatus>& statuses_;
  std::vector<std::shared_ptr<Instance>>& instances_;
  uint64_t plane_bytes_;
};

// An effect instance's statistics after a run (counts add up over tiles; maxima take the
// largest); the effect describes them in words.
struct Report {
  std::string effect, key;
  std::vector<std::pair<std::string, double>> sums, maxima;
  double get(const std::string& name) const;
  void sum(const std::string& name, double v) { sums.emplace_back(name, v); }
  void max(const std::string& name, double v) { maxima.emplace_back(name, v); }
  void merge(const Report& o);
};

// The gather passes' load, for taps/s against the roofline (--timings): pixels that ran the
// search and gather, the lattice samples taken in all (search + gather), and the taps a sample
// is: texel reads each with its own range weight, the roofline's unit (a point sample 1, a
// bilinear one 4).
struct GatherLoad {
  std::string pass;  // the plan's Pass::label (its name in the timings)
  uint64_t pixels = 0, samples = 0;
  uint32_t taps_per_sample = 1;
  std::vector<std::string> dispatches;  // the timings that add to `pass`'s (its other dispatches)
};

// Effects run in two stages: on the input AOVs (their composite terms add up, their reaches
// take the largest), then on the finished composite (each adds its reach).
enum class Stage { inputs, composite };

class Effect {
 public:
  virtual ~Effect() = default;
  virtual const char* name() const = 0;  // its preset section, e.g. "dof"
  virtual Stage stage() const { return Stage::inputs; }
  // Its rows of the parameter table.
  virtual std::vector<params::Def> params() const = 0;
  // Whether the inputs allow it at all, whatever the preset, and why not (`isg info`).
  virtual std::vector<EffectStatus> capabilities(const io::Roles& roles, const io::Scene& scene,
                                                 bool has_camera) const = 0;
  // Statuses, instances, resources and passes for this input and preset.
  virtual void plan(const PlanContext& c, PlanOut& out) const = 0;
  // Settings the preset leaves to the inputs, chosen from the frame's pixels (the whole frame,
  // once); the frame is then planned again with them.
  virtual void choose(const PlanContext& /*c*/, const io::Image& /*img*/, Choices& /*out*/) const {}
  // The load stage: files an instance reads besides the input (a light's shadow map), read
  // once per frame; one warning line each for what was repaired.
  virtual void load(Instance&, std::set<std::string>& /*warnings*/) const {}
  // Tiles: what a tile needs from the whole frame (read from the frame's pixels), kept in the
  // frame's instance, then copied into each tile's instance of the same key.
  virtual void prepare_tiles(Instance& /*frame*/, const io::Image&, const io::Roles&) const {}
  virtual void from_frame(Instance& /*tile*/, const Instance& /*frame*/) const {}
  // Lines for --timings from a report.
  virtual std::vector<std::string> describe(const Report&) const { return {}; }
};

// Every effect, in the order they run (lib/effects/registry.h).
const std::vector<const Effect*>& all_effects();
const Effect& effect_named(const std::string& name);  // throws std::logic_error naming it

}  // namespace isg::effects
