/* SPDX-License-Identifier: Apache-2.0 */
/* The stiff stand that traps (unreachable) at STOP_TICK: after verification,
 * which runs ticks 0-99. */
#include "stops_stand.h"

ROZ_PROCESS(tick)
{
    if (tick >= STOP_TICK)
        __builtin_trap();
    stops_stand(tick, 1.0);
}
