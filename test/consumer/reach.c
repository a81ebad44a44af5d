/* SPDX-License-Identifier: Apache-2.0 */
/* The consumer's own controller, built for wasm32 by roz_add_wasm_controller()
 * with the SDK roz provides and the channel header rozgen makes from the
 * consumer's robot.toml: joint2 goes to 1 rad, joint1 stays where it is. */
#include "my_arm_channels.h"
#include "roz_controller.h"

ROZ_PROCESS(tick)
{
    (void)tick;
    double q = roz_state_get(ROZ_MY_ARM_STATE_JOINT2_POSITION);
    roz_command_set(ROZ_MY_ARM_CMD_JOINT2_VELOCITY, 2.0 * (1.0 - q));
    roz_command_set(ROZ_MY_ARM_CMD_JOINT1_VELOCITY, 0.0);
}
