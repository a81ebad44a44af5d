/* SPDX-License-Identifier: Apache-2.0 */
/* The safety filter against a reference: its rules written out plainly here,
 * one channel at a time, straight from the manifest (no per-channel plan, no
 * shortcut for values that pass), run side by side with roz_filter_apply()
 * on long random sequences: targets in and out of range, at the limits and
 * the rate caps, NaN and infinities, zero and -0; position states inside,
 * at and past the margins, unknown; controlled stops and e-stops; a missing
 * state snapshot; re-initialisation. Every tick's outputs must be the same
 * bits and every counter (the totals and each channel's) the same number.
 * Manifests: the G1 and the UR5 (built in) and a small hand-made one with
 * every kind of channel (paired velocity and effort with and without rate
 * caps and with their own margins, a paired position, an unpaired velocity
 * whose limits exclude 0, gains). Where the filter can test a tick on AVX2
 * vectors, every run is made twice: with them (the tests count the ticks
 * that took that way) and with the CPU's AVX2 taken away, one value at a
 * time (white box: the only private field the test touches). */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/filter.h"
#include "support.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"
#include "support_thin.h"

/* ---- the reference ---------------------------------------------------------- */

typedef struct {
    const roz_manifest_t *m;
    double   dt;
    int      primed;
    int      stopping;                    /* a stop is on: hold[] latched */
    double   hold[ROZ_CFG_MAX_COMMANDS];  /* ROZ_SAFE_HOLD channels' setpoints */
    double   hold_sp[ROZ_CFG_MAX_COMMANDS], hold_kp[ROZ_CFG_MAX_COMMANDS],
             hold_p[ROZ_CFG_MAX_COMMANDS]; /* what the stop latched: setpoint, its
                                              stiffness, the measured position */
    int      gain[ROZ_CFG_MAX_COMMANDS];  /* a hold channel's stiffness command, -1: none */
    double   last[ROZ_CFG_MAX_COMMANDS];
    roz_filter_counters_t counters;
    roz_filter_channel_counters_t ch[ROZ_CFG_MAX_COMMANDS];
} ref_t;

static double ref_clamp(double v, double lo, double hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

/* the fastest speed from which braking by `rate` per tick stops within dist */
static double ref_brake_speed(double dist, double rate, double dt)
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

static double ref_margin(const roz_channel_t *s)
{
    double share = ROZ_MANIFEST_MARGIN_SHARE * (s->max - s->min);
    if (s->limit_margin > 0.0)
        return s->limit_margin;
    return share < ROZ_MANIFEST_MARGIN_MAX ? share : ROZ_MANIFEST_MARGIN_MAX;
}

static double ref_safe_default(const ref_t *r, uint16_t i, const double *state)
{
    const roz_channel_t *c = &r->m->commands[i];
    if (r->stopping && c->safe_default == ROZ_SAFE_HOLD)
        return r->hold[i];
    if (c->type == ROZ_IF_POSITION && c->position_state != ROZ_CHANNEL_UNPAIRED) {
        double held = state != NULL ? state[c->position_state] : NAN;
        if (isfinite(held))
            return ref_clamp(held, c->min, c->max);
        if (r->primed)
            return r->last[i];
    }
    return c->default_value;
}

static void ref_init(ref_t *r, const roz_manifest_t *m)
{
    memset(r, 0, sizeof *r);
    r->m = m;
    r->dt = 1.0 / (double)m->control_rate_hz;
    /* each hold channel's stiffness command: its joint's (same name up to
     * the '/') */
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        const char *slash = strrchr(c->name, '/');
        size_t len = slash != NULL ? (size_t)(slash - c->name) : strlen(c->name);
        r->gain[i] = -1;
        for (uint16_t k = 0; c->safe_default == ROZ_SAFE_HOLD && k < m->n_commands; k++) {
            const roz_channel_t *g = &m->commands[k];
            if (g->type == ROZ_IF_STIFFNESS && strncmp(g->name, c->name, len) == 0 &&
                g->name[len] == '/') {
                r->gain[i] = k;
                break;
            }
        }
    }
}

