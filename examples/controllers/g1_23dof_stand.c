/* SPDX-License-Identifier: Apache-2.0 */
/* Stand for the 23-DoF Unitree G1 (manifest unitree_g1_23dof): the same
 * joint-space PD toward a slightly crouched pose as g1_stand, on the 23
 * joints this variant has (legs, waist yaw, shoulders, elbows, wrist roll).
 * The robot's own PD runs it; the gains ramp in over the first second. It
 * does not balance: the robot hangs (README, "A real Unitree G1"). */
#include "roz_controller.h"
#include "unitree_g1_23dof_channels.h"

#define JOINTS 23
#define POS ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_POSITION
#define VEL ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY
#define KP ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS
#define KD ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_DAMPING
#define TAU ROZ_UNITREE_G1_23DOF_CMD_LEFT_HIP_PITCH_JOINT_EFFORT

_Static_assert(ROZ_UNITREE_G1_23DOF_N_COMMANDS == 5 * JOINTS, "five commands a joint");
_Static_assert(VEL == POS + JOINTS && KP == POS + 2 * JOINTS && KD == POS + 3 * JOINTS &&
                   TAU == POS + 4 * JOINTS,
               "commands grouped by kind, joints in the manifest's order");

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
    double ramp = (double)tick / (double)ROZ_UNITREE_G1_23DOF_CONTROL_RATE_HZ; /* seconds */
    if (ramp > 1.0)
        ramp = 1.0;
    for (int j = 0; j < JOINTS; j++) {
        roz_command_set(POS + j, pose[j]);
        roz_command_set(VEL + j, 0.0);
        roz_command_set(KP + j, ramp * kp[j]);
        roz_command_set(KD + j, kd[j]);
        roz_command_set(TAU + j, 0.0);
    }
}
