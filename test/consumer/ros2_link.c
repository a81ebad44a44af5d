/* SPDX-License-Identifier: Apache-2.0 */
/* Links the ROS 2 topic ports from the package (with roz::ros2, roz::dds,
 * their generated types and Cyclone DDS found through it) and names their
 * ops tables: a package that exports them without their dependencies fails
 * here. */
#include <stdio.h>

#include "roz/port/agibot_x2.h"
#include "roz/port/engineai_pm01.h"

int main(void)
{
    printf("consumer: ports %s and %s linked\n", roz_engineai_pm01_ops.name,
           roz_agibot_x2_ops.name);
    return 0;
}
