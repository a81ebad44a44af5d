/* SPDX-License-Identifier: Apache-2.0 */
/* The G1 PD of g1_pd.c through the bulk extension: one state.get_all for
 * the snapshot, one command.set_all for all 145 commands, the same
 * arithmetic in between. Its targets and counters equal g1_pd's bit for bit
 * (test_bulk); the benchmark times both. */
#include "roz_controller.h"
#include "unitree_g1_channels.h"

#define JOINTS 29
#define Q ROZ_UNITREE_G1_STATE_LEFT_HIP_PITCH_JOINT_POSITION
#define QD ROZ_UNITREE_G1_STATE_LEFT_HIP_PITCH_JOINT_VELOCITY
#define POS ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_POSITION
#define VEL ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_VELOCITY
#define KP ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_STIFFNESS
#define KD ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_DAMPING
#define TAU ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_EFFORT
#define READ (QD + JOINTS) /* the states the PD reads: positions, then velocities */

static const double q_ref[JOINTS] = {
    -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, -0.1, 0.0, 0.0, 0.3, -0.2, 0.0, 0.0, 0.0, 0.0,
    0.2,  0.2, 0.0, 0.9, 0.0,  0.0, 0.0,  0.2, -0.2, 0.0, 0.9, 0.0, 0.0, 0.0,
};

static double state[READ];
static double cmd[ROZ_UNITREE_G1_N_COMMANDS];

ROZ_PROCESS(tick)
{
    (void)tick;
    roz_state_get_all(state, READ);
    for (int j = 0; j < JOINTS; j++) {
        double q = state[Q + j];
        double qd = state[QD + j];
        double kp = j < 12 ? 60.0 : 30.0;
        double kd = j < 12 ? 1.5 : 0.8;
        cmd[POS + j] = q;
        cmd[VEL + j] = 0.0;
        cmd[KP + j] = 0.0;
        cmd[KD + j] = 0.0;
        cmd[TAU + j] = kp * (q_ref[j] - q) - kd * qd;
    }
    roz_command_set_all(cmd, ROZ_UNITREE_G1_N_COMMANDS);
}
