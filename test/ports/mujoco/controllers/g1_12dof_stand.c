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
static const stand_balance_t balance = {
    .ankle_pitch = 3.0, .ankle_pitch_rate = 0.3,
    .ankle_roll = 0.0, .ankle_roll_rate = 0.0,
    .hip_pitch = 1.0, .hip_pitch_rate = 0.1,
    .limit = 0.4, .sway = -0.05,
};

static const stand_robot_t robot = {
    .joints = JOINTS, .rate_hz = RATE_HZ, .pose = pose, .kp = kp, .kd = kd,
    .balance = &balance,
    .quat = ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ORIENTATION_X,
    .gyro = ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ANGULAR_VELOCITY_X,
    .legs = ROZ_UNITREE_G1_12DOF_STATE_LEFT_HIP_PITCH_JOINT_POSITION,
    .pos = ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_POSITION,
    .vel = ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY,
    .kp0 = ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS,
    .kd0 = ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_DAMPING,
    .tau = ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_EFFORT,
};

ROZ_PROCESS(tick)
{
    stand_tick(tick, &robot);
}
