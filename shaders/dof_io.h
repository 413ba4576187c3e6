#ifndef DOF_IO_H
#define DOF_IO_H
#include "isg_io.h"
ISG_IO_BEGIN
// Depth of field (paper §3.3): every dof pass shares this push block.
#define DOF_LOCAL 8
// Largest sample lattice (dof.samples ≤ 1024: a 32 × 32 grid), kept in shared memory.
#define DOF_MAX_LATTICE 1024
#define DOF_TILE 16  // tile side for the classification (NRD's ClassifyTiles)
// CoC range (max - min, pixels) below which a tile takes the cheap path.
#define DOF_CHEAP_RANGE 0.5
// dof.layered at half resolution where the blur is wide (issue 18): a pixel whose |CoC| is at
// least DOF_REUSE_COC pixels takes its result bilinearly from its workgroup's 2×2 quads'
// representatives whose CoC has its sign and lies within DOF_REUSE_TOL·|CoC| of its own, where
// they hold at least DOF_REUSE_COVER of the bilinear weight.
#define DOF_REUSE_COC 8.0
#define DOF_REUSE_TOL 0.1
#define DOF_REUSE_COVER 0.5
// dof.layered's lattice over a tile of radius R: grid = clamp(ceil(DOF_LATTICE_DENSITY · R),
// DOF_MIN_GRID, the dof.samples grid), so a small blur takes fewer samples (a 2 px CoC, 16
// instead of 64) at about one sample per pixel of diameter.
#define DOF_LATTICE_DENSITY 2.0
#define DOF_MIN_GRID 3
struct DofPush {
  uint width;
  uint height;
  uint tiles_x;
  uint tiles_y;
  uint grid;       // samples = grid * grid, a regular grid through the concentric disk map
  uint has_alpha;  // composite plane 3 is alpha (background where it is 0)
  uint margin;     // tiles look this far (pixels) for CoCs that reach into them
  float z_f;       // eq. 15: focus distance (planar depth, scene units)
  float c_inf;     // eq. 15: CoC radius at infinity, pixels
  float max_coc;   // |CoC| clamp, pixels
  float rotation;  // aperture rotation, radians
  uint tile_skip;  // 1: cheap tiles take the cheap path
  uint origin;     // the image's origin in the frame, x | y << 16 (the pixel hash's)
  uint coc_source;  // dof.coc: 0 eq. 15 from depth, 1 a CoC channel times c_inf
  uint depth_form;  // 0 planar, 1 normalized (depth_near .. depth_far), 2 inverse (1/Z)
  float depth_near;
  float depth_far;
  float stretch_x;  // dof.anamorphic s: the aperture 1/√s across and √s down (dof_stretch)
  float stretch_y;
};
ISG_IO_END
#endif