/* Every rule on one value v of command i (the filter's channel_apply()). */
static double ref_channel(ref_t *r, uint16_t i, double v, const double *state, roz_stop_t stop)
{
    const roz_manifest_t *m = r->m;
    const roz_channel_t *c = &m->commands[i];
    roz_filter_channel_counters_t *k = &r->ch[i];
    int held = 0;

    if (!isfinite(v)) { /* 1 */
        r->counters.nonfinite++;
        v = ref_safe_default(r, i, state);
    }
    if (v < c->min || v > c->max) { /* 2 */
        v = ref_clamp(v, c->min, c->max);
        r->counters.clamps++;
        k->clamps++;
    }
    if (c->max_rate > 0.0 && stop != ROZ_STOP_IMMEDIATE) { /* 3 */
        double lo = r->last[i] - c->max_rate, hi = r->last[i] + c->max_rate;
        if (v < lo || v > hi) {
            v = ref_clamp(v, lo, hi);
            r->counters.rate_caps++;
            k->rate_caps++;
        }
    }
    if (c->position_state != ROZ_CHANNEL_UNPAIRED && state != NULL &&
        (c->type == ROZ_IF_VELOCITY || c->type == ROZ_IF_EFFORT)) { /* 4 */
        const roz_channel_t *ps = &m->states[c->position_state];
        double p = state[c->position_state];
        double lo = ps->min + ref_margin(ps), hi = ps->max - ref_margin(ps);
        double limited = v;
        if (c->type == ROZ_IF_VELOCITY) {
            if (!isfinite(p))
                limited = 0.0 >= c->min && 0.0 <= c->max ? 0.0 : c->default_value;
            else if (v > 0.0)
                limited = p >= hi ? 0.0 : fmin(v, ref_brake_speed(hi - p, c->max_rate, r->dt));
            else if (v < 0.0)
                limited = p <= lo ? 0.0 : fmax(v, -ref_brake_speed(p - lo, c->max_rate, r->dt));
            held = limited != v;
        } else {
            held = !isfinite(p) ? v != 0.0 : (v > 0.0 && p >= hi) || (v < 0.0 && p <= lo);
            if (held)
                limited = 0.0;
        }
        if (held) {
            v = limited;
            r->counters.limit_stops++;
            k->limit_stops++;
        }
    }
    if (!held) {
        k->stop_run = 0;
    } else if (k->stop_run < UINT32_MAX) {
        k->stop_run++;
        if (k->stop_run > k->stop_longest)
            k->stop_longest = k->stop_run;
    }
    if (!(v >= c->min && v <= c->max)) /* 5 */
        v = isfinite(v) ? ref_clamp(v, c->min, c->max) : c->default_value;
    return v;
}

/* The hold's setpoint under stiffness kp_sent, restated: the latched
 * setpoint moved so kp_sent * (setpoint - p) = kp * (latched - p), then
 * within the band of p; p unknown: the latched value; no rate cap: p. */
static double ref_hold_setpoint(const ref_t *r, uint16_t i, double kp_sent)
{
    const roz_channel_t *c = &r->m->commands[i];
    double p = r->hold_p[i], sp = r->hold_sp[i];
    double band = c->max_rate > 0.0 ? 5.0 * c->max_rate : 0.0;
    if (!isfinite(p))
        return sp;
    if (isfinite(r->hold_kp[i]) && kp_sent > 0.0) {
        double v = p + r->hold_kp[i] / kp_sent * (sp - p);
        if (isfinite(v))
            sp = v;
    }
    return ref_clamp(sp, p - band, p + band);
}

