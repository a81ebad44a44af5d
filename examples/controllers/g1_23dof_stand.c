/* SPDX-License-Identifier: Apache-2.0 */
/* Stand for the 23-DoF Unitree G1 (manifest unitree_g1_23dof) that balances:
 * the same joint-space PD toward a slightly crouched pose and the same ankle
 * and hip strategy on the pelvis IMU as g1_stand (stand.h), on the 23 joints
 * this variant has (legs, waist yaw, shoulders, elbows, wrist roll). The
 * robot's own PD runs it; the gains ramp in over the first second. Built a
 * second time with STAND_BALANCE 0 as g1_23dof_stand_pd (the tests'
 * baseline, test/ports/mujoco/test_mujoco_stand.c). */
#include "stand.h"
#include "unitree_g1_23dof_channels.h"

#define JOINTS 23
#define RATE_HZ ((double)ROZ_UNITREE_G1_23DOF_CONTROL_RATE_HZ)

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
/* Target offsets per rad of lean and per rad/s (stand.h): g1_stand's. */
static const stand_balance_t balance = STAND_G1_BALANCE;

STAND_CONTROLLER(ROZ_UNITREE_G1_23DOF, LEFT_HIP_PITCH_JOINT)
