// The composite (AOV_CONTRACT.md "Output"): the target every effect adds its term to starts as
// the beauty, and pass foreground marks the pixels effects may touch. It runs first; the
// terms C += W·(X − Y) are this effect's passes in the plans of the effects that add them.
#include "effects/composite/effect.h"

namespace isg::effects {

namespace {
class Composite final : public Effect {
 public:
  const char* name() const override { return "composite"; }
  std::vector<params::Def> params() const override { return {}; }
  std::vector<EffectStatus> capabilities(const io::Roles&, const io::Scene&, bool) const override {
    return {};
  }
  void plan(const PlanContext& c, PlanOut& out) const override {
    const int inst = out.add(make_instance("composite", "composite"));
    out.need("composite", 4, true);
    std::vector<std::string> fg_reads = {"composite"};
    if (c.roles.has("depth")) {
      out.need("depth", 1, true);
      fg_reads.push_back("depth");
    }
    out.need("fg", 1, false);
    out.pass("composite", inst, "foreground", "foreground", fg_reads, {"fg"});
  }
};
}  // namespace

void plan_composite_term(PlanOut& out, int inst, const std::string& label, const std::string& W,
                         const std::string& X, const std::string& Y, const std::string& light) {
  out.pass("composite", inst, "composite_term", label, {"composite", W, X, Y, "fg"}, {"composite"},
           light);
}

const Effect& composite_effect() {
  static const Composite e;
  return e;
}

}  // namespace isg::effects
