/* SPDX-License-Identifier: Apache-2.0 */
/* Hover (quadcopter): climbs to HEIGHT above where it stood and holds there,
 * over the point it took off from, heading held -- a position loop over the
 * autopilot's velocity mode: each axis gets a velocity proportional to its
 * error (K 1/s), capped (VXY, VZ), the horizontal one turned into the
 * heading frame the commands are in. The height error (m) is emitted as a
 * metric each tick. */
#include "roz_controller.h"
#include "roz_math.h"
#include "quadcopter_channels.h"

#define HEIGHT 1.5  /* m above the start */
#define K      1.5  /* 1/s */
#define VXY    1.0  /* m/s */
#define VZ     1.0  /* m/s */
#define K_YAW  2.0  /* 1/s */

static int started;
static double home_x, home_y, home_z, home_yaw;

ROZ_PROCESS(tick)
{
    double x = roz_state_get(ROZ_QUADCOPTER_STATE_BODY_POSITION_X);
    double y = roz_state_get(ROZ_QUADCOPTER_STATE_BODY_POSITION_Y);
    double z = roz_state_get(ROZ_QUADCOPTER_STATE_BODY_POSITION_Z);
    double yaw = roz_state_get(ROZ_QUADCOPTER_STATE_BODY_YAW);
    (void)tick;
    if (!started) {
        started = 1;
        home_x = x;
        home_y = y;
        home_z = z;
        home_yaw = yaw;
    }
    double ex = home_x - x, ey = home_y - y, ez = home_z + HEIGHT - z;
    double c = roz_math_cos(yaw), s = roz_math_sin(yaw);
    roz_command_set(ROZ_QUADCOPTER_CMD_BODY_VELOCITY_X, roz_math_clamp(K * (c * ex + s * ey), -VXY, VXY));
    roz_command_set(ROZ_QUADCOPTER_CMD_BODY_VELOCITY_Y, roz_math_clamp(K * (-s * ex + c * ey), -VXY, VXY));
    roz_command_set(ROZ_QUADCOPTER_CMD_BODY_VELOCITY_Z, roz_math_clamp(K * ez, -VZ, VZ));
    roz_command_set(ROZ_QUADCOPTER_CMD_BODY_YAW_RATE, roz_math_clamp(K_YAW * (home_yaw - yaw), -1.0, 1.0));
    roz_emit_metric(ez);
}
