/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/filter.h"

#include <math.h>
#include <string.h>

/* ---- private ------------------------------------------------------------- */

static double clampd(double v, double lo, double hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

/* Largest speed from which a joint braking by at most `rate` per tick (0 =
 * no cap: it can stop in one tick) stays within `dist` (>= 0). Braking from
 * v covers dt*(v + (v-r) + (v-2r) + ...); the closed form below is the
 * continuous version of that sum, short of the discrete one by at most r*dt/8,
 * which the r*dt/4 taken off the distance covers. The one-step bound
 * v*dt <= dist always applies as well. */
static double brake_speed(double dist, double rate, double dt)
{
    double one_step = dist / dt;
    if (rate <= 0.0)
        return one_step;
    double d = dist - rate * dt / 4.0;
    if (d <= 0.0)
        return 0.0;
    double v = rate * (-0.5 + sqrt(0.25 + 2.0 * d / (rate * dt)));
    return v < one_step ? v : one_step;
}

/* ---- public -------------------------------------------------------------- */

int roz_filter_init(roz_filter_t *f, const roz_manifest_t *m)
{
    if (f == NULL || m == NULL || roz_manifest_validate(m, NULL) != ROZ_OK)
        return ROZ_EINVAL;
    memset(f, 0, sizeof *f);
    f->manifest = m;
    f->dt = 1.0 / (double)m->control_rate_hz;
    return ROZ_OK;
}

double roz_filter_safe_default(const roz_filter_t *f, uint16_t i, const double *state)
{
    const roz_channel_t *c = &f->manifest->commands[i];

    if (c->type == ROZ_IF_POSITION && c->position_state != ROZ_CHANNEL_UNPAIRED) {
        double held = state != NULL ? state[c->position_state] : NAN;
        if (isfinite(held))
            return clampd(held, c->min, c->max);
        /* Position unknown: keep the last target rather than jump to the
         * manifest default, which may be far from where the joint is. */
        if (f->primed)
            return f->last[i];
    }
    return c->default_value;
}

void roz_filter_prime(roz_filter_t *f, const double *state)
{
    for (uint16_t i = 0; i < f->manifest->n_commands; i++)
        f->last[i] = roz_filter_safe_default(f, i, state);
    f->primed = 1;
}

void roz_filter_apply(roz_filter_t *f, const double *target, const double *state,
                      roz_stop_t stop, double *out)
{
    const roz_manifest_t *m = f->manifest;

    if (!f->primed)
        roz_filter_prime(f, state);
    f->counters.ticks++;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        double v = stop == ROZ_STOP_NONE ? target[i] : roz_filter_safe_default(f, i, state);
        int held = 0; /* held back by position-limit enforcement this tick */

        /* 1. non-finite: the safe default */
        if (!isfinite(v)) {
            f->counters.nonfinite++;
            v = roz_filter_safe_default(f, i, state);
        }
        /* 2. clamp */
        if (v < c->min || v > c->max) {
            v = clampd(v, c->min, c->max);
            f->counters.clamps++;
            f->channel_clamps[i]++;
        }
        /* 3. rate cap against the last applied value; an e-stop skips it */
        if (c->max_rate > 0.0 && stop != ROZ_STOP_IMMEDIATE) {
            double lo = f->last[i] - c->max_rate, hi = f->last[i] + c->max_rate;
            if (v < lo || v > hi) {
                v = clampd(v, lo, hi);
                f->counters.rate_caps++;
                f->channel_rate_caps[i]++;
            }
        }
        /* 4. position limits through the paired position state */
        if (c->type == ROZ_IF_VELOCITY && c->position_state != ROZ_CHANNEL_UNPAIRED &&
            state != NULL) {
            const roz_channel_t *ps = &m->states[c->position_state];
            double p = state[c->position_state];
            double margin = roz_manifest_limit_margin(ps);
            double lo = ps->min + margin, hi = ps->max - margin;
            double limited = v;

            if (!isfinite(p)) {
                /* position unknown: stop, also when zero is a limit itself */
                limited = 0.0 >= c->min && 0.0 <= c->max ? 0.0 : c->default_value;
            } else if (v > 0.0) {
                limited = p >= hi ? 0.0 : fmin(v, brake_speed(hi - p, c->max_rate, f->dt));
            } else if (v < 0.0) {
                limited = p <= lo ? 0.0 : fmax(v, -brake_speed(p - lo, c->max_rate, f->dt));
            }
            if (limited != v) {
                v = limited;
                f->counters.limit_stops++;
                f->channel_limit_stops[i]++;
                held = 1;
            }
        }
        /* 4b. an effort paired with a position state may not push further
         * out: at or past the limit less the margin, an effort toward the
         * outside becomes 0; with the position unknown, 0 (no rate cap:
         * the limit wins, as for a velocity) */
        if (c->type == ROZ_IF_EFFORT && c->position_state != ROZ_CHANNEL_UNPAIRED &&
            state != NULL) {
            const roz_channel_t *ps = &m->states[c->position_state];
            double p = state[c->position_state];
            double margin = roz_manifest_limit_margin(ps);
            int outward = !isfinite(p) ? v != 0.0
                                       : (v > 0.0 && p >= ps->max - margin) ||
                                             (v < 0.0 && p <= ps->min + margin);
            if (outward) {
                v = 0.0;
                f->counters.limit_stops++;
                f->channel_limit_stops[i]++;
                held = 1;
            }
        }
        if (!held) {
            f->channel_stop_run[i] = 0;
        } else if (f->channel_stop_run[i] < UINT32_MAX) {
            f->channel_stop_run[i]++;
            if (f->channel_stop_run[i] > f->channel_stop_longest[i])
                f->channel_stop_longest[i] = f->channel_stop_run[i];
        }
        /* 5. whatever happened above, the port gets a value in [min, max] */
        if (!(v >= c->min && v <= c->max))
            v = isfinite(v) ? clampd(v, c->min, c->max) : c->default_value;
        f->last[i] = v;
        out[i] = v;
    }
}

void roz_filter_counters_get(const roz_filter_t *f, roz_filter_counters_t *out)
{
    *out = f->counters;
}

int roz_filter_channel_counters_get(const roz_filter_t *f, size_t channel,
                                    roz_filter_channel_counters_t *out)
{
    if (channel >= f->manifest->n_commands || channel >= ROZ_CFG_MAX_COMMANDS) {
        memset(out, 0, sizeof *out);
        return ROZ_ENOENT;
    }
    out->clamps = f->channel_clamps[channel];
    out->rate_caps = f->channel_rate_caps[channel];
    out->limit_stops = f->channel_limit_stops[channel];
    out->stop_run = f->channel_stop_run[channel];
    out->stop_longest = f->channel_stop_longest[channel];
    return ROZ_OK;
}
