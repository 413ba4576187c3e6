#ifndef DOF_LAYERED_IO_H
#define DOF_LAYERED_IO_H
// Pass dof.layered: push constants are the shared DofPush (dof_io.h).
#include "dof_io.h"
#endif
