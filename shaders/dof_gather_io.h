#ifndef DOF_GATHER_IO_H
#define DOF_GATHER_IO_H
// Pass dof.gather: push constants are the shared DofPush (dof_io.h).
#include "dof_io.h"
#endif
