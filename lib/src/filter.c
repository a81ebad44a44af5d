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

/* Every rule on one value v of command i (after the stop mode chose it),
 * with the counters: the filter's definition, step by step. `capped`: the
 * rate cap applies (not an e-stop). */
static double channel_apply(roz_filter_t *f, uint16_t i, double v, const double *state,
                            int capped)
{
    const roz_manifest_t *m = f->manifest;
    const roz_channel_t *c = &m->commands[i];
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
    if (c->max_rate > 0.0 && capped) {
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
        double margin = f->margin[c->position_state];
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
        double margin = f->margin[c->position_state];
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
    return v;
}

/* Step 4 ahead of the rest: whether it may change each paired command's
 * target this tick (pair_acts[]). It changes nothing for a velocity of 0
 * with the position known, nor for an effort that does not push out (or is
 * 0 while the position is unknown); every other case goes through
 * channel_apply(). The tests are the rules' conditions, written the same
 * way. Without a snapshot step 4 does nothing. Returns how many may. */
static size_t pairs_check(roz_filter_t *f, const double *target, const double *state)
{
    size_t k = 0, acting = 0;

    if (state == NULL) {
        for (; k < f->n_paired; k++)
            f->pair_acts[f->paired[k]] = 0;
        return 0;
    }
    for (; k < f->n_velocity; k++) {
        double v = target[f->paired[k]], p = state[f->pair_state[k]];
        uint8_t acts = !(v == 0.0 && isfinite(p));
        f->pair_acts[f->paired[k]] = acts;
        acting += acts;
    }
    for (; k < f->n_paired; k++) {
        double v = target[f->paired[k]], p = state[f->pair_state[k]];
        uint8_t acts = !isfinite(p) ? v != 0.0
                                    : (v > 0.0 && p >= f->pair_hi[k]) ||
                                          (v < 0.0 && p <= f->pair_lo[k]);
        f->pair_acts[f->paired[k]] = acts;
        acting += acts;
    }
    return acting;
}

/* One value of an ordinary tick (no stop): as it is when it passes steps 1
 * to 3 and step 4 leaves its channel alone, else through every rule. Step
 * 4 is asked first: it costs a byte, the bounds cost double arithmetic (a
 * library call each on a core without a double FPU). */
static double tick_value(roz_filter_t *f, size_t i, double v, const double *state)
{
    if (!f->pair_acts[i]) {
        const roz_channel_t *c = &f->manifest->commands[i];
        double last = f->last[i], lo = c->min, hi = c->max;
        if (c->max_rate > 0.0) {
            double below = last - c->max_rate, above = last + c->max_rate;
            lo = below > lo ? below : lo;
            hi = above < hi ? above : hi;
        }
        if (v >= lo && v <= hi) {
            f->channel_stop_run[i] = 0;
            return v;
        }
    }
    return channel_apply(f, (uint16_t)i, v, state, 1);
}

#if ROZ__FILTER_AVX2
/* Steps 1 to 3 on AVX2 vectors (GCC and Clang vector extensions), called
 * only when the CPU has them, a group of four channels at a time (the last
 * group may be shorter): whether its targets pass untouched, within [min,
 * max] and within the rate cap of the last applied value, the cap's bounds
 * computed as step 3 computes them (last -/+ max_rate; a cap of +inf:
 * none). Every comparison with NaN is false, so NaN fails. The targets are
 * copied to out on the way (out may be target): they are the outputs of
 * the groups that pass; the rules write the others again, from the targets
 * and the last values, which the tests leave alone. */
#define GROUP 4u
#define GROUP_WORDS ((ROZ_CFG_MAX_COMMANDS + GROUP - 1u) / GROUP / 64u + 1u)

typedef double roz__v4d __attribute__((vector_size(32)));
typedef long long roz__v4l __attribute__((vector_size(32)));

__attribute__((target("avx2"))) static inline roz__v4d load4(const double *p)
{
    roz__v4d v;
    memcpy(&v, p, sizeof v);
    return v;
}

/* Steps 1 to 3 on channels [i, i + 4), target copied to out. */
__attribute__((target("avx2"))) static inline roz__v4l pass4(const roz_filter_t *f,
                                                             const double *target, size_t i,
                                                             double *out)
{
    roz__v4d v = load4(&target[i]), last = load4(&f->last[i]), rate = load4(&f->pass_rate[i]);
    memcpy(&out[i], &v, sizeof v);
    return (v >= load4(&f->pass_min[i])) & (v <= load4(&f->pass_max[i])) & (v >= last - rate) &
           (v <= last + rate);
}

/* The same on the channels [i, n) of the last group, one at a time. */
__attribute__((target("avx2"))) static inline int pass_tail(const roz_filter_t *f,
                                                             const double *target, size_t i,
                                                             size_t n, double *out)
{
    int pass = 1;
    for (; i < n; i++) {
        double v = target[i], last = f->last[i], rate = f->pass_rate[i];
        pass &= (v >= f->pass_min[i]) & (v <= f->pass_max[i]) & (v >= last - rate) &
                (v <= last + rate);
        out[i] = v;
    }
    return pass;
}

/* Whether every group passes (the usual tick, so the test is kept to a few
 * instructions a group). */
__attribute__((target("avx2"))) static int all_pass_avx2(const roz_filter_t *f,
                                                         const double *target, size_t n,
                                                         double *out)
{
    roz__v4l pass = { -1, -1, -1, -1 };
    size_t i = 0;

    for (; i + GROUP <= n; i += GROUP)
        pass &= pass4(f, target, i, out);
    return ((pass[0] & pass[1] & pass[2] & pass[3]) != 0) & pass_tail(f, target, i, n, out);
}

/* Which groups do not pass, when some do not. */
__attribute__((target("avx2"))) static void groups_check_avx2(const roz_filter_t *f,
                                                              const double *target, size_t n,
                                                              double *out, uint64_t *fails)
{
    size_t i = 0;

    memset(fails, 0, GROUP_WORDS * sizeof fails[0]);
    for (; i + GROUP <= n; i += GROUP) {
        roz__v4l pass = pass4(f, target, i, out);
        if (!(pass[0] & pass[1] & pass[2] & pass[3]))
            fails[i / GROUP / 64u] |= 1ull << (i / GROUP % 64u);
    }
    if (i < n && !pass_tail(f, target, i, n, out))
        fails[i / GROUP / 64u] |= 1ull << (i / GROUP % 64u);
}

/* Channels [b, e) as they are: out holds their targets already. */
static void keep(roz_filter_t *f, const double *target, size_t b, size_t e)
{
    if (e > b) {
        memcpy(&f->last[b], &target[b], (e - b) * sizeof f->last[0]);
        memset(&f->channel_stop_run[b], 0, (e - b) * sizeof f->channel_stop_run[0]);
    }
}

/* The ordinary tick with the vectors: the groups that pass, on channels
 * step 4 leaves alone, keep the targets the test copied to out; the others
 * go value by value. */
static void tick_avx2(roz_filter_t *f, const double *target, const double *state, size_t n,
                      size_t acting, double *out)
{
    uint64_t fails[GROUP_WORDS];

    if (all_pass_avx2(f, target, n, out) && acting == 0) {
        /* the whole tick passes: the outputs are the targets (copied from
         * the targets, not from out: a load just after a wider store to
         * the same place may have to wait for it) */
        memcpy(f->last, target, n * sizeof f->last[0]);
        if (f->running) {
            memset(f->channel_stop_run, 0, n * sizeof f->channel_stop_run[0]);
            f->running = 0;
        }
        return;
    }
    groups_check_avx2(f, target, n, out, fails);
    for (size_t k = 0; acting != 0 && k < f->n_paired; k++) {
        size_t g = f->paired[k] / GROUP;
        if (f->pair_acts[f->paired[k]])
            fails[g / 64u] |= 1ull << (g % 64u);
    }
    f->running = 1;
    size_t kept = 0; /* channels [0, kept) are done */
    for (size_t w = 0; w < GROUP_WORDS; w++) {
        for (uint64_t bits = fails[w]; bits != 0u; bits &= bits - 1u) {
            size_t b = (w * 64u + (size_t)__builtin_ctzll(bits)) * GROUP;
            size_t e = n - b > GROUP ? b + GROUP : n;
            keep(f, target, kept, b);
            for (size_t i = b; i < e; i++) {
                double v = tick_value(f, i, target[i], state);
                f->last[i] = v;
                out[i] = v;
            }
            kept = e;
        }
    }
    keep(f, target, kept, n);
}
#endif

/* What a hold channel keeps from a stop's first tick on (roz/hold.h): its
 * last applied value, the setpoint the joint was held at, with its
 * stiffness's last applied value (the torque to keep) and the measured
 * position, the follow rule's value (clamped to the channel); while the
 * position is unknown, the follow rule's value alone. Sets hold[i] for the
 * channel's own stiffness's hold gain; a stop's ticks recompute it for the
 * stiffness they send. The filter is primed: last[] holds values. */
static void hold_latch(roz_filter_t *f, uint16_t i, const double *state)
{
    const roz_channel_t *c = &f->manifest->commands[i];
    double measured = roz_filter_safe_default(f, i, state); /* not stopping yet: follow */
    double p = state != NULL ? state[c->position_state] : NAN;
    roz_hold_from_t *h = &f->hold_from[i];
    uint16_t k = f->hold_kp[i];

    h->setpoint = isfinite(p) ? f->last[i] : measured;
    h->measured = isfinite(p) ? measured : NAN;
    h->kp = k != UINT16_MAX ? f->last[k] : NAN;
    double kp_hold = k != UINT16_MAX ? roz_filter_safe_default(f, k, state) : NAN;
    f->hold[i] = roz_hold_setpoint(h, kp_hold, roz_hold_band(c));
}

/* A hold channel with a stiffness command, one tick of a stop: the
 * stiffness first (toward its hold gain, by its rate cap unless @p capped
 * is 0), the setpoint that keeps the torque under it, and, where the
 * setpoint's own rate cap left it short of that, the stiffness held back
 * so the torque stays what the controller's last command gave
 * (test_hold_filter_property). */
static void hold_joint(roz_filter_t *f, uint16_t i, const double *state, int capped, double *out)
{
    uint16_t k = f->hold_kp[i];
    const roz_channel_t *kc = &f->manifest->commands[k];
    double floor = kc->min;
    if (capped && kc->max_rate > 0.0 && f->last[k] - kc->max_rate > floor)
        floor = f->last[k] - kc->max_rate;
    double kp = channel_apply(f, k, roz_filter_safe_default(f, k, state), state, capped);
    f->hold[i] = roz_hold_setpoint(&f->hold_from[i], kp, roz_hold_band(&f->manifest->commands[i]));
    double q = channel_apply(f, i, f->hold[i], state, capped);
    kp = roz_hold_gain_cap(&f->hold_from[i], q, kp, floor);
    f->last[k] = out[k] = kp;
    f->last[i] = out[i] = q;
}

/* The length of a channel name's joint part, before its last '/'; the
 * whole name without one. */
static size_t joint_part(const char *name)
{
    const char *slash = strrchr(name, '/');
    return slash != NULL ? (size_t)(slash - name) : strlen(name);
}

/* Each hold channel's stiffness command: the one of its joint (the same
 * name before the '/'). Start-up only: a loop over the channels each. */
static void find_hold_gains(roz_filter_t *f, const roz_manifest_t *m)
{
    for (uint16_t i = 0; i < m->n_commands; i++) {
        f->hold_kp[i] = UINT16_MAX;
        f->hold_gain[i] = 0;
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (m->commands[i].safe_default != ROZ_SAFE_HOLD)
            continue;
        size_t len = joint_part(m->commands[i].name);
        for (uint16_t k = 0; k < m->n_commands; k++) {
            if (m->commands[k].type == ROZ_IF_STIFFNESS &&
                joint_part(m->commands[k].name) == len &&
                strncmp(m->commands[k].name, m->commands[i].name, len) == 0) {
                f->hold_kp[i] = k;
                f->hold_gain[k] = 1;
                break;
            }
        }
    }
}

/* The fallen stop, every tick of it: what a vendor's damping command sends
 * (Unitree's deploy code: kp 0, kd its damping gain, dq 0, tau 0), at once
 * (no rate cap: a falling robot has no time for a ramp), through every other
 * rule. Stiffness 0 (clamped to the channel: a manifest with a fall rule has
 * 0 within every stiffness's limits), position commands follow the
 * measured position, every other channel its safe default (the damping's
 * is the manifest's damping gain). */
static void fallen_stop(roz_filter_t *f, const double *state, double *out)
{
    const roz_manifest_t *m = f->manifest;

    f->stopping = 1;
    f->fallen = 1;
    f->running = 1;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        double v = c->type == ROZ_IF_STIFFNESS ? clampd(0.0, c->min, c->max)
                                               : roz_filter_safe_default(f, i, state);
        v = channel_apply(f, i, v, state, 0);
        f->last[i] = v;
        out[i] = v;
    }
}

