/* SPDX-License-Identifier: Apache-2.0 */
/* Fall detection (roz/fall.h). The tilt is judged on cosines, the rule's
 * cos(max_tilt) computed once with roz_math.h (the same bits on every
 * target; no libm: a libm's cos and acos differ between C libraries and
 * cost an image some 5 KB). */
#include "roz/fall.h"

#include <math.h> /* NAN alone: no libm function is called */

#include "roz_math.h"

#if ROZ_CFG_FALL

/* cos(tilt) of the quaternion in @p state: NaN when unknown. */
static double cos_tilt(const roz_fall_rule_t *r, const double *state)
{
    double x = state[r->quaternion[0]], y = state[r->quaternion[1]];
    double z = state[r->quaternion[2]], w = state[r->quaternion[3]];
    double n = x * x + y * y + z * z + w * w;

    /* n - n is NaN unless n is finite; a zero quaternion has no direction */
    if (!(n - n == 0.0) || !(n > 0.0))
        return NAN;
    return (w * w + z * z - x * x - y * y) / n;
}

void roz_fall_init(roz_fall_t *f, const roz_manifest_t *m)
{
    const roz_fall_rule_t *r = m->fall;
    uint64_t ticks;

    f->rule = r;
    f->run = 0;
    f->cos_max = 1.0;
    f->need = 1;
    if (r == NULL)
        return;
    f->cos_max = roz_math_cos(r->max_tilt);
    ticks = ((uint64_t)r->for_ms * m->control_rate_hz + 999u) / 1000u;
    f->need = ticks > 1u ? (uint32_t)ticks : 1u;
}

int roz_fall_tick(roz_fall_t *f, const double *state)
{
    if (f->rule == NULL)
        return 0;
    double c = cos_tilt(f->rule, state);
    /* beyond the angle: cos(tilt) < cos(max_tilt) (cos falls on [0, pi]);
     * at it, not beyond; NaN compares false */
    if (c < f->cos_max) {
        if (f->run < f->need)
            f->run++;
    } else if (c == c) {
        f->run = 0; /* upright again; an unknown tilt leaves the count */
    }
    return f->run >= f->need;
}

double roz_fall_tilt(const roz_fall_rule_t *rule, const double *state)
{
    const int32_t *q = rule->quaternion;
    double x = state[q[0]], y = state[q[1]], z = state[q[2]], w = state[q[3]];
    double n = x * x + y * y + z * z + w * w;

    if (!(n - n == 0.0) || !(n > 0.0))
        return NAN;
    /* the base's z axis in the world, times |q|^2: its horizontal part's
     * length and its vertical part, whose angle is the tilt (accurate near
     * 0 and pi too, where acos of a cosine is not) */
    double hx = 2.0 * (x * z + w * y) / n, hy = 2.0 * (y * z - w * x) / n;
    return roz_math_atan2(roz_math_sqrt(hx * hx + hy * hy), (w * w + z * z - x * x - y * y) / n);
}

#else /* the fall rule left out: roz_runtime_init() refuses a manifest with one */

void roz_fall_init(roz_fall_t *f, const roz_manifest_t *m)
{
    (void)m;
    f->rule = NULL;
    f->cos_max = 1.0;
    f->need = 1;
    f->run = 0;
}

int roz_fall_tick(roz_fall_t *f, const double *state)
{
    (void)f;
    (void)state;
    return 0;
}

double roz_fall_tilt(const roz_fall_rule_t *rule, const double *state)
{
    (void)rule;
    (void)state;
    return NAN;
}

#endif /* ROZ_CFG_FALL */
