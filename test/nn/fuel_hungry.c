/* SPDX-License-Identifier: Apache-2.0 */
/* A controller that needs more fuel than any UR5 runtime grants by default:
 * it declares 500,000 units a tick (the UR5's default ceiling, 4x its
 * default budget of 100,000, is 400,000) and spends about twice the default
 * budget every tick, holding every joint. rozrun_fuel_max runs it with and
 * without rozrun's --fuel-max. */
#include "roz_controller.h"

ROZ_FUEL_PER_TICK(500000);

static volatile unsigned sink;

ROZ_PROCESS(tick)
{
    for (unsigned i = 0; i < 20000u; i++)
        sink = sink + i + (unsigned)tick;
    for (int i = 0; i < roz_command_count(); i++)
        roz_command_set(i, 0.0);
}
