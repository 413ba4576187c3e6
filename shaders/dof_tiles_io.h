#ifndef DOF_TILES_IO_H
#define DOF_TILES_IO_H
// Pass dof.tiles: push constants are the shared DofPush (dof_io.h).
#include "dof_io.h"
#endif
