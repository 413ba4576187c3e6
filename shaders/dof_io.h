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
struct DofPush {
  uint width;
  uint height;
  uint tiles_x;
  uint tiles_y;
  uint grid;       // samples = grid * grid, a regular grid through the concentric disk map
  uint blades;     // 0: disk aperture, else an n-blade polygon
  uint has_alpha;  // composite plane 3 is alpha (background where it is 0)
  uint margin;     // tiles look this far (pixels) for CoCs that reach into them
  float z_f;       // eq. 15: focus distance (planar depth, scene units)
  float c_inf;     // eq. 15: CoC radius at infinity, pixels
  float max_coc;   // |CoC| clamp, pixels
  float rotation;  // aperture rotation, radians
  uint tile_skip;  // 1: cheap tiles take the cheap path
  uint origin;     // the image's origin in the frame, x | y << 16 (the pixel hash's)
  uint pad1;
  uint pad2;
};
ISG_IO_END
#endif
