/* SPDX-License-Identifier: Apache-2.0 */
/* What the humanoid stand examples (g1_stand, g1_23dof_stand, pm01_stand,
 * x2_stand) share: each tick, every joint gets its pose's position target,
 * zero velocity and feed-forward torque, and its gains, the stiffness
 * ramped in over the first second (the manifests' rate caps would ramp it
 * anyway; ramping here keeps the command equal to what was asked). The
 * robot's own PD runs it. Each command kind's channels are consecutive,
 * one per joint, from the first joint's (pos, vel, kp, kd, tau). */
#ifndef ROZ_EXAMPLE_STAND_H
#define ROZ_EXAMPLE_STAND_H

#include "roz_controller.h"

static inline void stand_step(long long tick, double rate_hz, int joints, const double *pose,
                              const double *kp, const double *kd, int pos, int vel, int kp0,
                              int kd0, int tau)
{
    double ramp = (double)tick / rate_hz; /* seconds */
    if (ramp > 1.0)
        ramp = 1.0;
    for (int j = 0; j < joints; j++) {
        roz_command_set(pos + j, pose[j]);
        roz_command_set(vel + j, 0.0);
        roz_command_set(kp0 + j, ramp * kp[j]);
        roz_command_set(kd0 + j, kd[j]);
        roz_command_set(tau + j, 0.0);
    }
}

#endif /* ROZ_EXAMPLE_STAND_H */
