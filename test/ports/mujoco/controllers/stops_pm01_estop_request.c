/* SPDX-License-Identifier: Apache-2.0 */
/* The PM01 stand that asks for an e-stop at STOP_TICK. */
#include "stops_pm01.h"

ROZ_PROCESS(tick)
{
    pm01_stand_tick(tick);
    if (tick == STOP_TICK)
        roz_request_estop();
}
