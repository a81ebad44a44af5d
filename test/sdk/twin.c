/* SPDX-License-Identifier: Apache-2.0 */
/* The C twin (twin.h): twin.rs computes the same, operation for operation. */
#include "roz_controller.h"
#include "roz_math.h"
#include "twin.h"
#include "ur5_channels.h"

ROZ_FUEL_PER_TICK(TWIN_FUEL);

ROZ_PROCESS(tick)
{
    double s[ROZ_UR5_N_STATES], c[ROZ_UR5_N_COMMANDS];
    double t = (double)roz_sim_time_ns() * 1e-9;
    if (roz_state_get_all(s, ROZ_UR5_N_STATES) != ROZ_UR5_N_STATES) {
        roz_request_estop();
        return;
    }
    for (int j = 0; j < ROZ_UR5_N_COMMANDS; j++) {
        double q = s[ROZ_UR5_STATE_SHOULDER_PAN_JOINT_POSITION + j];
        double v = s[ROZ_UR5_STATE_SHOULDER_PAN_JOINT_VELOCITY + j];
        double phase = 0.7 * t + 0.5 * (double)j;
        double target = 0.6 * roz_math_sin(phase) * roz_math_cos(0.3 * t) +
                        0.1 * roz_math_atan2(q, 1.0 + v * v);
        double gain = roz_math_sqrt(1.0 + roz_math_fabs(q)) * roz_math_exp(-0.1 * roz_math_fabs(v));
        double e = target - q;
        c[j] = 2.5 * roz_math_tanh(gain * e) + 0.05 * roz_math_log(1.0 + e * e) -
               0.01 * roz_math_pow(roz_math_fabs(e), 1.5) +
               0.02 * (roz_sin(phase) - roz_cos(phase));
    }
    c[0] = 4.0 * roz_math_sin(0.9 * t + roz_math_copysign(0.25, c[0])); /* beyond +-3.14 */
    roz_emit_metric((double)roz_command_set_all(c, ROZ_UR5_N_COMMANDS));
    roz_emit_metric((double)roz_command_set(ROZ_UR5_CMD_WRIST_3_JOINT_VELOCITY,
                                            roz_math_clamp(c[5] * 1.5, -0.5, 0.5)));
    roz_emit_metric(roz_math_floor(t * 3.0) + roz_math_ceil(-t) + roz_math_trunc(t * 0.5) +
                    roz_math_fmin(t, 2.0) + roz_math_fmax(t - 5.0, -0.0) + (double)(tick % 7));
}
