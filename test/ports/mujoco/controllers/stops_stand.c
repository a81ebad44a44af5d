/* SPDX-License-Identifier: Apache-2.0 */
/* The stiff stand, for ever: the baseline, and the e-stop, stale, link and
 * watchdog cases (the stop comes from outside). */
#include "stops_stand.h"

ROZ_PROCESS(tick)
{
    stops_stand(tick, 1.0);
}
