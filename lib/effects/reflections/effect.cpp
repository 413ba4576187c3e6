// Glossy reflections: the parameter table, what the inputs allow, the plan (reflections.pack,
// reflections.isg for both methods, the composite term) and the statistics in words. No Vulkan
// (recorder.cpp records the passes).
#include <cstdio>

#include "effects/composite/effect.h"
#include "effects/reflections/instance.h"
#include "effects/reflections/params.h"

namespace isg::effects {

namespace {

std::string missing_of(const io::Roles& roles, const std::vector<std::string>& need) {
  std::string m;
  for (const auto& r : need)
    if (!roles.has(r)) m += (m.empty() ? "" : ", ") + r;
  return m;
}

class Reflections final : public Effect {
 public:
  const char* name() const override { return "reflections"; }

  std::vector<params::Def> params() const override {
    return {
      params::def(refl_keys::method, "isg", {"none", "isg", "blur"},
       "glossy reflection method (needs refl, refl.dist, refl.weight, N, P or Z, and the "
       "camera): isg (the paper's parameter search and gather, eq. 4, 10-14), blur (a "
       "constant-width disk blur of refl: the naive alternative, no contact hardening)"),
      params::def(refl_keys::search_samples, "25", 1, 1024,
       "parameter-search samples per pixel, rounded to a square grid through the concentric "
       "disk map (rotated per 4x4 block of pixels)"),
      params::def(refl_keys::gather_samples, "49", 1, 1024,
       "gather samples per pixel, rounded to a square grid (as search_samples)"),
      params::def(refl_keys::roughness, "0.25", 0, 1,
       "GGX perceptual roughness (alpha = r²) where the input has no roughness channel"),
      params::def(refl_keys::roughness_override, "false",
       "use reflections.roughness everywhere, ignoring the roughness channel (for AOVs "
       "rendered with mirror floors)"),
      params::def(refl_keys::energy, "0.99", 0.5, 0.999,
       "fraction E of the GGX lobe inside the cone θ_max: tan(θ_max/2) = alpha·sqrt(E/(1−E))"),
      params::def(refl_keys::a, "1", 0, 1e6,
       "eq. 10: weight of l², the world distance between the two points in scene_radius units"),
      params::def(refl_keys::b, "1", 0, 1e6,
       "eq. 10: weight of n², n = 1 − N_i·N_0"),
      params::def(refl_keys::sigma, "0.01", 1e-9, 1e6,
       "eq. 10: σ of the range function (l measured in units of the scene's scene_radius)"),
      params::def(refl_keys::max_radius, "256", 0.5, 1024,
       "largest search and gather footprint radius (the cone is truncated to fit)", "pixels"),
      params::def(refl_keys::blur_radius, "16", 0, 1024,
       "radius of method blur (16: the best constant radius on the shared case gloss)", "pixels"),
      params::def(refl_keys::search_reach, "true",
       "the parameter search counts only reflections whose own footprint reaches the pixel "
       "(PCSS's blocker test, for reflections)"),
      params::def(refl_keys::search_misses, "false",
       "misses (refl.dist <= 0, infinitely far: eq. 13's limit) take part in the parameter "
       "search"),
      params::def(refl_keys::masking, "true",
       "scale refl.glossy by the rough lobe's directional albedo 1/(1 + 2·Λ(θ_i)) (Smith "
       "masking-shadowing, height-correlated): the energy a single-scattering GGX lobe loses"),
      params::def(refl_keys::anisotropic, "true",
       "elongate the footprint along the screen image of the plane of incidence (eq. 14's cos "
       "applied across it only); false: the paper's round footprint R_g = R_s·cos θ_i"),
  };
  }

  std::vector<EffectStatus> capabilities(const io::Roles& roles, const io::Scene&,
                                         bool has_camera) const override {
    EffectStatus st{"reflections", false, "", ""};
    std::string m = missing_of(roles, {"beauty", "refl", "refl.weight", "refl.dist", "normal"});
    if (!roles.has("position") && !roles.has("depth")) m += std::string(m.empty() ? "" : ", ") + "position or depth";
    if (!m.empty()) st.why = "missing " + m;
    else if (!has_camera) st.why = "no camera (scene file, or worldToCamera/worldToNDC in the header)";
    else st.runs = true;
    return {st};
  }

  void plan(const PlanContext& c, PlanOut& out) const override {
    const auto& roles = c.roles;
    EffectStatus st{"reflections", false, c.p.get(refl_keys::method), ""};
    const io::Camera* cam = c.camera;
    std::string absent = missing_of(roles, {"refl", "refl.dist", "refl.weight", "normal"});
    if (!roles.has("position") && !roles.has("depth"))
      absent += std::string(absent.empty() ? "" : " ") + "position (or depth)";
    if (st.method == "none") st.why = "reflections.method = none";
    else if (!absent.empty()) st.why = "missing channels for role " + absent;
    else if (!cam) st.why = "no camera (scene file, or worldToCamera/worldToNDC in the header)";
    else st.runs = true;
    out.status(st);
    if (!st.runs) return;
    // Pass reflections.isg (both methods: isg and the naive blur), then the composite term
    // refl.weight·(refl.glossy − refl).
    auto inst = make_instance<ReflInstance>("reflections", "reflections");
    inst->s = refl_settings(*cam, c.scene.scene_radius, c.p, c.view_h());
    const int k = out.add(inst);
    out.need("refl", 3, true);
    out.need("refl.dist", 1, true);
    out.need("refl.weight", 3, true);
    out.need("normal", 3, true);
    const std::string geo = c.geo();
    out.need(geo, c.geo_planes(), true);
    std::vector<std::string> reads = {"refl", "refl.dist", "refl.weight", "normal", geo, "fg"};
    if (roles.has("roughness") && !inst->s.roughness_override) {
      out.need("roughness", 1, true);
      reads.push_back("roughness");
    }
    // reflections.pack: the taps' data, two 16-byte texels a pixel and a coarse cell
    // (reflections.isg's input), bound as storage in two ranges, the pixels' the larger.
    const uint32_t w = uint32_t(c.width), h = uint32_t(c.height);
    const uint64_t pack_bytes = refl_pack_texels(w, h) * 16, pixel_bytes = uint64_t(w) * h * 16;
    out.buffer("refl.pack.geo", pack_bytes, pixel_bytes);
    out.buffer("refl.pack.color", pack_bytes, pixel_bytes);
    out.pass("reflections", k, "reflections.pack", "reflections.pack", reads,
             {"refl.pack.geo", "refl.pack.color"});
    reads = {"refl.pack.geo", "refl.pack.color"};
    if (roles.has("roughness") && !inst->s.roughness_override) reads.push_back("roughness");
    out.need("refl.glossy", 3, false);
    out.buffer("refl.tiles", uint64_t(refl_tiles_words(w, h, st.method == "isg")) * 4);
    out.pass("reflections", k, "reflections.isg", "reflections." + st.method, reads,
             {"refl.glossy", "refl.tiles"});
    plan_composite_term(out, k, "composite[reflections]", "refl.weight", "refl.glossy", "refl");
  }

  std::vector<std::string> describe(const Report& r) const override {
    char b[64];
    std::snprintf(b, sizeof b, "%.3f", r.get("skipped") / r.get("tiles") * 100.0);
    return {std::string("reflections: ") + b + "% of tiles had nothing glossy (cheap path)"};
  }
};

}  // namespace

const Effect& reflections_effect() {
  static const Reflections e;
  return e;
}

}  // namespace isg::effects
