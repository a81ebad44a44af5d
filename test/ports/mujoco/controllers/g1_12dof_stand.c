/* SPDX-License-Identifier: Apache-2.0 */
/* The 12-joint G1 (manifest unitree_g1_12dof: legs driven, upper body
 * rigid) standing on stand.h: unitree_rl_gym's default leg pose, ramped in
 * over the first second, with g1_stand's ankle and hip balance on the pelvis
 * IMU. Stiffer than unitree_rl_gym's deploy gains (kp 100/100/100/150/40/40,
 * which a policy balances on; this stand without one falls forward on them
 * from the model's zero pose, as g1_stand does on the 29-DoF G1 from it):
 * kp 150 at the hips and ankle pitch, 200 at the knees, 100 at ankle roll,
 * inside the manifest's stiffness limits. test/ports/mujoco/CMakeLists.txt
 * runs it: the variant holds the pose. */
#include "stand.h"
#include "unitree_g1_12dof_channels.h"

#define JOINTS 12
#define RATE_HZ ((double)ROZ_UNITREE_G1_12DOF_CONTROL_RATE_HZ)

static const double pose[JOINTS] = {
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, /* left leg */
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, /* right leg */
};
static const double kp[JOINTS] = { 150, 150, 150, 200, 150, 100, 150, 150, 150, 200, 150, 100 };
static const double kd[JOINTS] = { 2, 2, 2, 4, 2, 2, 2, 2, 2, 4, 2, 2 };
static const stand_balance_t balance = STAND_G1_BALANCE;

static const stand_robot_t robot = {
    .joints = JOINTS, .rate_hz = RATE_HZ, .pose = pose, .kp = kp, .kd = kd,
    .balance = &balance,
    STAND_CHANNELS(ROZ_UNITREE_G1_12DOF, LEFT_HIP_PITCH_JOINT),
};

STAND_PROCESS(robot)
