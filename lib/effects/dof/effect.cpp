// Depth of field, last, on the finished composite (AOV_CONTRACT.md "Output"): the parameter
// table, what the inputs allow, the plan (dof.coc, dof.tiles, then dof.search + dof.gather or
// dof.layered) and the statistics in words. No Vulkan (recorder.cpp records the passes).
#include <cstdio>

#include "effects/dof/instance.h"
#include "effects/dof/params.h"

namespace isg::effects {

namespace {

class Dof final : public Effect {
 public:
  const char* name() const override { return "dof"; }
  Stage stage() const override { return Stage::composite; }

  std::vector<params::Def> params() const override {
    return {
      params::def(dof_keys::method, "none", {"none", "isg", "layered"},
       "depth-of-field method, applied last on the composite (needs depth and the camera): isg "
       "(the paper's parameter search and gather, eq. 15-17), layered (near and far fields "
       "gathered apart, the near field composited over the far by its coverage)"),
      params::def(dof_keys::samples, "64", 1, 1024,
       "samples per pixel per gather pass, rounded to a square grid through the concentric disk "
       "map (rotated per pixel); layered takes at most this many: ceil(2 R)^2, at least 9, in a "
       "tile whose largest CoC is R pixels"),
      params::def(dof_keys::focus_distance, "0", 0, 1e9,
       "focus distance z_f of eq. 15 (0: the camera's focus_distance)", "scene units"),
      params::def(dof_keys::fstop, "0", 0, 1024, "f-number (0: the camera's fstop)"),
      params::def(dof_keys::coc_infinity, "0", 0, 1024,
       "c_inf of eq. 15, the CoC radius at infinity (0: thin lens from focal length, f-stop, "
       "focus distance, sensor width and image width)", "pixels"),
      params::def(dof_keys::coc_scale, "1", 0, 100, "multiplies every circle of confusion"),
      params::def(dof_keys::max_coc, "32", 0.5, 256,
       "largest CoC radius; nearer points are clamped to it", "pixels"),
      params::def(dof_keys::aperture, "disk", {"disk", "polygon"},
       "aperture (bokeh) shape: the gathers' spatial weight"),
      params::def(dof_keys::blades, "6", 3, 16, "blades of a polygon aperture"),
      params::def(dof_keys::rotation, "0", -360, 360, "rotation of a polygon aperture",
       "degrees"),
      params::def(dof_keys::anamorphic, "1", 0.25, 4,
       "anamorphic squeeze: the aperture s times as tall as wide (an anamorphic lens's oval "
       "bokeh; 2 for a 2x lens), of the round aperture's area; below 1, wider than tall"),
      params::def(dof_keys::coc_source, "camera", {"camera", "depth", "channel"},
       "where the circle of confusion comes from: camera (eq. 15 from depth and the camera's "
       "lens, with the overrides above), depth (eq. 15 from depth with dof.focus_distance and "
       "dof.coc_infinity, no camera needed), channel (a CoC the renderer or an earlier isg run "
       "wrote, role coc: signed radius in pixels, near negative, times dof.coc_scale; no depth "
       "needed)"),
      params::def(dof_keys::depth_form, "planar", {"planar", "normalized", "inverse"},
       "how the depth channel holds depth: planar (distance along the view axis, the contract's "
       "Z), normalized (0 at dof.depth_near, 1 at dof.depth_far, 1 and beyond background), "
       "inverse (1/Z: far is 0)"),
      params::def(dof_keys::depth_near, "0.1", 0, 1e9, "dof.depth_form=normalized: the depth at 0",
       "scene units"),
      params::def(dof_keys::depth_far, "100", 0, 1e12, "dof.depth_form=normalized: the depth at 1",
       "scene units"),
      params::def(dof_keys::tile_skip, "true",
       "16x16 tiles whose CoC range is under half a pixel take the cheap path (a plain aperture "
       "average)"),
  };
  }

