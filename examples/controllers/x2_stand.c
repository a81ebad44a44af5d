/* SPDX-License-Identifier: Apache-2.0 */
/* Stand for the AgiBot X2: joint-space PD on all 30 joints toward a slightly
 * crouched pose, run by the robot's own PD: position target, zero velocity
 * and feed-forward torque, and the gains, which ramp in over the first
 * second. Leg gains are the vendor example's (kp 40/40/30/80/40/20, kd
 * 4/4/3/8/4/2); the waist, arm and head gains and the pose are ours. */
#include "stand.h"
#include "agibot_x2_channels.h"

#define JOINTS 30
#define POS ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_POSITION
#define VEL ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY
#define KP ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS
#define KD ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_DAMPING
#define TAU ROZ_AGIBOT_X2_CMD_LEFT_HIP_PITCH_JOINT_EFFORT

/* Standing pose in HAL group order (rad). */
static const double pose[JOINTS] = {
    -0.3, 0.0, 0.0, 0.6, -0.3, 0.0,           /* left leg: hip pitch, roll, yaw, knee, ankle */
    -0.3, 0.0, 0.0, 0.6, -0.3, 0.0,           /* right leg */
    0.0, 0.0, 0.0,                            /* waist yaw, pitch, roll */
    0.0, 0.1, 0.0, -0.3, 0.0, 0.0, 0.0,       /* left arm: shoulder pitch, roll, yaw, elbow, wrist */
    0.0, -0.1, 0.0, -0.3, 0.0, 0.0, 0.0,      /* right arm */
    0.0,                                      /* head yaw */
};
static const double kp[JOINTS] = {
    40, 40, 30, 80, 40, 20, 40, 40, 30, 80, 40, 20, 60, 60, 60,
    30, 30, 30, 30, 10, 10, 10, 30, 30, 30, 30, 10, 10, 10, 10,
};
static const double kd[JOINTS] = {
    4, 4, 3, 8, 4, 2, 4, 4, 3, 8, 4, 2, 3, 3, 3,
    2, 2, 2, 2, 1, 1, 1, 2, 2, 2, 2, 1, 1, 1, 1,
};

ROZ_PROCESS(tick)
{
    stand_step(tick, (double)ROZ_AGIBOT_X2_CONTROL_RATE_HZ,
               JOINTS, pose, kp, kd, POS, VEL, KP, KD, TAU);
}
