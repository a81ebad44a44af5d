/* SPDX-License-Identifier: Apache-2.0 */
/* The PM01 stand that traps (unreachable) at STOP_TICK: after verification,
 * which runs ticks 0-99. */
#include "stops_pm01.h"

ROZ_PROCESS(tick)
{
    if (tick >= STOP_TICK)
        __builtin_trap();
    pm01_stand_tick(tick);
}
