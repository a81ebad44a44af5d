/* SPDX-License-Identifier: Apache-2.0 */
/* The hold every stop sends (roz/hold.h). */
#include "roz/hold.h"

static int finite(double v)
{
    return v - v == 0.0; /* NaN unless finite */
}

double roz_hold_setpoint(const roz_hold_from_t *h, double kp_sent, double band)
{
    double p = h->measured, sp = h->setpoint;

    if (!finite(p))
        return sp; /* position unknown: keep the command (NaN: none) */
    if (!finite(sp))
        return p; /* no position command: where the joint is */
    if (finite(h->kp))
        sp = roz_hold_keep_torque(sp, p, h->kp, kp_sent);
    if (!(band >= 0.0))
        band = 0.0;
    return sp < p - band ? p - band : sp > p + band ? p + band : sp;
}

double roz_hold_gain_cap(const roz_hold_from_t *h, double q_sent, double kp_sent,
                         double kp_floor)
{
    double p = h->measured;
    if (!finite(p) || !finite(h->setpoint) || !finite(h->kp) || !finite(q_sent))
        return kp_sent;
    double torque = h->kp * (h->setpoint - p);
    double d = q_sent - p;
    torque = torque < 0.0 ? -torque : torque;
    d = d < 0.0 ? -d : d;
    /* rounding is no excess: the hold's own setpoint gives the torque back
     * within an ulp or two, and must keep its gain */
    if (!(kp_sent * d > torque * (1.0 + ROZ_HOLD_ROUNDING) + ROZ_HOLD_ROUNDING))
        return kp_sent;
    double kp = torque / d;
    return kp > kp_floor ? kp : kp_floor < kp_sent ? kp_floor : kp_sent;
}
