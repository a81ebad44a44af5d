/* SPDX-License-Identifier: Apache-2.0 */
/* The socketcan port's holds (roz/port/can_hold.h). */
#include "roz/port/can_hold.h"

#include "roz/hold.h"
#include "roz/hal/joints.h"

#include <math.h>

static int finite(double v)
{
    return v - v == 0.0; /* NaN unless finite */
}

/* A channel's default, inside it; 0 without the channel. */
static double hold_value(const roz_manifest_t *m, int32_t ch)
{
    return ch >= 0 ? roz_channel_clamp(&m->commands[ch], m->commands[ch].default_value) : 0.0;
}

/* 0 as the channel allows it; 0 without the channel. */
static double neutral(const roz_manifest_t *m, int32_t ch)
{
    return ch >= 0 ? roz_channel_clamp(&m->commands[ch], 0.0) : 0.0;
}

double roz_can_hold_damping(const roz_manifest_t *m, const roz_can_joint_t *jt)
{
    return hold_value(m, jt->kd_cmd);
}

void roz_can_watchdog_hold(const roz_manifest_t *m, const roz_can_joint_t *jt,
                           const roz_can_last_t *last, double measured, roz_mit_command_t *out)
{
    double dir = (double)jt->direction;
    double kp = hold_value(m, jt->kp_cmd);
    /* roz/hold.h's hold from the last command that went out: its torque
     * kept under the hold gain, within the band of the position measured
     * with it (now, without one); the measured position without a command */
    roz_hold_from_t from = { NAN, NAN, measured };
    if (last->sent) {
        from.setpoint = jt->pos_cmd >= 0 ? last->position : NAN;
        from.kp = jt->kp_cmd >= 0 ? last->stiffness : NAN;
        if (finite(last->measured))
            from.measured = last->measured;
    }
    double band = jt->pos_cmd >= 0 ? roz_hold_band(&m->commands[jt->pos_cmd]) : 0.0;
    double q = roz_hold_setpoint(&from, jt->kp_cmd >= 0 ? kp : NAN, band);
    if (!finite(q)) {
        /* nothing to hold: no stiffness (test_can_hold_without_a_command_
         * or_finite_values) */
        q = jt->pos_cmd >= 0 ? roz_channel_clamp(&m->commands[jt->pos_cmd], jt->zero_offset)
                             : jt->zero_offset;
        kp = neutral(m, jt->kp_cmd);
    } else if (jt->pos_cmd >= 0) {
        q = roz_channel_clamp(&m->commands[jt->pos_cmd], q);
    }
    out->position = dir * (q - jt->zero_offset);
    out->velocity = dir * neutral(m, jt->vel_cmd);
    out->kp = kp;
    out->kd = roz_can_hold_damping(m, jt);
    out->torque = dir * neutral(m, jt->eff_cmd);
}
