/* SPDX-License-Identifier: Apache-2.0 */
/* Torque-level PD for the Unitree G1, computed in the controller: for every
 * joint tau = kp * (q_ref - q) - kd * qdot, sent as the effort command with
 * the motor's own gains at zero and its position target holding q. Reads 58
 * states and writes all 145 commands each tick: the benchmark's workload. */
#include "g1_pd.h"

ROZ_PROCESS(tick)
{
    (void)tick;
    for (int j = 0; j < JOINTS; j++) {
        double q = roz_state_get(Q + j);
        double qd = roz_state_get(QD + j);
        double kp = j < 12 ? 60.0 : 30.0;
        double kd = j < 12 ? 1.5 : 0.8;
        roz_command_set(POS + j, q);
        roz_command_set(VEL + j, 0.0);
        roz_command_set(KP + j, 0.0);
        roz_command_set(KD + j, 0.0);
        roz_command_set(TAU + j, kp * (q_ref[j] - q) - kd * qd);
    }
}
