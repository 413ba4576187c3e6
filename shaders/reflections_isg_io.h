#ifndef REFLECTIONS_ISG_IO_H
#define REFLECTIONS_ISG_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
// Tiles of REFL_TILE² pixels: reflections.list keeps those with a glossy pixel; the others take
// the cheap path (refl copied). reflections.isg's workgroup is one tile.
#define REFL_TILE 16
// Pass reflections.pack: workgroup width (one row of pixels).
#define REFL_PACK_LOCAL 64
// refl.pack.color's w for a pixel with nothing to gather (background or refl.weight 0); hits
// keep refl.dist > 0, misses 0.
#define REFL_NO_REFLECTION -1.0
// The passes' settings are specialization constants (gpu::Kernel): constant 0 the flags below,
// constant 1 the mode of reflections.isg.
#define REFL_MODE_ISG 0u   // parameter search (eq. 4, 10-12) then gather (eq. 13, 14)
#define REFL_MODE_BLUR 1u  // the naive alternative: a constant-width disk blur of refl
#define REFL_SEARCH_REACH 1u    // the search counts only reflections whose footprint covers p_0
#define REFL_ANISOTROPIC 4u     // the footprint narrows across the plane of incidence (eq. 14)
#define REFL_SEARCH_MISSES 8u   // misses (no refl.dist) count in the search, as t = 1
#define REFL_MASKING 16u        // the lobe's masking-shadowing albedo
#define REFL_HAS_POSITION 32u   // P is given (else from depth and the camera)
#define REFL_HAS_ROUGHNESS 64u  // the roughness channel (else the preset's everywhere)
// The sample lattice's rotation (the pixel hash's angle) is shared by the pixels of each
// REFL_ROTATION_BLOCK² block (issue 18): neighbouring lanes then read neighbouring texels
// (lavapipe's gathers are scalar loads, one cache line each where rotations differ). Against a
// rotation per pixel: shared gloss refl RMSE 0.00232 -> 0.00229, reflections.isg about 5 %
// faster at 1080p; without rotation 0.00238.
#define REFL_ROTATION_BLOCK 4u
// Pixels at most this rough are mirrors: refl.glossy = refl.
#define REFL_MIN_ROUGHNESS 1e-4
// Largest reflected-cone angle θ_max (radians): GGX's tail makes 2·θ_h reach 180° at alpha 1.
#define REFL_MAX_THETA 1.3
// Its half-angle tangent, tan(REFL_MAX_THETA / 2) (the shader clamps tan θ_h to it).
#define REFL_TAN_HALF_MAX_THETA 0.76020440
// cos θ_incident is clamped here (eq. 14 at grazing angles).
#define REFL_MIN_COS 0.05
// The parameter search runs once per 2×2 quad (its first glossy pixel); a pixel whose range
// weight (eq. 10) to that representative is below this searches for itself.
#define REFL_QUAD_SAME 0.5
// A lobe whose footprint R_s (eq. 13) is at least this many pixels takes its gather bilinearly
// from the gathers of the 4×4 blocks around it (each its top-left quad's representative's; on
// its surface, their footprints within a factor REFL_REUSE_RATIO of its own, holding at least
// REFL_REUSE_COVER of the bilinear weight); narrower lobes, and pixels without such neighbours,
// gather for themselves. 64 pixels, sixteen block spacings (the bilinear blend's error falls
// with the square of spacing / R_s): at 32, isg-synth gloss 480x270 refl.glossy RMSE 0.01888
// against 0.01794 (128: 0.01792), reflections.isg at 1080p the same on isg-synth contact and
// about 6 % slower on isg-synth gloss (issue 18).
#define REFL_REUSE_RADIUS 64.0
// Coarse taps (issue 18): refl.pack.* also hold, from texel REFL_COARSE_BASE (the image's w·h
// rounded up to 16 texels, 256 bytes: reflections.pack binds the cells as a storage range of
// their own, so each range stays within the device's storage-buffer range, llvmpipe's 128 MiB
// holding a 3840×2160 frame's w·h texels but not w·h·17/16), one texel per REFL_COARSE² cell
// (cells aligned to the image, ceil(w / REFL_COARSE) a row): the geometry and distance of the
// cell's pixel min(REFL_COARSE·c + REFL_COARSE_PICK, last), and the cell's refl prefiltered
// around it (reflections_cells.comp). A parameter search whose radius R_p is at
// least REFL_COARSE_RADIUS pixels (lattice points ≥ 2·R_p / grid apart, 13 pixels for 5×5) taps
// the cells: the point a tap lands on moves by up to REFL_COARSE_PICK + 1 pixels, and the texels
// it reads, sixteen times fewer, stay in cache (search radii reach reflections.max_radius, 256
// pixels at the defaults).
#define REFL_COARSE 4u
#define REFL_COARSE_PICK 1u
#define REFL_COARSE_RADIUS 32.0
#define REFL_COARSE_GATHER 32.0
// Cells a row of a w-pixel-wide image; cell (cx, cy)'s texel from the cells' first (the pack's
// storage range) and in refl.pack.* (w x h).
#define REFL_COARSE_CELLS(w) (((w) + REFL_COARSE - 1u) / REFL_COARSE)
#define REFL_COARSE_BASE(w, h) (((w) * (h) + 15u) / 16u * 16u)
#define REFL_COARSE_CELL(w, cx, cy) ((cy) * REFL_COARSE_CELLS(w) + (cx))
#define REFL_COARSE_AT(w, h, cx, cy) (REFL_COARSE_BASE(w, h) + REFL_COARSE_CELL(w, cx, cy))
#define REFL_REUSE_RATIO 1.25
#define REFL_REUSE_COVER 0.5
// refl.tiles (uint words) holds, per tile, glossy pixels + REFL_STATS_SEARCHES · searches
// (REFL_TILE_CHEAP for a tile with nothing glossy), then the number of gathers each tile ran (the
// dispatches add theirs atomically to zero); then the tiles reflections.isg runs on
// (reflections.list): a VkDispatchIndirectCommand (tiles_x by the rows the list fills), their
// number and the tile indices; then the VkDispatchIndirectCommand of reflections.isg.own
// (REFL_OWN_ROW by the rows its list fills) and the number of pixels on that list. Then, for
// method isg, the records of the listed tiles' quads, two words each: the glossy mask of its four
// pixels (bit k at (k & 1, k >> 1)) and its representative's t̄ (float bits), REFL_QUADS² a tile;
// then, from a 16-byte boundary, the blocks' wide gathers, two 16-byte texels each: the mean and
// R_s (float bits; R_s < 0: none), and the representative's refl.pack.geo texel (P − eye, oct N),
// REFL_BLOCKS² a tile (a tile reflections.list left out gets R_s = −1 alone); then the pixels reflections.isg.own finishes (their indices).
#define REFL_STATS_SEARCHES 1024u
#define REFL_TILE_CHEAP 0xffffffffu
#define REFL_QUADS (REFL_TILE / 2u)   // 2×2 quads a tile row
#define REFL_BLOCKS (REFL_TILE / 4u)  // 4×4 blocks a tile row
#define REFL_AT_ARGS(nt) (2u * (nt))
#define REFL_AT_COUNT(nt) (2u * (nt) + 3u)
#define REFL_AT_LIST(nt) (2u * (nt) + 4u)
#define REFL_AT_OWN_ARGS(nt) (3u * (nt) + 4u)
#define REFL_AT_OWN_COUNT(nt) (3u * (nt) + 7u)
#define REFL_TILES_WORDS(nt) (3u * (nt) + 8u)  // the header above (method blur: all)
#define REFL_AT_QUADS(nt) (REFL_TILES_WORDS(nt))
#define REFL_AT_BLOCKS(nt) ((REFL_AT_QUADS(nt) + 2u * REFL_QUADS * REFL_QUADS * (nt) + 3u) / 4u * 4u)
#define REFL_AT_OWN(nt) (REFL_AT_BLOCKS(nt) + 8u * REFL_BLOCKS * REFL_BLOCKS * (nt))
#define REFL_TILES_WORDS_ISG(nt) (REFL_AT_OWN(nt) + REFL_TILE * REFL_TILE * (nt))
// Pass reflections.isg.own: a lane per listed pixel, REFL_OWN_LOCAL a workgroup, REFL_OWN_ROW
// workgroups a row of the dispatch.
#define REFL_OWN_LOCAL 64u
#define REFL_OWN_ROW 256u
// Pass reflections.list: one lane per tile.
#define REFL_LIST_LOCAL 64
struct ReflIsgPush {
  uint width;
  uint height;
  uint grids;          // search grid | gather grid << 16: samples = grid², concentric disk
  uint origin;         // the image's origin in the frame, x | y << 16 (the pixel hash's)
  float cx;            // principal point, frame pixels (pixel coordinates here are the frame's)
  float cy;
  float roughness;     // preset roughness (where the channel is absent or overridden)
  float tan_h_factor;  // sqrt(E / (1 − E)): tan θ_h = alpha · tan_h_factor holds a fraction E
  float max_radius;    // footprint clamp, pixels
  float blur_radius;   // REFL_MODE_BLUR radius, pixels
  float a;             // eq. 10 weight of l² (l in units of scene_radius)
  float b;             // eq. 10 weight of n²
  float inv_sigma;     // 1 / σ of eq. 10
  float inv_scene_radius;
  float f_px;          // focal length in pixels: (height / 2) / tan(yfov / 2)
  float eye_x;         // camera position, world: the float nearest the double (eye_hi) ...
  float eye_y;
  float eye_z;
  float eye_lo_x;      // ... and the remainder (eye − eye_hi); reflections.pack only
  float eye_lo_y;
  float eye_lo_z;
  float r00;           // world-to-camera rotation, row-major (camera looks down −Z, +Y up)
  float r01;
  float r02;
  float r10;
  float r11;
  float r12;
  float r20;
  float r21;
  float r22;
};
ISG_IO_END
#endif
