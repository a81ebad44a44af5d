/* SPDX-License-Identifier: Apache-2.0 */
/* stops_trap.c on the X2 (x2_stops_stand.h says how). */
#include "x2_stops_stand.h"
#include "stops_trap.c"
