/* SPDX-License-Identifier: Apache-2.0 */
/* The stiff stand that asks for an e-stop at STOP_TICK. */
#include "stops_stand.h"

ROZ_PROCESS(tick)
{
    stops_stand(tick, 1.0);
    if (tick == STOP_TICK)
        roz_request_estop();
}
