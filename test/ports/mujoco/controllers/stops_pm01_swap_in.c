/* SPDX-License-Identifier: Apache-2.0 */
/* The PM01 stand as a controller swapped in under the standing robot: its
 * gains and balance at full from its first tick (the stand's clock a
 * second on: it starts at tick 0, the robot is up). */
#include "stops_pm01.h"

ROZ_PROCESS(tick)
{
    pm01_stand_tick(tick + ROZ_ENGINEAI_PM01_CONTROL_RATE_HZ);
}
