/* SPDX-License-Identifier: Apache-2.0 */
/* The PM01 stand that loops for ever from STOP_TICK: its fuel budget stops it. */
#include "stops_pm01.h"

ROZ_PROCESS(tick)
{
    pm01_stand_tick(tick);
    volatile int spin = tick >= STOP_TICK;
    while (spin)
        ;
}