static void ref_apply(ref_t *r, const double *target, const double *state, roz_stop_t stop,
                      double *out)
{
    const roz_manifest_t *m = r->m;

    if (!r->primed) {
        for (uint16_t i = 0; i < m->n_commands; i++) {
            const roz_channel_t *c = &m->commands[i];
            r->last[i] = c->type == ROZ_IF_STIFFNESS || c->type == ROZ_IF_DAMPING
                             ? ref_clamp(0.0, c->min, c->max) /* the start-up hold's gains */
                             : ref_safe_default(r, i, state);
        }
        r->primed = 1;
    }
    r->counters.ticks++;
    /* a stop's first tick latches each hold: the last setpoint, the last
     * stiffness of its joint (same name up to the '/') and the measured
     * position (the follow rule's value; unknown: that value alone) */
    if (stop == ROZ_STOP_NONE) {
        r->stopping = 0;
    } else if (!r->stopping) {
        for (uint16_t i = 0; i < m->n_commands; i++) {
            const roz_channel_t *c = &m->commands[i];
            if (c->safe_default != ROZ_SAFE_HOLD)
                continue;
            double measured = ref_safe_default(r, i, state);
            double p = state != NULL ? state[c->position_state] : NAN;
            r->hold_sp[i] = isfinite(p) ? r->last[i] : measured;
            r->hold_p[i] = isfinite(p) ? measured : NAN;
            r->hold_kp[i] = r->gain[i] >= 0 ? r->last[r->gain[i]] : NAN;
            r->hold[i] = ref_hold_setpoint(r, i, r->gain[i] >= 0
                                                     ? ref_clamp(m->commands[r->gain[i]].default_value,
                                                                 m->commands[r->gain[i]].min,
                                                                 m->commands[r->gain[i]].max)
                                                     : NAN);
        }
        r->stopping = 1;
    }
    int done[ROZ_CFG_MAX_COMMANDS] = { 0 };
    if (stop != ROZ_STOP_NONE) {
        /* a held joint with a stiffness: the stiffness toward its hold gain,
         * the setpoint keeping the torque under it, then the stiffness no
         * higher than keeps the torque at the setpoint sent (not below its
         * rate cap) */
        for (uint16_t i = 0; i < m->n_commands; i++) {
            int k = r->gain[i];
            if (m->commands[i].safe_default != ROZ_SAFE_HOLD || k < 0)
                continue;
            const roz_channel_t *kc = &m->commands[k];
            double floor = kc->min;
            if (stop != ROZ_STOP_IMMEDIATE && kc->max_rate > 0.0)
                floor = fmax(floor, r->last[k] - kc->max_rate);
            double kp = ref_channel(r, (uint16_t)k, ref_safe_default(r, (uint16_t)k, state), state,
                                    stop);
            r->hold[i] = ref_hold_setpoint(r, i, kp);
            double q = ref_channel(r, i, r->hold[i], state, stop);
            double torque = fabs(r->hold_kp[i] * (r->hold_sp[i] - r->hold_p[i]));
            double d = fabs(q - r->hold_p[i]);
            if (isfinite(torque) && isfinite(d) && kp * d > torque * (1.0 + 1e-9) + 1e-9)
                kp = fmin(kp, fmax(floor, torque / d));
            r->last[k] = out[k] = kp;
            r->last[i] = out[i] = q;
            done[i] = done[k] = 1;
        }
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (done[i])
            continue;
        double v = stop == ROZ_STOP_NONE ? target[i] : ref_safe_default(r, i, state);
        v = ref_channel(r, i, v, state, stop);
        r->last[i] = v;
        out[i] = v;
    }
}

/* ---- random inputs ------------------------------------------------------------ */

static uint64_t rng_state;

static uint64_t rng(void)
{
    return roz_test_rng(&rng_state);
}

static double uniform(double lo, double hi)
{
    return roz_test_uniform(&rng_state, lo, hi);
}

static int chance(unsigned percent)
{
    return rng() % 100u < percent;
}

/* A target for command c whose last applied value is `last`: mostly a
 * controller's ordinary output (in range, near the last value), often an
 * edge (a limit, the rate cap exactly, just past it, 0, -0), sometimes
 * garbage (out of range, NaN, infinities). */
