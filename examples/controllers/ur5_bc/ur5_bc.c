/* SPDX-License-Identifier: Apache-2.0 */
/* A learned UR5 hold: the network train.py distilled from pd_hold.c by
 * behaviour cloning (12 -> 32 tanh -> 6, through roz_nn.h and the nn
 * imports) maps the joint positions and velocities to the velocity
 * commands, every tick. It holds the arm at pd_hold's pose
 * (test/nn/test_nn_bc.c). */
#include "roz_controller.h"
#include "roz_nn.h"
#include "ur5_channels.h"

#include "bc_net.h"

_Static_assert(BC_N_IN == 12 && BC_N_OUT == 6, "the distilled hold's shape");

static double s[12];
static float in[BC_N_IN], out[BC_N_OUT];

ROZ_PROCESS(tick)
{
    (void)tick;
    roz_state_get_all(s, 12); /* 6 positions, then 6 velocities */
    for (int k = 0; k < 12; k++)
        in[k] = (float)s[k];
    if (bc_forward(in, out) != 0) {
        roz_request_estop();
        return;
    }
    for (int j = 0; j < 6; j++)
        roz_command_set(ROZ_UR5_CMD_SHOULDER_PAN_JOINT_VELOCITY + j, (double)out[j]);
}
