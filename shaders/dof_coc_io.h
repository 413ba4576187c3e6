#ifndef DOF_COC_IO_H
#define DOF_COC_IO_H
// Pass dof.coc: push constants are the shared DofPush (dof_io.h).
#include "dof_io.h"
#endif
