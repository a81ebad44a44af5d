/* SPDX-License-Identifier: Apache-2.0 */
/* The stiff stand that loops for ever from STOP_TICK: its fuel budget stops it. */
#include "stops_stand.h"

ROZ_PROCESS(tick)
{
    stops_stand(tick, 1.0);
    volatile int spin = tick >= STOP_TICK;
    while (spin)
        ;
}
