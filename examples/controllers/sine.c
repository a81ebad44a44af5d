/* SPDX-License-Identifier: Apache-2.0 */
/* Sine wave on control time: command i = A * sin(2*pi*f*t + i*pi/3), with A
 * half the channel's upper limit and f = 0.5 Hz. Deterministic: it follows
 * timing.sim_time_ns, not the wall clock. Works with any manifest. */
#include "roz_controller.h"

#define TWO_PI 6.283185307179586
#define FREQ_HZ 0.5

ROZ_PROCESS(tick)
{
    (void)tick;
    double t = (double)roz_sim_time_ns() * 1e-9;
    int n = roz_command_count();
    for (int i = 0; i < n; i++) {
        double amp = 0.5 * roz_command_limit_max(i);
        roz_command_set(i, amp * roz_sin(TWO_PI * FREQ_HZ * t + (double)i * (TWO_PI / 6.0)));
    }
    roz_emit_metric(t);
}
