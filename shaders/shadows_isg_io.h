#ifndef SHADOWS_ISG_IO_H
#define SHADOWS_ISG_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
// Method isg works in tiles of SHADOWS_ISG_TILE² pixels: shadows.isg.tiles classifies them,
// shadows.isg.list keeps those with a shadow boundary within reach, shadows.isg.reach,
// shadows.isg.quads and shadows.isg run over those (a workgroup a tile), shadows.isg.own over the
// pixels shadows.isg lists; the other tiles keep L.softshadow = L.shadow.
#define SHADOWS_ISG_TILE 16
// The tiles buffer (uint): [0, nt) tile flags from shadows.isg.tiles (bit 0: a foreground pixel
// with some light, bit 1: one with some shadow), [nt, 2nt) the tile's largest occluder distance
// (float bits), [2nt, 3nt) 1 where a tile takes the cheap path (shadows.isg.reach, or the list's
// marking), then the statistics at 3nt + SHADOWS_ISG_STAT_*; then the tiles shadows.isg runs on
// (shadows.isg.list): a VkDispatchIndirectCommand (tiles_x by the rows the list fills, so that no
// count exceeds the device's workgroup limit on a large plate), their number, then the tile
// indices.
#define SHADOWS_ISG_AT_STATS(nt) (3u * (nt))
#define SHADOWS_ISG_AT_ARGS(nt) (3u * (nt) + SHADOWS_ISG_STATS)
#define SHADOWS_ISG_AT_COUNT(nt) (3u * (nt) + SHADOWS_ISG_STATS + 3u)
#define SHADOWS_ISG_AT_LIST(nt) (3u * (nt) + SHADOWS_ISG_STATS + 4u)
// Then what the dispatches of shadows.isg pass on (issue 18: four dispatches, as reflections.isg's,
// barriers and shared memory in shadows.isg.reach only): per tile the largest occluder distance
// within its reach (float bits; shadows.isg.reach); the dispatch of the pixels' list (a
// VkDispatchIndirectCommand, SHADOWS_ISG_OWN_ROW by the rows the list fills) and their number;
// per tile the records of its QUADS² 2×2 quads (shadows.isg.quads: the representative's index or
// SHADOWS_ISG_NO_REP, its mean occluder distance, its wide gather and R_g, 4 words); the pixels'
// list (shadows.isg: the pixels that search or gather for themselves, their index |
// SHADOWS_ISG_OWN_SEARCH | SHADOWS_ISG_OWN_BORROW).
#define SHADOWS_ISG_AT_DLOC(nt) (4u * (nt) + SHADOWS_ISG_STATS + 4u)
#define SHADOWS_ISG_AT_OWN_ARGS(nt) (5u * (nt) + SHADOWS_ISG_STATS + 4u)
#define SHADOWS_ISG_AT_OWN_COUNT(nt) (SHADOWS_ISG_AT_OWN_ARGS(nt) + 3u)
#define SHADOWS_ISG_AT_QUADS(nt) (SHADOWS_ISG_AT_OWN_ARGS(nt) + 4u)
#define SHADOWS_ISG_AT_OWN(nt) (SHADOWS_ISG_AT_QUADS(nt) + SHADOWS_ISG_TILE * SHADOWS_ISG_TILE * (nt))
#define SHADOWS_ISG_TILES_WORDS(nt) (SHADOWS_ISG_AT_OWN(nt) + SHADOWS_ISG_TILE * SHADOWS_ISG_TILE * (nt))
#define SHADOWS_ISG_OWN_SEARCH 0x80000000u  // the pixel searches for itself
#define SHADOWS_ISG_OWN_BORROW 0x40000000u  // the pixel takes its neighbours' mean (borrowed_d)
#define SHADOWS_ISG_NO_REP 0xffffffffu  // a quad with no foreground pixel
// Pass shadows.isg.own: a lane per listed pixel, SHADOWS_ISG_OWN_LOCAL a workgroup,
// SHADOWS_ISG_OWN_ROW workgroups a row of the dispatch.
#define SHADOWS_ISG_OWN_LOCAL 64u
// Passes shadows.isg.quads and .own on a GPU: the lanes that take one search or gather sum, a
// part each (shadows_isg.h; at most the subgroup size). H200, 1080p isg-synth contact, the four
// dispatches, medians of 6 alternated runs: 2 lanes 0.193 ms, 4 lanes 0.176, 8 lanes 0.188.
#define SHADOWS_ISG_PART_LANES 4u
#define SHADOWS_ISG_OWN_ROW 256u
// Pass shadows.isg.list: one lane per tile.
#define SHADOWS_ISG_LIST_LOCAL 64
#define SHADOWS_ISG_FLAG_LIT 1u
#define SHADOWS_ISG_FLAG_SHADOW 2u
#define SHADOWS_ISG_STAT_DMAX 0u     // the image's largest occluder distance (float bits)
#define SHADOWS_ISG_STAT_CLAMPED 1u  // pixels whose search or gather radius exceeded max_radius
#define SHADOWS_ISG_STAT_FULL 2u     // pixels that ran the search and gather
#define SHADOWS_ISG_STAT_SEARCHES 3u // parameter searches run (one per 2×2 quad, more at edges)
#define SHADOWS_ISG_STAT_GATHERS 4u  // gathers run (one per quad for wide penumbrae, more at edges)
#define SHADOWS_ISG_STAT_BORROWED 5u // pixels that took their neighbour quads' occluder distance
#define SHADOWS_ISG_STATS 6u
// The search runs once per 2×2 quad (its first foreground pixel, the representative); a pixel
// whose eq. 6 range weight to the representative is below this searches for itself.
#define SHADOWS_ISG_QUAD_SAME 0.5
// A pixel whose gather radius R_g is at least this many pixels takes its result bilinearly from
// the gathers of the quads' representatives around it (on its surface, R_g within a factor
// SHADOWS_ISG_REUSE_RATIO of its own, holding at least SHADOWS_ISG_REUSE_COVER of the bilinear
// weight); narrower penumbrae, and pixels without such neighbours, gather for themselves.
#define SHADOWS_ISG_REUSE_RADIUS 32.0
#define SHADOWS_ISG_REUSE_RATIO 1.25
#define SHADOWS_ISG_REUSE_COVER 0.5
// A quad whose search found no occluder within reach, amid at least this many of the 8 quads
// around it in its tile that did, on the pixel's surface (eq. 6 weight ≥ SHADOWS_ISG_QUAD_SAME
// to their representatives), takes their mean occluder distance (issue 19): in a wide penumbra
// the search's 25 samples over a 64-pixel disk find the shadow's core by chance, and the quads
// that miss it stayed at the hard shadow, lit specks in the penumbra. RMSE / doing nothing's
// (shared contact, rowdepth; own grazing, lowlight): none 0.352 0.200 0.345 0.499; 1 of 8
// 0.356 0.201 0.263 0.495; 2: the same as 1 but lowlight 0.490; 3: 0.353 0.199 0.277 0.490;
// 2 of the 24 in the 5x5 around: 0.364 0.203 0.281 0.498. 3 of 8 is the one no case loses by.
#define SHADOWS_ISG_BORROW_MIN 3
// D − d is kept above this fraction of D in eq. 8 (occluders next to the light).
#define SHADOWS_ISG_MIN_GAP 0.05
// The search's blocker test counts an occluded sample whose occluder, at distance t from p_0,
// lies within this many times R_s(t) (eq. 8) of p_0 across the light's direction (1: p_0's cone
// to the light, exactly; the rest is slack for the lattice's spacing). Measured with t from p_0,
// RMSE / doing nothing's on the Cycles cases (shared contact, rowdepth; own far1e5, far1e6,
// grazing, lowlight) and the RMSE of isg-synth contact and of the 80° grazing view
// (tests/gpu/test_shadows_isg.cpp):
//   1.25: 0.329 0.220 0.351 0.620 0.366 0.496;
//   1.5:  0.345 0.206 0.365 0.605 0.351 0.501; synth 0.02377, grazing view 0.01040;
//   1.75: 0.351 0.202 0.372 0.593 0.347 0.509; synth 0.02271, grazing view 0.00954;
//   2:    0.353 0.196 0.375 0.590 0.345 0.524; synth 0.02242, grazing view 0.00953.
// With t from the tap (its own L.occluder, as before) and 2: 0.353 0.201 0.391 0.620 0.377 0.519;
// synth 0.02269, grazing view 0.00953. 1.75 is the one no case loses by (rowdepth +0.5 %).
#define SHADOWS_ISG_REACH 1.75
// irradiance(): the receiver's cosine to the light's centre is kept above this in the weights'
// normalisation (a receiver edge-on to the light's centre still sees its upper half).
#define SHADOWS_ISG_MIN_CN 1e-3
// Disk and rect lights: the cosine between the light's direction and its plane's normal is kept
// above this in the cross-section distance (across()).
#define SHADOWS_ISG_MIN_COS 0.2
// The penumbra lies on the receiver stretched by 1 / cos θ_i along the light's direction (θ_i
// between the receiver's normal, from P's screen derivatives, and the light): the footprint is an
// ellipse (issue 19). The stretch is capped here: the uniform kernel over the projected disk holds
// while the occluder distance changes little across the footprint, and on a receiver under grazing
// light it changes as fast as the footprint grows. Measured on the own Cycles cases (RMSE / doing
// nothing's): a cap of 5 gave grazing 0.42, lowlight 0.515, shared rowdepth 0.209; 2 gave 0.38,
// 0.519, 0.201; no stretch 0.35, 0.551, 0.187. With the search's occluder distances taken from
// p_0 (SHADOWS_ISG_REACH 1.5), 4 gave grazing 0.360, lowlight 0.497, rowdepth 0.218 against 2's
// 0.351, 0.501, 0.206. With the gather's irradiance weights (REACH 1.75), 3 gave shared contact
// 0.349, rowdepth 0.200, grazing 0.343, lowlight 0.491, far1e5 0.374 against 2's 0.352, 0.200,
// 0.345, 0.499, 0.373 (4: 0.349, 0.204, 0.346, 0.492), but the closed forms lost: the parallel
// planes under a light 18° beside the edge 0.0068 -> 0.0141 (the ellipse's samples spread along
// the light, where the penumbra does not change), the upright edge 0.0127 -> 0.0139; kept at 2.
#define SHADOWS_ISG_MAX_STRETCH 2.0
// Settings of shadows.isg: its specialization constant 0 (SHADOWS_ISG_HAS_POSITION alone that of
// shadows.isg.tiles; SHADOWS_ISG_TILE_SKIP the list's push constant).
#define SHADOWS_ISG_ROTATE 1u       // rotate the sample grid per pixel (pixel hash)
#define SHADOWS_ISG_SEARCH_REACH 2u // the search counts only occluders in p_0's cone to the light
#define SHADOWS_ISG_TILE_SKIP 4u    // tiles with no shadow boundary within reach take the cheap path
#define SHADOWS_ISG_ORIENTED 8u     // disk and rect lights: the penumbra's cross-section lies in
                                    // the light's plane (light_n), not across the ray