/* ---- public -------------------------------------------------------------- */

int roz_filter_init(roz_filter_t *f, const roz_manifest_t *m)
{
    if (f == NULL || m == NULL || roz_manifest_validate(m, NULL) != ROZ_OK)
        return ROZ_EINVAL;
    memset(f, 0, sizeof *f);
    f->manifest = m;
    f->dt = 1.0 / (double)m->control_rate_hz;
    for (uint16_t s = 0; s < m->n_states; s++) {
        if (m->states[s].type == ROZ_IF_POSITION)
            f->margin[s] = roz_manifest_limit_margin(&m->states[s]);
    }
    /* a valid manifest pairs commands with position states only */
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (m->commands[i].type == ROZ_IF_VELOCITY &&
            m->commands[i].position_state != ROZ_CHANNEL_UNPAIRED)
            f->paired[f->n_paired++] = i;
    }
    f->n_velocity = f->n_paired;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (m->commands[i].type == ROZ_IF_EFFORT &&
            m->commands[i].position_state != ROZ_CHANNEL_UNPAIRED)
            f->paired[f->n_paired++] = i;
    }
    find_hold_gains(f, m);
    /* each one's position state, and its limits less the margin as step 4
     * computes them */
    for (uint16_t k = 0; k < f->n_paired; k++) {
        int32_t s = m->commands[f->paired[k]].position_state;
        f->pair_state[k] = (uint16_t)s;
        f->pair_lo[k] = m->states[s].min + f->margin[s];
        f->pair_hi[k] = m->states[s].max - f->margin[s];
    }
