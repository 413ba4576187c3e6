#include "effects/params.h"

namespace isg::effects {

using params::Def;
using params::Type;

std::vector<Def> shadows_params() {
  return {
      {"shadows.method", Type::choice, "isg", 0, 0, {"none", "hard", "isg", "pcss", "vssm", "cssm"},
       "soft-shadow method for every light with L.shadow and L.direct: isg (the paper's "
       "parameter search and gather, eq. 4-9; needs P or Z, the camera, the light's scene entry "
       "and L.occluder, which the light's shadow map provides where the input has none), hard (keep the input's hard shadow), pcss (percentage-closer "
       "soft shadows from the light's shadow map, thesis §2.4.2), vssm (variance soft shadow "
       "maps, thesis ch. 7), cssm (convolution soft shadow maps, thesis ch. 5); the shadow-map "
       "methods need P, or Z and the camera, and the light's shadowmap in the scene file", ""},
      {"shadows.search_samples", Type::integer, "25", 1, 1024, {},
       "parameter-search samples per pixel, rounded to a square grid through the concentric "
       "disk map (rotated per pixel)", ""},
      {"shadows.gather_samples", Type::integer, "49", 1, 1024, {},
       "gather samples per pixel, rounded to a square grid (as search_samples)", ""},
      {"shadows.sigma", Type::number, "0.01", 1e-9, 1e6, {},
       "eq. 6: σ of the gaussian range function (l measured in units of the scene's "
       "scene_radius)", ""},
      {"shadows.max_radius", Type::number, "64", 0.5, 1024, {},
       "largest search and gather radius; pixels that need more are clamped and counted "
       "(--timings)", "pixels"},
      {"shadows.rotate", Type::boolean, "true", 0, 0, {},
       "rotate the sample grid per pixel (a hash of the pixel, the same every frame)", ""},
      {"shadows.search_reach", Type::boolean, "true", 0, 0, {},
       "the parameter search counts only occluders whose own penumbra reaches the pixel "
       "(PCSS's blocker test, in image space)", ""},
      {"shadows.tile_skip", Type::boolean, "true", 0, 0, {},
       "16x16 tiles with no shadow boundary within the search radius keep L.shadow (fully lit "
       "or umbra)", ""},
      // Shadow-map methods (lib/effects/shadows/shadowmap.h).
      {"shadows.pcss_taps", Type::integer, "32", 1, 1024, {},
       "pcss: blocker-search and PCF taps per pixel (stratified: rounded to a square grid)", ""},
      {"shadows.pcss_pattern", Type::choice, "stratified", 0, 0, {"stratified", "poisson"},
       "pcss: tap pattern in the disk, rotated per pixel when shadows.rotate is on", ""},
      {"shadows.bias", Type::number, "2", 0, 100, {},
       "shadow-map methods: constant depth bias, in shadow-map texel footprints at the "
       "receiver, on top of the receiver-plane depth (fitted from the screen neighbours)",
       "texels"},
      {"shadows.slope_max", Type::number, "4", 0, 1e3, {},
       "shadow-map methods: the receiver-plane depth may differ from the receiver's by at "
       "most this many texel footprints per texel of lateral offset (grazing-angle clamp)", ""},
      {"shadows.spread_bias", Type::number, "2", 0, 100, {},
       "shadow-map methods: extra depth bias, times the smallest light-depth step from the "
       "pixel to a screen neighbour (large where P blends two surfaces at a silhouette)", ""},
      {"shadows.depth_ulps", Type::number, "1", 0, 1e3, {},
       "shadow-map methods: the map's own precision, added to the receiver's depth uncertainty "
       "(times shadows.spread_bias): this many float32 steps at the light's distance from the "
       "world origin, where the renderer computed the map's depths (negligible near the origin; "
       "6 cm a step at 1e6 m)", "steps"},
      {"shadows.smap_max_radius", Type::number, "64", 0.5, 1024, {},
       "shadow-map methods: largest blocker-search and filter radius; pixels that need more "
       "are clamped and counted (--timings)", "texels"},
      {"shadows.vssm_m", Type::integer, "5", 1, 16, {},
       "vssm: the blocker search's kernel is split into m x m sub-kernels (thesis §7.4.2); 1: "
       "no subdivision", ""},
      {"shadows.vssm_h", Type::integer, "3", 0, 5, {},
       "vssm: height of the quad-tree the filter kernel is subdivided by where it is not "
       "planar (Algorithm 3); 0: no subdivision", ""},
      {"shadows.vssm_leaf_taps", Type::integer, "4", 0, 64, {},
       "vssm: PCF taps (a square grid) in each non-planar leaf sub-kernel; 0: such leaves are "
       "taken as lit, as plain variance shadow maps do", ""},
      {"shadows.vssm_flat", Type::number, "0.0001", 0, 1, {},
       "vssm: a sub-kernel whose mean depth is behind the receiver and whose variance is below "
       "this times scene_radius is fully lit (thesis §7.5.5)", ""},
      {"shadows.vssm_contact", Type::number, "0.01", 0, 1, {},
       "vssm: where the receiver is closer than this times scene_radius behind the mean "
       "blocker, the shadow is a 3x3 PCF (contact shadows, thesis §7.5.4)", ""},
      {"shadows.cssm_order", Type::integer, "8", 1, 16, {},
       "cssm: Fourier terms M of the shadow test's expansion (eq. 5.10); 4, 8 and 16 are "
       "the thesis's settings (8: the best error on the shared contact case, 4M + 1 basis "
       "images)", ""},
      {"shadows.cssm_filter", Type::choice, "sat", 0, 0, {"sat", "mipmap"},
       "cssm: prefiltering of the basis images, summed-area tables or mipmaps (§5.3.1)", ""},
      {"shadows.cssm_max_basis", Type::integer, "1024", 64, 16384, {},
       "cssm: largest side of the basis images, texels; a larger map is box-averaged 2x2 "
       "(exactly, the basis being linear in its texels) until it fits, so 4M + 1 images fit "
       "the device (kernels narrower than the averaged texel lose their detail)", ""},
      {"shadows.cssm_sharpen_a", Type::number, "30", 0, 1e3, {},
       "cssm: A of the sharpening exponent p = 1 + A exp(-B (d - z_avg)) (eq. 5.9); 0: none", ""},
      {"shadows.cssm_sharpen_b", Type::number, "100", 0, 1e6, {},
       "cssm: B of eq. 5.9, per unit of normalised depth (the map's depth range is 1)", ""},
  };
}

std::vector<Def> reflections_params() {
  return {
      {"reflections.method", Type::choice, "isg", 0, 0, {"none", "isg", "blur"},
       "glossy reflection method (needs refl, refl.dist, refl.weight, N, P or Z, and the "
       "camera): isg (the paper's parameter search and gather, eq. 4, 10-14), blur (a "
       "constant-width disk blur of refl: the naive alternative, no contact hardening)", ""},
      {"reflections.search_samples", Type::integer, "25", 1, 1024, {},
       "parameter-search samples per pixel, rounded to a square grid through the concentric "
       "disk map (rotated per pixel)", ""},
      {"reflections.gather_samples", Type::integer, "49", 1, 1024, {},
       "gather samples per pixel, rounded to a square grid (as search_samples)", ""},
      {"reflections.roughness", Type::number, "0.25", 0, 1, {},
       "GGX perceptual roughness (alpha = r²) where the input has no roughness channel", ""},
      {"reflections.roughness_override", Type::boolean, "false", 0, 0, {},
       "use reflections.roughness everywhere, ignoring the roughness channel (for AOVs "
       "rendered with mirror floors)", ""},
      {"reflections.energy", Type::number, "0.99", 0.5, 0.999, {},
       "fraction E of the GGX lobe inside the cone θ_max: tan(θ_max/2) = alpha·sqrt(E/(1−E))",
       ""},
      {"reflections.a", Type::number, "1", 0, 1e6, {},
       "eq. 10: weight of l², the world distance between the two points in scene_radius units",
       ""},
      {"reflections.b", Type::number, "1", 0, 1e6, {},
       "eq. 10: weight of n², n = 1 − N_i·N_0", ""},
      {"reflections.sigma", Type::number, "0.01", 1e-9, 1e6, {},
       "eq. 10: σ of the range function (l measured in units of the scene's scene_radius)", ""},
      {"reflections.max_radius", Type::number, "256", 0.5, 1024, {},
       "largest search and gather footprint radius (the cone is truncated to fit)", "pixels"},
      {"reflections.blur_radius", Type::number, "16", 0, 1024, {},
       "radius of method blur (16: the best constant radius on the shared case gloss)", "pixels"},
      {"reflections.search_reach", Type::boolean, "true", 0, 0, {},
       "the parameter search counts only reflections whose own footprint reaches the pixel "
       "(PCSS's blocker test, for reflections)", ""},
      {"reflections.search_misses", Type::boolean, "false", 0, 0, {},
       "misses (refl.dist <= 0, infinitely far: eq. 13's limit) take part in the parameter "
       "search", ""},
      {"reflections.masking", Type::boolean, "true", 0, 0, {},
       "scale refl.glossy by the rough lobe's directional albedo 1/(1 + 2·Λ(θ_i)) (Smith "
       "masking-shadowing, height-correlated): the energy a single-scattering GGX lobe loses", ""},
      {"reflections.anisotropic", Type::boolean, "true", 0, 0, {},
       "elongate the footprint along the screen image of the plane of incidence (eq. 14's cos "
       "applied across it only); false: the paper's round footprint R_g = R_s·cos θ_i", ""},
  };
}

std::vector<Def> dof_params() {
  return {
      {"dof.method", Type::choice, "none", 0, 0, {"none", "isg", "layered"},
       "depth-of-field method, applied last on the composite (needs depth and the camera): isg "
       "(the paper's parameter search and gather, eq. 15-17), layered (near and far fields "
       "gathered apart, the near field composited over the far by its coverage)", ""},
      {"dof.samples", Type::integer, "64", 1, 1024, {},
       "samples per pixel per gather pass, rounded to a square grid through the concentric disk "
       "map (rotated per pixel)", ""},
      {"dof.focus_distance", Type::number, "0", 0, 1e9, {},
       "focus distance z_f of eq. 15 (0: the camera's focus_distance)", "scene units"},
      {"dof.fstop", Type::number, "0", 0, 1024, {}, "f-number (0: the camera's fstop)", ""},
      {"dof.coc_infinity", Type::number, "0", 0, 1024, {},
       "c_inf of eq. 15, the CoC radius at infinity (0: thin lens from focal length, f-stop, "
       "focus distance, sensor width and image width)", "pixels"},
      {"dof.coc_scale", Type::number, "1", 0, 100, {}, "multiplies every circle of confusion", ""},
      {"dof.max_coc", Type::number, "32", 0.5, 256, {},
       "largest CoC radius; nearer points are clamped to it", "pixels"},
      {"dof.aperture", Type::choice, "disk", 0, 0, {"disk", "polygon"},
       "aperture (bokeh) shape: the gathers' spatial weight", ""},
      {"dof.blades", Type::integer, "6", 3, 16, {}, "blades of a polygon aperture", ""},
      {"dof.rotation", Type::number, "0", -360, 360, {}, "rotation of a polygon aperture",
       "degrees"},
      {"dof.tile_skip", Type::boolean, "true", 0, 0, {},
       "16x16 tiles whose CoC range is under half a pixel take the cheap path (a plain aperture "
       "average)", ""},
  };
}

std::vector<Def> output_params() {
  return {
      {"output.compression", Type::choice, "zip", 0, 0,
       {"none", "rle", "zip", "zips", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"},
       "EXR compression of the output", ""},
      {"input.positions", Type::choice, "P", 0, 0, {"P", "Z", "auto"},
       "where positions come from: P as the renderer wrote it (consistent with a shadow map the "
       "renderer computed in the same float32 world), or Z and the camera; auto takes Z where "
       "P's float32 step is over 64x Z's (the camera more than 64 scene diameters from the "
       "world origin), for maps that are exact where P is not", ""},
      {"limits.max_megapixels", Type::number, "268.5", 0.001, 4096, {},
       "largest input image accepted, checked before decoding", "megapixels"},
      {"limits.max_channels", Type::integer, "1024", 1, 65536, {},
       "most channels accepted in one input file, checked before decoding", ""},
      {"limits.max_memory_mb", Type::integer, "16384", 16, 1 << 22, {},
       "most host memory the decoded input may take", "MiB"},
      {"limits.tile_size", Type::integer, "0", 0, 1 << 16, {},
       "process the image in tiles of this many pixels a side (rounded up to 16), each with the "
       "apron its passes read, giving what one piece would; 0: only when the plan's buffers "
       "exceed half the device's memory or its largest storage buffer", "pixels"},
      {"limits.check_seconds", Type::number, "30", 0, 3600, {},
       "time OpenEXR may take to decode an input, in a child process where a damaged file "
       "cannot crash or hang isg (0: decode in isg itself, for trusted files only)", "s"},
  };
}

std::vector<Def> all_params() {
  std::vector<Def> all;
  for (auto table : {shadows_params, reflections_params, dof_params, output_params}) {
    auto t = table();
    all.insert(all.end(), t.begin(), t.end());
  }
  return all;
}

params::Params default_params() { return params::Params(all_params()); }

}  // namespace isg::effects
