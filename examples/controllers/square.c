/* SPDX-License-Identifier: Apache-2.0 */
/* Square (diff_drive): the base drives a 1 m square counter-clockwise and
 * stops where it started, on its odometry alone -- four legs of SIDE metres
 * at up to VMAX, each followed by a 90 degree turn in place, with the
 * heading held on the legs. Each leg ends when the distance along its
 * heading reaches SIDE, each turn when the unwrapped heading is within
 * TURN_TOL of its target; both approach their end slowing down (P laws).
 * The phase (0..8; 8: done) is emitted as a metric each tick. */
#include "roz_controller.h"
#include "roz_math.h"
#include "diff_drive_channels.h"

#define SIDE     1.0    /* m */
#define VMAX     0.3    /* m/s */
#define WMAX     1.0    /* rad/s */
#define K_DIST   1.5    /* 1/s: speed per metre left */
#define K_HEAD   3.0    /* 1/s: turn rate per radian of heading error */
#define TURN_TOL 0.005  /* rad */
#define HALF_PI  1.5707963267948966
#define PI       3.141592653589793

static int phase;              /* even: a leg, odd: a turn; 8: done */
static int started;
static double leg_x, leg_y;          /* where the current leg began */
static double yaw_prev, yaw_u; /* the odometry's heading, unwrapped */

ROZ_PROCESS(tick)
{
    double x = roz_state_get(ROZ_DIFF_DRIVE_STATE_BASE_ODOM_X);
    double y = roz_state_get(ROZ_DIFF_DRIVE_STATE_BASE_ODOM_Y);
    double yaw = roz_state_get(ROZ_DIFF_DRIVE_STATE_BASE_ODOM_YAW);
    double v = 0.0, w = 0.0;
    (void)tick;
    if (!started) {
        started = 1;
        leg_x = x;
        leg_y = y;
        yaw_prev = yaw;
        yaw_u = yaw;
    }
    double d = yaw - yaw_prev; /* the step, across the +-pi wrap */
    if (d > PI)
        d -= 2.0 * PI;
    else if (d < -PI)
        d += 2.0 * PI;
    yaw_u += d;
    yaw_prev = yaw;

    double heading = (double)((phase + 1) / 2) * HALF_PI; /* this phase's target */
    double err = heading - yaw_u;
    if (phase < 8 && phase % 2 == 0) {
        double along = (x - leg_x) * roz_math_cos(heading) + (y - leg_y) * roz_math_sin(heading);
        double left = SIDE - along;
        if (left <= 0.0) {
            phase++;
        } else {
            v = roz_math_clamp(K_DIST * left + 0.02, 0.0, VMAX);
            w = roz_math_clamp(K_HEAD * err, -WMAX, WMAX);
        }
    } else if (phase < 8) {
        if (roz_math_fabs(err) < TURN_TOL) {
            phase++;
            leg_x = x;
            leg_y = y;
        } else {
            w = roz_math_clamp(K_HEAD * err, -WMAX, WMAX);
        }
    }
    roz_command_set(ROZ_DIFF_DRIVE_CMD_BASE_LINEAR_X, v);
    roz_command_set(ROZ_DIFF_DRIVE_CMD_BASE_ANGULAR_Z, w);
    roz_emit_metric((double)phase);
}
