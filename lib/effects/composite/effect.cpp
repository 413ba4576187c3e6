// The composite (AOV_CONTRACT.md "Output"): the target every effect adds its term to starts as
// the beauty, and pass foreground marks the pixels effects may touch. It runs first; the
// terms C += W·(X − Y) are this effect's passes in the plans of the effects that add them.
#include "effects/composite/effect.h"

#include "isg_io.h"

namespace isg::effects {

std::vector<float> foreground_reference(const float* alpha, const float* depth, size_t n) {
  std::vector<float> fg(n, 1.0f);
  for (size_t i = 0; i < n; ++i) {
    bool bg = false;
    if (alpha) bg = bg || alpha[i] == 0.0f;
    if (depth) bg = bg || depth[i] <= 0.0f || double(depth[i]) >= ISG_BACKGROUND_DEPTH;
    fg[i] = bg ? 0.0f : 1.0f;
  }
  return fg;
}

std::vector<float> foreground_of(const io::Image& img, const io::Roles& roles) {
  const size_t n = img.pixels();
  std::vector<float> beauty, depth;
  const io::RoleBinding* b = roles.get("beauty");
  if (b && b->components() == 4) beauty = io::gather_role(img, *b, 4);
  if (const io::RoleBinding* d = roles.get("depth")) depth = io::gather_role(img, *d, 1);
  return foreground_reference(beauty.empty() ? nullptr : beauty.data() + 3 * n,
                              depth.empty() ? nullptr : depth.data(), n);
}

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
