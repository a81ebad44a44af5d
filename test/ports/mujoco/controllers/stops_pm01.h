/* SPDX-License-Identifier: Apache-2.0 */
/* The standing PM01 the stop cases start from (test_mujoco_stops.c,
 * test_mujoco_stops_pm01): the example balancing stand pm01_stand itself
 * (examples/controllers/pm01_stand.c, its gains ramped in over the first
 * second), its tick renamed pm01_stand_tick() so each controller file here
 * wraps it and says what it does at STOP_TICK. */
#ifndef STOPS_PM01_H
#define STOPS_PM01_H

#include "roz_controller.h"

#pragma push_macro("ROZ_PROCESS")
#undef ROZ_PROCESS
#define ROZ_PROCESS(tick) static void pm01_stand_tick(long long tick)
#include "pm01_stand.c"
#pragma pop_macro("ROZ_PROCESS")

/* 2 s at 500 Hz: the stand has settled */
#define STOP_TICK 1000

#endif /* STOPS_PM01_H */
