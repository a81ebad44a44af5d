/* SPDX-License-Identifier: Apache-2.0 */
/* Stand for the AgiBot X2 that balances: joint-space PD on all 30 joints
 * toward a slightly crouched pose, run by the robot's own PD (position
 * target, zero velocity and feed-forward torque, and the gains, which ramp
 * in over the first second), with the G1 stand's balance (stand.h): ankle
 * pitch from the pelvis's sway over the ankles, hip pitch from its tilt,
 * read off the IMU, and ankle roll from its roll (sideways pushes). Hip yaw
 * gains are the vendor example's (kp 30, kd 3); the hip pitch, hip roll,
 * knee and ankle gains (kp 100/100/150/80/40, kd 4/4/6/3/2: the example's
 * 40/40/80/40/20 let the robot sink and fall within 2 s in MuJoCo, and take
 * a third of the sideways push), the waist, arm and head gains and the
 * pose are ours. Built a
 * second time with STAND_BALANCE 0 as x2_stand_pd (the tests' baseline,
 * test/ports/mujoco/test_mujoco_stand.c). */
#include "stand.h"
#include "agibot_x2_channels.h"

#define JOINTS 30
#define RATE_HZ ((double)ROZ_AGIBOT_X2_CONTROL_RATE_HZ)

/* Standing pose in HAL group order (rad). */
static const double pose[JOINTS] = STAND_X2_POSE;
static const double kp[JOINTS] = {
    100, 100, 30, 150, 80, 40, 100, 100, 30, 150, 80, 40, 100, 100, 100,
    30, 30, 30, 30, 10, 10, 10, 30, 30, 30, 30, 10, 10, 10, 10,
};
static const double kd[JOINTS] = {
    4, 4, 3, 6, 3, 2, 4, 4, 3, 6, 3, 2, 3, 3, 3,
    2, 2, 2, 2, 1, 1, 1, 2, 2, 2, 2, 1, 1, 1, 1,
};

/* Target offsets per rad of lean and per rad/s (stand.h): the G1's ankle
 * and hip strategy, on the X2's legs (the same joint order: hip pitch,
 * roll, yaw, knee, ankle pitch, roll). */
static const stand_balance_t balance = {
    .ankle_pitch = 3.0, .ankle_pitch_rate = 0.3,
    .ankle_roll = 1.0, .ankle_roll_rate = 0.1,
    .hip_pitch = 1.0, .hip_pitch_rate = 0.1,
    .limit = 0.4, .sway = 0.05,
};

STAND_CONTROLLER(ROZ_AGIBOT_X2, LEFT_HIP_PITCH_JOINT)
