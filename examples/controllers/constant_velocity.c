/* SPDX-License-Identifier: Apache-2.0 */
/* Constant velocity: every command channel at a fifth of its upper limit
 * (for velocity channels, a slow constant motion). Works with any manifest. */
#include "roz_controller.h"

ROZ_PROCESS(tick)
{
    (void)tick;
    int n = roz_command_count();
    for (int i = 0; i < n; i++)
        roz_command_set(i, 0.2 * roz_command_limit_max(i));
}
