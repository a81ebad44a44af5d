/* SPDX-License-Identifier: Apache-2.0 */
/* Stand for the 23-DoF Unitree G1 (manifest unitree_g1_23dof): the same
 * joint-space PD toward a slightly crouched pose as g1_stand, on the 23
 * joints this variant has (legs, waist yaw, shoulders, elbows, wrist roll).
 * The robot's own PD runs it; the gains ramp in over the first second. It
 * does not balance: the robot hangs (docs/ports/unitree_g1.md). */
#include "stand.h"
#include "unitree_g1_23dof_channels.h"

#define JOINTS 23
#define POS ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_POSITION
#define VEL ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY
#define KP ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS
#define KD ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_DAMPING
#define TAU ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_EFFORT

/* Standing pose in the manifest's joint order (rad). */
static const double pose[JOINTS] = {
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, /* left leg */
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, /* right leg */
    0.0,                            /* waist yaw */
    0.2, 0.2, 0.0, 0.9, 0.0,        /* left arm */
    0.2, -0.2, 0.0, 0.9, 0.0,       /* right arm */
};
/* Gains per joint (legs stiffer than arms). */
static const double kp[JOINTS] = {
    100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40, 100,
    40,  40,  40,  40,  20, 40, 40,  40,  40,  20,
};
static const double kd[JOINTS] = {
    2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2, 2, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
};

ROZ_PROCESS(tick)
{
    stand_step(tick, (double)ROZ_UNITREE_G1_23DOF_CONTROL_RATE_HZ,
               JOINTS, pose, kp, kd, POS, VEL, KP, KD, TAU);
}
