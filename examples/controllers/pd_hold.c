/* SPDX-License-Identifier: Apache-2.0 */
/* PD hold to a pose on the UR5: a velocity command per joint,
 * v = kp * (target - q) - kd * qdot, using the generated channel indices. */
#include "roz_controller.h"
#include "ur5_channels.h"

static const double pose[6] = { 0.0, -1.2, 1.5, -0.3, 1.57, 0.0 }; /* rad */

#define KP 2.0  /* 1/s */
#define KD 0.1

ROZ_PROCESS(tick)
{
    (void)tick;
    for (int j = 0; j < 6; j++) {
        double q = roz_state_get(ROZ_UR5_STATE_SHOULDER_PAN_JOINT_POSITION + j);
        double qd = roz_state_get(ROZ_UR5_STATE_SHOULDER_PAN_JOINT_VELOCITY + j);
        roz_command_set(ROZ_UR5_CMD_SHOULDER_PAN_JOINT_VELOCITY + j, KP * (pose[j] - q) - KD * qd);
    }
}