static double pick_target(const roz_channel_t *c, double last)
{
    double span = c->max - c->min;
    switch (rng() % 16u) {
    case 0: return c->min;
    case 1: return c->max;
    case 2: return last + c->max_rate;
    case 3: return last - c->max_rate;
    case 4: return last + c->max_rate * uniform(1.0, 1.5);
    case 5: return 0.0;
    case 6: return -0.0;
    case 7: return uniform(c->min - span, c->max + span);
    case 8:
        switch (rng() % 4u) {
        case 0: return NAN;
        case 1: return INFINITY;
        case 2: return -INFINITY;
        default: return c->max + span * 1e6;
        }
    case 9: return last;
    default: {
        double step = c->max_rate > 0.0 ? c->max_rate : span * 0.01;
        double v = last + uniform(-step, step);
        return chance(50) ? ref_clamp(v, c->min, c->max) : v;
    }
    }
}

/* A value for state s, `prev` last tick: mostly a small move; often one
 * at or around a margin edge or a limit, sometimes far out or unknown. */
static double pick_state(const roz_channel_t *s, double prev)
{
    double span = s->max - s->min;
    double margin = s->type == ROZ_IF_POSITION ? ref_margin(s) : 0.0;
    switch (rng() % 20u) {
    case 0: return s->max - margin;
    case 1: return s->min + margin;
    case 2: return s->max - margin * uniform(0.0, 3.0);
    case 3: return s->min + margin * uniform(0.0, 3.0);
    case 4: return uniform(s->min - 0.2 * span, s->max + 0.2 * span);
    case 5: return chance(50) ? NAN : (chance(50) ? INFINITY : -INFINITY);
    case 6: return s->max;
    case 7: return s->min;
    default: {
        double v = isfinite(prev) ? prev : s->default_value;
        return v + uniform(-0.02, 0.02) * span;
    }
    }
}

/* ---- the comparison --------------------------------------------------------- */

static roz_filter_t f;
static ref_t ref;
static double target[ROZ_CFG_MAX_COMMANDS], state[ROZ_CFG_MAX_STATES];
static double out[ROZ_CFG_MAX_COMMANDS], ref_out[ROZ_CFG_MAX_COMMANDS];

static void same_counters(const roz_manifest_t *m, uint64_t seed, long tick)
{
    roz_filter_counters_t got;
    roz_filter_counters_get(&f, &got);
    if (memcmp(&got, &ref.counters, sizeof got) != 0)
        fail_msg("%s, seed %llu, tick %ld: totals differ (clamps %llu/%llu, rate caps %llu/%llu, "
                 "limit stops %llu/%llu, non-finite %llu/%llu)",
                 m->robot_id, (unsigned long long)seed, tick, (unsigned long long)got.clamps,
                 (unsigned long long)ref.counters.clamps, (unsigned long long)got.rate_caps,
                 (unsigned long long)ref.counters.rate_caps, (unsigned long long)got.limit_stops,
                 (unsigned long long)ref.counters.limit_stops, (unsigned long long)got.nonfinite,
                 (unsigned long long)ref.counters.nonfinite);
    for (uint16_t i = 0; i < m->n_commands; i++) {
        roz_filter_channel_counters_t c;
        assert_int_equal(roz_filter_channel_counters_get(&f, i, &c), ROZ_OK);
        if (memcmp(&c, &ref.ch[i], sizeof c) != 0)
            fail_msg("%s, seed %llu, tick %ld: %s: counters differ (clamps %u/%u, rate caps "
                     "%u/%u, limit stops %u/%u, stop run %u/%u, longest %u/%u)",
                     m->robot_id, (unsigned long long)seed, tick, m->commands[i].name, c.clamps,
                     ref.ch[i].clamps, c.rate_caps, ref.ch[i].rate_caps, c.limit_stops,
                     ref.ch[i].limit_stops, c.stop_run, ref.ch[i].stop_run, c.stop_longest,
                     ref.ch[i].stop_longest);
    }
}

/* 1: the filter may use AVX2 where it can; 0: it may not. */
static int vectors;
/* 1: quiet ticks are a controller holding still (each value where it was,
 * paired velocities 0) but for one value, half the time; with many
 * channels, the only way a whole tick passes often enough to test the
 * vector way at the edges */
