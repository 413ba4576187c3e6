#ifndef DOF_SEARCH_IO_H
#define DOF_SEARCH_IO_H
// Pass dof.search: push constants are the shared DofPush (dof_io.h).
#include "dof_io.h"
#endif
