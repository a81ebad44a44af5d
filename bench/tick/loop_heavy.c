/* SPDX-License-Identifier: Apache-2.0 */
/* A loop-heavy controller for the metering benchmark (bench/tick): for the
 * Unitree G1 it computes a joint-space coupling term with a 29 x 29 matrix
 * (a stand-in for the mass-matrix products of a whole-body controller) in
 * nested loops of straight-line arithmetic, then a PD law on top. Most of
 * its time is wasm instructions in loops, not host calls: the case where
 * charging fuel per run of instructions costs the most. */
#include "roz_controller.h"
#include "unitree_g1_channels.h"

#define JOINTS 29
#define Q ROZ_UNITREE_G1_STATE_LEFT_HIP_PITCH_JOINT_POSITION
#define QD ROZ_UNITREE_G1_STATE_LEFT_HIP_PITCH_JOINT_VELOCITY
#define TAU ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_EFFORT
#define POS ROZ_UNITREE_G1_CMD_LEFT_HIP_PITCH_JOINT_POSITION

static double m[JOINTS][JOINTS];
static double q[JOINTS], qd[JOINTS], tau[JOINTS];

ROZ_PROCESS(tick)
{
    for (int i = 0; i < JOINTS; i++) {
        q[i] = roz_state_get(Q + i);
        qd[i] = roz_state_get(QD + i);
    }
    /* a symmetric, diagonally dominant coupling that depends on the pose */
    for (int i = 0; i < JOINTS; i++) {
        for (int j = 0; j < JOINTS; j++) {
            double c = 0.01 * (q[i] - q[j]);
            m[i][j] = (i == j ? 2.0 : 0.05) + c * c * (1.0 - c * c * (1.0 / 6.0));
        }
    }
    for (int i = 0; i < JOINTS; i++) {
        double acc = 0.0;
        for (int j = 0; j < JOINTS; j++)
            acc += m[i][j] * (-0.5 * q[j] - 0.05 * qd[j]);
        tau[i] = acc;
    }
    for (int i = 0; i < JOINTS; i++) {
        roz_command_set(POS + i, q[i]);
        roz_command_set(TAU + i, tau[i] + 0.001 * (double)(tick % 7));
    }
}
