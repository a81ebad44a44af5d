/* SPDX-License-Identifier: Apache-2.0 */
/* The G1 PD of g1_pd.c through the bulk extension: one state.get_all for
 * the snapshot, one command.set_all for all 145 commands, the same
 * arithmetic in between. The command array lives in the controller's
 * memory across ticks, so the velocity, stiffness and damping commands,
 * always 0, are written once (zero-initialised); the legs (60, 1.5) and the
 * rest (30, 0.8) run as two loops. Its targets and counters equal g1_pd's
 * bit for bit (test_bulk); the benchmark times both. */
#include "g1_pd.h"

#define READ (QD + JOINTS) /* the states the PD reads: positions, then velocities */

static double state[READ];
static double cmd[ROZ_UNITREE_G1_N_COMMANDS]; /* VEL, KP, KD stay 0 */

#define LEGS 12

ROZ_PROCESS(tick)
{
    (void)tick;
    roz_state_get_all(state, READ);
    for (int j = 0; j < LEGS; j++) {
        double q = state[Q + j];
        cmd[POS + j] = q;
        cmd[TAU + j] = 60.0 * (q_ref[j] - q) - 1.5 * state[QD + j];
    }
    for (int j = LEGS; j < JOINTS; j++) {
        double q = state[Q + j];
        cmd[POS + j] = q;
        cmd[TAU + j] = 30.0 * (q_ref[j] - q) - 0.8 * state[QD + j];
    }
    roz_command_set_all(cmd, ROZ_UNITREE_G1_N_COMMANDS);
}