static int calm;
/* ticks that took the vector way (the filter's flag left cleared) */
static uint64_t vector_ticks;

static void filter_init(const roz_manifest_t *m)
{
    assert_int_equal(roz_filter_init(&f, m), ROZ_OK);
#if ROZ__FILTER_AVX2
    if (!vectors)
        f.avx2 = 0;
#endif
}

/* `ticks` random ticks on m from `seed`; returns how many values the rules
 * changed (so a run that exercised nothing is caught). */
static uint64_t run(const roz_manifest_t *m, uint64_t seed, long ticks)
{
    uint64_t changed = 0;
    roz_stop_t stop = ROZ_STOP_NONE;

    rng_state = seed;
    filter_init(m);
    ref_init(&ref, m);
    for (uint16_t s = 0; s < m->n_states; s++)
        state[s] = m->states[s].default_value;
    for (long t = 0; t < ticks; t++) {
        /* a stop lasts a while, as a latched fault does */
        if (stop == ROZ_STOP_NONE ? chance(2) : chance(20))
            stop = stop != ROZ_STOP_NONE ? ROZ_STOP_NONE
                                         : (chance(50) ? ROZ_STOP_CONTROLLED : ROZ_STOP_IMMEDIATE);
        if (chance(1)) { /* start over, as a new runtime would */
            filter_init(m);
            ref_init(&ref, m);
        }
        /* some ticks keep every value where it was: the common case */
        int quiet = chance(30);
        for (uint16_t s = 0; s < m->n_states; s++) {
            if (!quiet || chance(2))
                state[s] = pick_state(&m->states[s], state[s]);
        }
        for (uint16_t i = 0; i < m->n_commands; i++) {
            const roz_channel_t *c = &m->commands[i];
            double last = ref.primed ? ref.last[i] : c->default_value;
            if (quiet && calm) /* a controller holding still: paired velocities 0 */
                target[i] = c->type == ROZ_IF_VELOCITY && c->position_state != ROZ_CHANNEL_UNPAIRED
                                ? 0.0
                                : ref_clamp(last, c->min, c->max);
            else
                target[i] = quiet && !chance(5) ? ref_clamp(last, c->min, c->max)
                                                : pick_target(c, last);
        }
        if (quiet && calm && chance(50)) { /* but one value anywhere: an edge, a step, garbage */
            uint16_t i = (uint16_t)(rng() % m->n_commands);
            target[i] = pick_target(&m->commands[i], ref.primed ? ref.last[i]
                                                                : m->commands[i].default_value);
        }
        const double *snap = m->n_states > 0 && !chance(2) ? state : NULL;
        roz_filter_apply(&f, target, snap, stop, out);
        vector_ticks += !f.running;
        ref_apply(&ref, target, snap, stop, ref_out);
        if (memcmp(out, ref_out, (size_t)m->n_commands * sizeof out[0]) != 0) {
            for (uint16_t i = 0; i < m->n_commands; i++) {
                if (memcmp(&out[i], &ref_out[i], sizeof out[i]) != 0)
                    fail_msg("%s, seed %llu, tick %ld, stop %d: %s: target %.17g -> %.17g, "
                             "reference %.17g", m->robot_id, (unsigned long long)seed, t,
                             (int)stop, m->commands[i].name, target[i], out[i], ref_out[i]);
            }
        }
        same_counters(m, seed, t);
        for (uint16_t i = 0; i < m->n_commands; i++)
            changed += memcmp(&out[i], &target[i], sizeof out[i]) != 0;
    }
    return changed;
}

/* A robot with one of each: a paired velocity with a rate cap and its own
 * margin, one without a cap on the default margin; a paired effort with and
 * without a cap; a paired position; an unpaired velocity whose limits exclude
 * 0 (its default is its safe value); a gain with a rate cap. */
