#include "effects/effect.h"

#include <algorithm>
#include <stdexcept>

#include "effects/registry.h"

namespace isg::effects {

void PlanOut::need(const std::string& name, int planes, bool upload) {
  for (const auto& r : resources_)
    if (r.name == name) return;
  resources_.push_back({name, planes, upload, plane_bytes_ * uint64_t(planes)});
}

void PlanOut::buffer(const std::string& name, uint64_t bytes, uint64_t range) {
  resources_.push_back({name, 1, false, bytes, range});
}

int PlanOut::add(std::shared_ptr<Instance> inst) {
  instances_.push_back(std::move(inst));
  return int(instances_.size()) - 1;
}

void PlanOut::pass(const std::string& effect, int inst, std::string name, std::string label,
                   std::vector<std::string> reads, std::vector<std::string> writes,
                   std::string light) {
  passes_.push_back({std::move(name), std::move(label), std::move(reads), std::move(writes),
                     std::move(light), effect, inst});
}

double Report::get(const std::string& name) const {
  for (const auto& [k, v] : sums)
    if (k == name) return v;
  for (const auto& [k, v] : maxima)
    if (k == name) return v;
  throw std::logic_error("report " + key + " has no figure " + name);
}

void Report::merge(const Report& o) {
  auto slot = [](std::vector<std::pair<std::string, double>>& v, const std::string& k) {
    for (auto& e : v)
      if (e.first == k) return &e.second;
    return static_cast<double*>(nullptr);
  };
  for (const auto& e : o.sums) {
    if (double* x = slot(sums, e.first)) *x += e.second;
    else sums.push_back(e);
  }
  for (const auto& e : o.maxima) {
    if (double* x = slot(maxima, e.first)) *x = std::max(*x, e.second);
    else maxima.push_back(e);
  }
}

#define ISG_DECLARE_EFFECT(name) const Effect& name##_effect();
ISG_EFFECTS(ISG_DECLARE_EFFECT)
#undef ISG_DECLARE_EFFECT

const std::vector<const Effect*>& all_effects() {
#define ISG_LIST_EFFECT(name) &name##_effect(),
  static const std::vector<const Effect*> all = {ISG_EFFECTS(ISG_LIST_EFFECT)};
#undef ISG_LIST_EFFECT
  return all;
}

const Effect& effect_named(const std::string& name) {
  for (const Effect* e : all_effects())
    if (name == e->name()) return *e;
  throw std::logic_error("no effect named " + name + " (lib/effects/registry.h)");
}

}  // namespace isg::effects
