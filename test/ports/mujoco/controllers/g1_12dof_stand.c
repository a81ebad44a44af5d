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

ROZ_PROCESS(tick)
{
    static double sway_prev; /* the last valid sway, for its rate */
    static int have_prev;
    double target[JOINTS];
    for (int j = 0; j < JOINTS; j++)
        target[j] = pose[j];
    double ramp = (double)tick / RATE_HZ;
    stand_lean_t lean = stand_lean(ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ORIENTATION_X,
                                   ROZ_UNITREE_G1_12DOF_STATE_BASE_IMU_ANGULAR_VELOCITY_X,
                                   ROZ_UNITREE_G1_12DOF_STATE_LEFT_HIP_PITCH_JOINT_POSITION);
    double sway_rate = have_prev && lean.valid ? (lean.sway - sway_prev) * RATE_HZ : 0.0;
    have_prev = lean.valid;
    sway_prev = lean.sway;
    stand_balance(target, pose, &lean, sway_rate, &balance, ramp < 1.0 ? ramp : 1.0);
    stand_step(tick, RATE_HZ, JOINTS, target, kp, kd,
               ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_POSITION,
               ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY,
               ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS,
               ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_DAMPING,
               ROZ_UNITREE_G1_12DOF_CMD_LEFT_HIP_PITCH_JOINT_EFFORT);
}
