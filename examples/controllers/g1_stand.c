/* SPDX-License-Identifier: Apache-2.0 */
/* Humanoid stand for the Unitree G1 (29 DoF) that balances: joint-space PD on
 * all 29 joints toward a slightly crouched standing pose, with unitree_rl_gym's
 * gains (hips 100, knees 150, ankles 40), plus an ankle and hip strategy on
 * the pelvis IMU: the lean (roll, pitch) and its rate move the ankles' and
 * hip pitches' targets so the feet push the body back over them (stand.h).
 * The robot's own PD runs it: we send the targets, zero velocity and
 * feed-forward torque, and the gains, ramped in over the first second.
 * Alone, the joint PD does not hold the G1 up: its ankles' kp 40 give both
 * feet 80 N.m a radian of lean against gravity's ~240 (docs/ports/mujoco.md).
 * Built a second time with STAND_BALANCE 0 as g1_stand_pd (the tests'
 * baseline, test/ports/mujoco/test_mujoco_stand.c). */
#include "stand.h"
#include "unitree_g1_channels.h"

#define JOINTS 29
#define RATE_HZ ((double)ROZ_UNITREE_G1_CONTROL_RATE_HZ)

/* Standing pose in SDK joint order (rad). */
static const double pose[JOINTS] = STAND_G1_POSE;
/* Gains per joint (legs stiffer than arms). */
static const double kp[JOINTS] = {
    100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40, 100, 40, 40,
    40, 40, 40, 40, 20, 20, 20, 40, 40, 40, 40, 20, 20, 20,
};
static const double kd[JOINTS] = {
    2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2, 2, 2, 2,
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
};
/* Target offsets per rad of lean and per rad/s (stand.h). */
static const stand_balance_t balance = STAND_G1_BALANCE;

STAND_CONTROLLER(ROZ_UNITREE_G1, LEFT_HIP_PITCH_JOINT)