#if ROZ__FILTER_AVX2
    for (uint16_t i = 0; i < m->n_commands; i++) {
        f->pass_min[i] = m->commands[i].min;
        f->pass_max[i] = m->commands[i].max;
        f->pass_rate[i] = m->commands[i].max_rate > 0.0 ? m->commands[i].max_rate : INFINITY;
    }
    __builtin_cpu_init();
    f->avx2 = __builtin_cpu_supports("avx2") != 0;
#endif
    return ROZ_OK;
}

double roz_filter_safe_default(const roz_filter_t *f, uint16_t i, const double *state)
{
    const roz_channel_t *c = &f->manifest->commands[i];

    if (f->stopping && !f->fallen && c->safe_default == ROZ_SAFE_HOLD)
        return f->hold[i]; /* latched at the stop: test_filter_hold_latches */
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
    for (uint16_t i = 0; i < f->manifest->n_commands; i++) {
        const roz_channel_t *c = &f->manifest->commands[i];
        /* gains start where the ports' start-up hold has them, at zero (a
         * hold gain is for stops, not for the first tick) */
        f->last[i] = c->type == ROZ_IF_STIFFNESS || c->type == ROZ_IF_DAMPING
                         ? clampd(0.0, c->min, c->max)
                         : roz_filter_safe_default(f, i, state);
    }
    f->primed = 1;
}

