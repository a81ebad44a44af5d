/* SPDX-License-Identifier: Apache-2.0 */
/* Hostile, in C: drives joint 0 at 0.3 rad/s; at tick 150 recurses with a
 * 4 KiB frame until its shadow stack (in linear memory, 16 KiB) runs down
 * through its data and off the bottom of memory. The depth limit is never
 * reached; it only keeps the compiler from refusing endless recursion. */
#include "roz_controller.h"

static volatile int sink;

static int dig(int depth)
{
    volatile unsigned char frame[4096];
    for (int i = 0; i < (int)sizeof frame; i += 512)
        frame[i] = (unsigned char)depth;
    if (depth > 0x7fffffff - 2)
        return 0;
    return dig(depth + 1) + frame[depth & 4095];
}

ROZ_PROCESS(tick)
{
    roz_command_set(0, 0.3);
    if (tick == 150)
        sink = dig(0);
}
