/* SPDX-License-Identifier: Apache-2.0 */
/* The stiff stand as a controller swapped in under a standing robot: its
 * gains from its first tick (it starts at tick 0, the robot is up). */
#include "stops_stand.h"

ROZ_PROCESS(tick)
{
    stops_stand(tick, 0.0);
}