void roz_filter_apply(roz_filter_t *f, const double *target, const double *state,
                      roz_stop_t stop, double *out)
{
    size_t n = f->manifest->n_commands;

    if (!f->primed)
        roz_filter_prime(f, state);
    f->counters.ticks++;
    if (stop == ROZ_STOP_NONE) {
        f->stopping = 0;
        f->fallen = 0;
    } else if (stop == ROZ_STOP_FALLEN) {
        fallen_stop(f, state, out);
        return;
    } else if (!f->stopping || f->fallen) {
        /* the stop's first tick: the hold channels keep the setpoint the
         * joint was held at, not the measured position, which sags under
         * gravity (test/ports/mujoco/test_mujoco_stops.c) */
        for (uint16_t i = 0; i < n; i++) {
            if (f->manifest->commands[i].safe_default == ROZ_SAFE_HOLD)
                hold_latch(f, i, state);
        }
        f->stopping = 1;
        f->fallen = 0;
    }
    if (stop != ROZ_STOP_NONE) {
        int capped = stop != ROZ_STOP_IMMEDIATE;
        f->running = 1;
        /* the joints held with a stiffness: both channels together */
        for (uint16_t i = 0; i < n; i++) {
            if (f->manifest->commands[i].safe_default == ROZ_SAFE_HOLD &&
                f->hold_kp[i] != UINT16_MAX)
                hold_joint(f, i, state, capped, out);
        }
        for (size_t i = 0; i < n; i++) {
            if (f->hold_gain[i] || (f->manifest->commands[i].safe_default == ROZ_SAFE_HOLD &&
                                    f->hold_kp[i] != UINT16_MAX))
                continue;
            double v = roz_filter_safe_default(f, (uint16_t)i, state);
            v = channel_apply(f, (uint16_t)i, v, state, capped);
            f->last[i] = v;
            out[i] = v;
        }
        return;
    }
    /* Most values on most ticks pass every rule untouched: a value within
     * [min, max] and within the rate cap of the last one (the intersection
     * of the two, the cap's bounds computed as step 3 computes them), on a
     * channel step 4 leaves alone, is the output as it is. (v >= lo fails
     * for NaN, as v >= min does.) Every other value goes through all the
     * rules. Where the CPU has AVX2, the values are tested four at a time
     * on vectors, and a group that passes whole is copied. */
    size_t acting = pairs_check(f, target, state);
#if ROZ__FILTER_AVX2
    if (f->avx2) {
        tick_avx2(f, target, state, n, acting, out);
        return;
    }
#else
    (void)acting;
#endif
    f->running = 1;
    for (size_t i = 0; i < n; i++) {
        double v = tick_value(f, i, target[i], state);
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
