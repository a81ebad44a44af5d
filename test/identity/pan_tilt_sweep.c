/* SPDX-License-Identifier: Apache-2.0 */
/* A pan-tilt controller built with the SDK and the generated header of
 * pan_tilt.toml, so it carries the identity of that robot: a slow pan sweep
 * on control time, the tilt held level by a P term on its position. */
#include "roz_controller.h"
#include "pan_tilt_channels.h"

#define TWO_PI 6.283185307179586

ROZ_PROCESS(tick)
{
    (void)tick;
    double t = (double)roz_sim_time_ns() * 1e-9;
    roz_command_set(ROZ_PAN_TILT_CMD_PAN_VELOCITY, 0.5 * roz_sin(TWO_PI * 0.2 * t));
    roz_command_set(ROZ_PAN_TILT_CMD_TILT_VELOCITY,
                    -2.0 * roz_state_get(ROZ_PAN_TILT_STATE_TILT_POSITION));
}