#define SHADOWS_ISG_HAS_POSITION 16u  // P is given (else from depth and the camera)
struct ShadowsIsgPush {
  uint width;
  uint height;
  uint grids;         // search grid | gather grid << 16: samples = grid², concentric disk
  uint origin;         // the image's origin in the frame, x | y << 16 (the pixel hash's)
  float cx;            // principal point, frame pixels (pixel coordinates here are the frame's)
  float light_size;    // L of eq. 5 and 8: the light's radius in world units
  float inv_sigma;     // 1 / σ of eq. 6 (l in units of scene_radius)
  float inv_scene_radius;
  float max_radius;    // largest search and gather radius, pixels
  float f_px;          // focal length in pixels: (height / 2) / tan(yfov / 2)
  float light_x;       // the light's centre relative to the camera (light − eye, from double)
  float light_y;
  float light_z;
  float r00;           // world-to-camera rotation, row-major (camera looks down −Z, +Y up)
  float r01;
  float r02;
  float r10;
  float r11;
  float r12;
  float r20;
  float r21;
  float r22;
  float light_nx;      // the light's normal (disk, rect)
  float light_ny;
  float light_nz;
  float cy;
};
// Pass shadows.isg.tiles, which also packs what every tap of shadows.isg reads into one
// 16-byte texel a pixel, L.isg.pack = (P − eye, L.shadow or SHADOWS_ISG_BACKGROUND).
#define SHADOWS_ISG_BACKGROUND -1e30  // below any L.shadow a renderer writes
struct ShadowsIsgTilesPush {
  uint width;
  uint height;
  uint origin;         // as ShadowsIsgPush
  float cx;            // principal point, frame pixels
  float cy;
  float f_px;
  float eye_x;         // camera position, world: the float nearest the double (eye_hi) ...
  float eye_y;
  float eye_z;
  float eye_lo_x;      // ... and the remainder (eye − eye_hi)
  float eye_lo_y;
  float eye_lo_z;
  float r00;           // world-to-camera rotation, row-major
  float r01;
  float r02;
  float r10;
  float r11;
  float r12;
  float r20;
  float r21;
  float r22;
};
// Pass shadows.isg.list: the tiles shadows.isg must run on. A tile is left out (its pixels keep
// the hard shadow, copied before) only where no shadow boundary lies within a reach that bounds
// shadows.isg's own: eq. 5's R_p from the image's d_max at the tile's smallest distance to the
// light and camera depth, over the pixel's footprint at its least (z / f_px /
// SHADOWS_ISG_MAX_STRETCH). shadows.isg would take its cheap path there; the tiles listed decide
// for themselves as before.
struct ShadowsIsgListPush {
  uint width;
  uint height;
  uint flags;          // SHADOWS_ISG_TILE_SKIP
  float light_size;
  float max_radius;
  float f_px;
  float light_x;       // light − eye, as ShadowsIsgPush
  float light_y;
  float light_z;
  float r20;           // the world-to-camera rotation's last row (camera depth = −row · (P − eye))
  float r21;
  float r22;
};
ISG_IO_END
#endif