static const roz_channel_t mixed_cmd[] = {
    { .name = "a/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -2.0, .max = 2.0,
      .default_value = 0.0, .max_rate = 0.3, .position_state = 0 },
    { .name = "b/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -1.0, .max = 3.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = 1 },
    { .name = "a/effort", .type = ROZ_IF_EFFORT, .unit = "N*m", .min = -40.0, .max = 40.0,
      .default_value = 0.0, .max_rate = 5.0, .position_state = 0 },
    { .name = "b/effort", .type = ROZ_IF_EFFORT, .unit = "N*m", .min = -10.0, .max = 25.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = 1 },
    { .name = "a/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.5, .max = 1.5,
      .default_value = 0.0, .max_rate = 0.05, .position_state = 0 },
    { .name = "c/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = 0.5, .max = 1.5,
      .default_value = 1.0, .max_rate = 0.1, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "a/stiffness", .type = ROZ_IF_STIFFNESS, .unit = "", .min = 0.0, .max = 200.0,
      .default_value = 0.0, .max_rate = 10.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_channel_t mixed_state[] = {
    { .name = "a/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED,
      .limit_margin = 0.1 },
    { .name = "b/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = 0.0, .max = 0.5,
      .default_value = 0.25, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "a/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -2.0, .max = 2.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_manifest_t mixed = { "mixed", "test", 250, mixed_cmd, 7, mixed_state, 3, NULL, NULL, 0, 0, NULL, NULL };

/* Sets the mode from the test's state; after the runs, checks that the
 * vector way was taken in that mode (where the CPU has it) and never in the
 * other. */
static void mode_begin(void **st)
{
    vectors = *(const int *)*st;
    vector_ticks = 0;
}

static void mode_end(uint64_t min_vector_ticks)
{
#if ROZ__FILTER_AVX2
    __builtin_cpu_init();
    if (vectors && __builtin_cpu_supports("avx2"))
        assert_true(vector_ticks >= min_vector_ticks);
    else
        assert_int_equal(vector_ticks, 0);
#else
    (void)min_vector_ticks;
    assert_int_equal(vector_ticks, 0);
#endif
}

/* ticks a run and what the runs must have seen: under an emulator a
 * THIN-th of each (support_thin.h) */
#define THIN ROZ_TEST_THIN(4)

/* run() for the seeds @p from to @p to, each times @p k: what they changed. */
static uint64_t runs(const roz_manifest_t *m, uint64_t from, uint64_t to, uint64_t k, long ticks)
{
    uint64_t changed = 0;
    for (uint64_t seed = from; seed <= to; seed++)
        changed += run(m, seed * k, ticks);
    return changed;
}

static void test_reference_mixed(void **st)
{
    mode_begin(st);
    uint64_t changed = runs(&mixed, 1, 20, 0x9e3779b97f4a7c15ull, 20000 / THIN);
    assert_true(changed > 10000 / THIN); /* the rules were at work, not idle */
    mode_end(1000 / THIN);
}

static void test_reference_ur5(void **st)
{
    mode_begin(st);
    uint64_t changed = runs(&roz_manifest_ur5, 1, 5, 0xd1b54a32d192ed03ull, 20000 / THIN);
    assert_true(changed > 10000 / THIN);
    mode_end(1000 / THIN);
}

static void test_reference_g1(void **st)
{
    mode_begin(st);
    uint64_t changed = runs(&roz_manifest_unitree_g1, 1, 3, 0x2545f4914f6cdd1dull, 5000 / THIN);
    calm = 1;
    changed += runs(&roz_manifest_unitree_g1, 4, 6, 0x2545f4914f6cdd1dull, 5000 / THIN);
    calm = 0;
    assert_true(changed > 10000 / THIN);
    mode_end(500 / THIN);
}

int main(void)
{
    static int on = 1, off = 0;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_prestate(test_reference_mixed, &on),
        cmocka_unit_test_prestate(test_reference_ur5, &on),
        cmocka_unit_test_prestate(test_reference_g1, &on),
        cmocka_unit_test_prestate(test_reference_mixed, &off),
        cmocka_unit_test_prestate(test_reference_ur5, &off),
        cmocka_unit_test_prestate(test_reference_g1, &off),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
