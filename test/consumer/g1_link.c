/* SPDX-License-Identifier: Apache-2.0 */
/* Links the Unitree G1 port from the package (with roz::dds and Cyclone DDS
 * found through it) and names its ops table: a package that exports the
 * DDS ports without their dependencies fails here. */
#include <stdio.h>

#include "roz/port/unitree_g1.h"

int main(void)
{
    printf("consumer: port %s linked\n", roz_unitree_g1_ops.name);
    return 0;
}
