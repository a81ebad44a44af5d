/* SPDX-License-Identifier: Apache-2.0 */
/* Fall detection (roz/fall.h). */
#include "roz/fall.h"

#include <math.h>

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
    f->cos_max = cos(r->max_tilt);
    ticks = ((uint64_t)r->for_ms * m->control_rate_hz + 999u) / 1000u;
    f->need = ticks > 1u ? (uint32_t)ticks : 1u;
}

int roz_fall_tick(roz_fall_t *f, const double *state)
{
    if (f->rule == NULL)
        return 0;
    double c = cos_tilt(f->rule, state);
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
    double c = cos_tilt(rule, state);
    return c == c ? acos(c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c) : NAN;
}
