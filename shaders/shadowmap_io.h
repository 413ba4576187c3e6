#ifndef SHADOWMAP_IO_H
#define SHADOWMAP_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
#define SHADOWMAP_LOCAL 16
// Counters the shadow-map passes add to (atomics in the stats buffer).
#define SHADOWMAP_STAT_PIXELS 0   // foreground pixels inside the map
#define SHADOWMAP_STAT_SKIPPED 1  // of them: proven fully lit or in umbra, filter skipped
#define SHADOWMAP_STAT_CLAMPED 2  // of them: kernel radius clamped to shadows.smap_max_radius
#define SHADOWMAP_STAT_CONTACT 3  // of them: contact PCF (vssm, §7.5.4)
#define SHADOWMAP_STATS 4
// The own list of vssm and cssm (shadowmap_common.h's sm_pixel_of): word 0 the pixels listed,
// words 1-3 the VkDispatchIndirectCommand of the own pass (SHADOWMAP_OWN_ROW workgroups a row,
// a row per SHADOWMAP_OWN_ROW workgroups of pixels begun), then the pixels' indices.
#define SHADOWMAP_OWN_HEAD 4u
#define SHADOWMAP_OWN_ROW 16u
// Receiver plane (issue 19): a plane that the screen neighbours left out of its fit agree with
// (their light-space 1/z off the plane's by at most SHADOWMAP_PLANE_TOL of their step) is a
// smooth receiver, trusted up to SHADOWMAP_TRUSTED_SLOPE texel footprints per texel (89.1 degrees
// from the normal: a floor lit 8 degrees above the horizon needs 7); others (silhouettes, P's
// float steps far from the origin) and planes fitted with no neighbour to spare are clamped to
// shadows.slope_max. Own grazing case (light 8 degrees above the floor), RMSE over doing
// nothing: pcss 2.14 -> 0.99, vssm 2.59 -> 1.13 (tolerance 0.1: 1.01, 1.15; 2: 0.93, 1.05, but
// the far-from-origin CSSM test then passes its 10 % bar no more).
#define SHADOWMAP_PLANE_TOL 0.5
#define SHADOWMAP_TRUSTED_SLOPE 64.0
// Soft shadows from the light's shadow map (shadows.method = pcss | vssm | cssm). Per light;
// read by every shadowmap_* pass from a storage buffer (std430: scalars only, no padding).
struct ShadowmapParams {
  // Image and map sizes; geometry source: position (3 planes) or depth + the camera below.
  uint width, height, map_w, map_h;
  uint has_position, taps, rotate, has_camera;
  // Light view: world_to_light rows 0-2 (row-major 3x4) applied to P − light (the light's
  // centre below), so the translation column is what is left of it; tan of the half fields of
  // view, or (ortho) the map's half extents in world units.
  float l00, l01, l02, l03, l10, l11, l12, l13, l20, l21, l22, l23;
  float tan_x, tan_y;
  // Light radius (world; ortho: tan of the sun's half angle, its radius per unit of distance),
  // nearest blocker depth in the map (bounds the blocker search).
  float light_radius, min_depth;
  // Largest kernel radius (texels); constant depth bias in receiver texel footprints;
  // the receiver-plane (slope) bias is clamped to slope_max receiver texel footprints;
  // spread_bias: times the smallest light-depth step to a screen neighbour.
  // depth_eps: the map's own precision (SHADOWMAP_NOISE_EPS times its measured depth noise),
  // added to the receiver's depth uncertainty (spread) with input_ulps (shadows.depth_ulps)
  // float32 steps of the receiver's own input (P at its distance from the world origin, or Z).
  float max_radius, bias, slope_max, spread_bias, depth_eps;
  // Camera (depth -> position): focal length in pixels, eye − light (the light's centre as
  // rounded below, in double on the host), world-to-camera rotation rows.
  float f_px, eye_rel_x, eye_rel_y, eye_rel_z;
  float r0, r1, r2, r3, r4, r5, r6, r7, r8;
  float light_x, light_y, light_z;  // the light's centre (world), rounded to float
  // Principal point (frame pixels; pixel coordinates here are the frame's: this image's plus
  // the origin); the image's origin in the frame, x | y << 16 (also the pixel hash's).
  float cx, cy;
  uint origin;
  float far_clip;  // the map's far plane: receivers beyond it are outside the map
  float input_ulps;
  float reach;  // shadows.reach: pcss's and vssm's filter taps (0: off)
  float input_edges;  // shadows.input_edges, texels (0: off): L.shadow's weight (sm_input_edges)
  uint facing;  // 1: a sphere light, its disk facing the receiver; 0: a disk or rect light in the
                // map's plane (sm_irradiance's emitter cosine)
  uint pcss_narrow;  // shadows.pcss_narrow: pcss's narrowed blocker searches
  uint ortho;  // 1: a sun's orthographic map (contract input 3): planar depth is linear over the
               // map on a plane, a cone's radius grows with depth (shadowmap_common.h's sm_w)
};
// A pcss narrowed blocker search's radius over the light's cone at the mean blocker depth
// (shadowmap_pcss.comp).
#define PCSS_NARROW_MARGIN 1.5
// √π / 2: the half-width of a square of a unit disk's area (a disk's box, §5.3.1's kernels).
#define SM_BOX_OF_DISK 0.886226925452758
// sm_irradiance: the receiver's cosine to the light's centre is kept above this in the weights'
// normalisation (a receiver edge-on to the light's centre still sees its upper half).
#define SHADOWMAP_MIN_CN 1e-3
// The map's precision: this many times its measured depth noise (ShadowmapData::noise, the
// deviation of independent per-texel noise; a float32 step is about 2.4 of it).
#define SHADOWMAP_NOISE_EPS 4.0
// The filters of PCSS and of VSSM's PCF taps count a texel in front of the receiver plane as a
// blocker only where the light's cone from the receiver reaches it (issue 19): its offset from
// the receiver's map position at most shadows.reach times k·(1/z_texel − 1/z_receiver) (k:
// texels per unit of 1/z at the light's radius) plus this many texels — a tap's texel centre lies
// up to √2/2 texel from where the sample fell and the blocker anywhere in its texel. A surface that meets the receiver's plane extended
// (a floor in front of a ramp, lit at grazing) lies outside every cone from the receiver to the
// light and no longer shadows it.
#define SHADOWMAP_REACH_MARGIN 1.5
struct ShadowmapPush {
  uint width;
  uint height;
};
ISG_IO_END
#endif