  std::vector<EffectStatus> capabilities(const io::Roles& roles, const io::Scene&,
                                         bool has_camera) const override {
    EffectStatus st{"dof", false, "", ""};
    // With depth and a camera, as the default dof.coc_source = camera asks; else what another
    // source needs.
    if (!roles.has("beauty")) {
      st.why = "missing beauty";
    } else if (roles.has("depth") && has_camera) {
      st.runs = true;
    } else if (roles.has("coc")) {
      st.runs = true;
      st.why = "with dof.coc_source=channel (role coc)";
    } else if (!roles.has("depth")) {
      st.why = "missing depth (or a CoC channel: dof.coc_source=channel)";
    } else {
      st.why = "no camera (scene file, or worldToCamera/worldToNDC in the header); dof.coc_source=depth "
               "runs without one";
    }
    return {st};
  }

  void plan(const PlanContext& c, PlanOut& out) const override {
    EffectStatus st{"dof", false, c.p.get(dof_keys::method), ""};
    const std::string source = c.p.get(dof_keys::coc_source);
    if (st.method == "none") st.why = "dof.method = none";
    else if (source == "channel" && !c.roles.has("coc"))
      st.why = "dof.coc_source = channel: missing channels for role coc (--channel coc=NAME)";
    else if (source != "channel" && !c.roles.has("depth")) st.why = "missing channels for role depth";
    else if (source == "camera" && !c.camera)
      st.why = "no camera (scene file, or worldToCamera/worldToNDC in the header); dof.coc_source = "
               "depth runs without one";
    else if (source == "depth" && !(c.p.get(dof_keys::focus_distance) > 0 && c.p.get(dof_keys::coc_infinity) > 0))
      st.why = "dof.coc_source = depth needs dof.focus_distance and dof.coc_infinity (no lens to take them from)";
    else if (c.p.get(dof_keys::depth_form) == "normalized" && !(c.p.get(dof_keys::depth_far) > c.p.get(dof_keys::depth_near)))
      st.why = "dof.depth_form = normalized needs dof.depth_far > dof.depth_near";
    else st.runs = true;
    out.status(st);
    if (!st.runs) return;
    auto inst = make_instance<DofInstance>("dof", "dof");
    // The camera's lens only for dof.coc_source = camera; else the parameters alone.
    io::Camera cc = source == "camera" ? *c.camera : io::Camera{};
    cc.width = c.view_w();  // CoC in pixels of the frame
    inst->s = dof_settings(cc, c.scene.units, c.p);
    const int k = out.add(inst);
    if (source == "channel") out.need("coc", 1, true);  // the renderer's CoC, uploaded
    out.need("dof.coc", 1, false);
    out.need("dof.input", 4, false);
    out.buffer("dof.tiles", uint64_t(dof_tiles_x(uint32_t(c.width))) *
                                uint64_t(dof_tiles_y(uint32_t(c.height))) * 4 * sizeof(float));
    out.pass("dof", k, "dof.coc", "dof.coc", {"composite", source == "channel" ? "coc" : "depth"},
             {"dof.coc", "dof.input"});
    out.pass("dof", k, "dof.tiles", "dof.tiles", {"dof.coc"}, {"dof.tiles"});
    if (st.method == "isg") {
      out.need("dof.radius", 1, false);
      out.pass("dof", k, "dof.search", "dof.search", {"dof.coc", "dof.tiles"}, {"dof.radius"});
      out.pass("dof", k, "dof.gather", "dof.gather",
               {"dof.input", "dof.coc", "dof.tiles", "dof.radius"}, {"composite"});
    } else {
      out.pass("dof", k, "dof.layered", "dof.layered", {"dof.input", "dof.coc", "dof.tiles"},
               {"composite"});
    }
  }

  std::vector<std::string> describe(const Report& r) const override {
    char b[64];
    std::snprintf(b, sizeof b, "%.3f", r.get("cheap") / r.get("tiles") * 100.0);
    return {std::string("dof: ") + b + "% of tiles took the cheap path"};
  }
};

}  // namespace

const Effect& dof_effect() {
  static const Dof e;
  return e;
}

}  // namespace isg::effects
