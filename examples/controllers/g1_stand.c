/* SPDX-License-Identifier: Apache-2.0 */
/* Humanoid stand for the Unitree G1: joint-space PD on all 29 joints toward a
 * slightly crouched standing pose. The robot's own PD runs it: we send the
 * position target, zero velocity and feed-forward torque, and the gains, which
 * ramp in over the first second (the manifest's rate caps would ramp them
 * anyway; ramping here keeps the command equal to what was asked). */
#include "stand.h"
#include "unitree_g1_channels.h"

#define JOINTS 29
#define POS ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_POSITION
#define VEL ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY
#define KP ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS
#define KD ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_DAMPING
#define TAU ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_EFFORT

/* Standing pose in SDK joint order (rad). */
static const double pose[JOINTS] = {
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0,   /* left leg */
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0,   /* right leg */
    0.0, 0.0, 0.0,                    /* waist */
    0.2, 0.2, 0.0, 0.9, 0.0, 0.0, 0.0,  /* left arm */
    0.2, -0.2, 0.0, 0.9, 0.0, 0.0, 0.0, /* right arm */
};
/* Gains per joint (legs stiffer than arms). */
static const double kp[JOINTS] = {
    100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40, 100, 40, 40,
    40, 40, 40, 40, 20, 20, 20, 40, 40, 40, 40, 20, 20, 20,
};
static const double kd[JOINTS] = {
    2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2, 2, 2, 2,
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
};

ROZ_PROCESS(tick)
{
    stand_step(tick, (double)ROZ_UNITREE_G1_CONTROL_RATE_HZ,
               JOINTS, pose, kp, kd, POS, VEL, KP, KD, TAU);
}
