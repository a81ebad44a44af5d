/* SPDX-License-Identifier: Apache-2.0 */
/* Property test of the safety filter (roz/filter.h) and of command.set
 * (roz/abi.h): random manifests within the compile-time maxima, random
 * command streams (NaN, +-Inf, huge, out of range, bad indices) written
 * through roz_abi_command_set(), random states (out of range, NaN, +-Inf),
 * and random stop modes, for ROZ_PROPERTY_TICKS ticks in all (default
 * 1,000,000; fewer under sanitizers). After every tick, for every channel:
 *
 *  P1  the output is finite and within [min, max];
 *  P2  without a stop, it is the last output moved toward the clamped target
 *      by at most max_rate; a non-finite target counts as the safe default;
 *  P3  under a controlled stop, it is the last output moved toward the safe
 *      default by at most max_rate; under an e-stop it is the safe default;
 *  P4  a velocity command paired with a position state p never points
 *      further out: p >= max - margin => out <= 0, p <= min + margin =>
 *      out >= 0, p unknown (NaN/Inf) => out = 0; inside, p + out*dt stays
 *      inside [min + margin, max - margin], where margin is that state's
 *      limit margin (random per state: its own, or 0 for the default);
 *  P4e an effort command paired with a position state p never pushes
 *      further out: p >= max - margin => out <= 0, p <= min + margin =>
 *      out >= 0, p unknown (NaN/Inf) => out = 0;
 *  P5  P2 and P3 hold exactly, except where P4 or P4e forced a change (the filter
 *      counts it as a limit stop: the documented precedence of position
 *      limits over the rate cap);
 *  P6  command.set returns -1 for a bad index or a non-finite value (and the
 *      channel's target becomes non-finite, i.e. its safe default), 1 with
 *      the target at the nearer limit for a value outside [min, max], 0 with
 *      the value taken otherwise; channels not set keep their target;
 *  P7  a channel's run of limit stops grows by one on a tick with a limit
 *      stop and is 0 after one without; its longest run is the longest seen.
 *
 * The safe default is computed here from the manifest (filter.h): the
 * manifest default, except a position command paired with a position state,
 * which holds that state's value (clamped to the command's limits), or its
 * last output while that value is not finite.
 *
 * Seeded and reproducible: ROZ_PROPERTY_SEED (decimal or 0x hex) overrides
 * the fixed default seed; the seed is printed, and a failure names the seed,
 * the tick, the manifest and the channel. */
/* white-box: this test reads the private fields of the module it tests */
#define ROZ_PRIVATE_ACCESS
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/abi.h"
#include "roz/filter.h"
#include "roz/manifest.h"
#include "support.h"

#ifndef ROZ_PROPERTY_DEFAULT_TICKS
#define ROZ_PROPERTY_DEFAULT_TICKS 1000000
#endif
#define DEFAULT_SEED 0x526f7a2050726f70ull /* "Roz Prop" */

/* ---- a seeded generator (splitmix64) -------------------------------------- */

static uint64_t rng;

static uint64_t next64(void)
{
    uint64_t z = (rng += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static uint32_t below(uint32_t n) /* 0..n-1 */
{
    return (uint32_t)(next64() % n);
}

static double unit(void) /* [0, 1) */
{
    return (double)(next64() >> 11) * 0x1p-53;
}

static double uniform(double lo, double hi)
{
    double v = lo + (hi - lo) * unit();
    if (!isfinite(v)) /* hi - lo overflowed: pick in halves */
        v = unit() < 0.5 ? lo * unit() : hi * unit();
    return v < lo ? lo : (v > hi ? hi : v);
}

static int chance(double p)
{
    return unit() < p;
}

/* ---- random manifests ----------------------------------------------------- */

static roz_channel_t cmds[ROZ_CFG_MAX_COMMANDS];
static roz_channel_t states[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
static char cmd_names[ROZ_CFG_MAX_COMMANDS][12];
static char state_names[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1][12];
static roz_manifest_t man;

static const double scales[] = { 1e-9, 1e-3, 0.1, 1.0, 3.14, 10.0, 1e3, 1e6, 1e150, 1e300 };

static void random_limits(double *min, double *max)
{
    double s = scales[below(sizeof scales / sizeof scales[0])];
    switch (below(6)) {
    case 0: /* symmetric */
    case 1:
        *min = -s;
        *max = s;
        break;
    case 2: /* asymmetric around 0 */
        *min = -s * uniform(0.01, 1.0);
        *max = s * uniform(0.01, 1.0);
        break;
    case 3: /* 0 at an end */
        *min = chance(0.5) ? 0.0 : -s;
        *max = *min == 0.0 ? s : 0.0;
        break;
    case 4: /* anywhere, maybe excluding 0 */
        *min = uniform(-s, s);
        *max = *min + s * uniform(1e-6, 1.0);
        break;
    default: /* tiny range */
        *min = uniform(-s, s);
        *max = *min + fmax(fabs(*min) * 1e-9, 1e-12);
        break;
    }
    if (!(isfinite(*min) && isfinite(*max) && *min < *max)) {
        *min = -1.0;
        *max = 1.0;
    }
}

static double pick_in(double min, double max)
{
    switch (below(5)) {
    case 0: return min;
    case 1: return max;
    case 2: return min <= 0.0 && 0.0 <= max ? 0.0 : min;
    default: return uniform(min, max);
    }
}

static double random_rate(double min, double max)
{
    double range = max - min;
    if (!isfinite(range))
        range = DBL_MAX;
    switch (below(6)) {
    case 0:
    case 1: return 0.0;                               /* no cap */
    case 2: return range * uniform(0.001, 0.1);
    case 3: return range * uniform(0.1, 2.0);
    case 4: return fmin(range, 1.0) * 1e-12;           /* barely moves */
    default: return 1e300;                             /* a cap that never bites */
    }
}

static const uint32_t rates[] = { 1, 7, 50, 100, 500, 1000, 10000, 1000000 };

typedef struct {
    int    n_pos;                  /* position states */
    uint16_t pos_index[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
} shape_t;

static shape_t shape;

/* A position state's limit margin: 0 (the default) or its own, which must
 * leave room to move (2 * margin < max - min). */
static double random_margin(double min, double max)
{
    double range = max - min;
    switch (below(5)) {
    case 0:
    case 1: return 0.0;
    case 2: return range * uniform(1e-9, 0.49);
    case 3: return range * 0.4999;                     /* barely any room */
    default: return range > 0.1 ? 0.05 : 0.0;          /* roz's old global margin */
    }
}

/* roz_manifest_limit_margin(), restated: the state's own margin, or the
 * smaller of 0.05 and 5 % of its range. */
static double margin_of(const roz_channel_t *s)
{
    if (s->limit_margin > 0.0)
        return s->limit_margin;
    return fmin(0.05, 0.05 * (s->max - s->min));
}

static void random_manifest(void)
{
    uint32_t ncmd, nst;
    switch (below(20)) {
    case 0: ncmd = ROZ_CFG_MAX_COMMANDS - below(ROZ_CFG_MAX_COMMANDS > 8 ? 8 : 1); break;
    case 1: case 2: case 3: case 4: case 5: ncmd = 9 + below(56); break;
    default: ncmd = 1 + below(8); break;
    }
    if (ncmd > ROZ_CFG_MAX_COMMANDS)
        ncmd = ROZ_CFG_MAX_COMMANDS;
    nst = ROZ_CFG_MAX_STATES == 0 ? 0 : below(ncmd * 2 + 2);
    if (nst > ROZ_CFG_MAX_STATES)
        nst = ROZ_CFG_MAX_STATES;

    shape.n_pos = 0;
    for (uint32_t s = 0; s < nst; s++) {
        roz_channel_t *c = &states[s];
        snprintf(state_names[s], sizeof state_names[s], "s%u", (unsigned)s);
        c->name = state_names[s];
        c->unit = "";
        c->type = chance(0.6) ? ROZ_IF_POSITION : (roz_interface_t)below(ROZ_IF_COUNT_);
        random_limits(&c->min, &c->max);
        c->default_value = pick_in(c->min, c->max);
        c->max_rate = 0.0;
        c->position_state = ROZ_CHANNEL_UNPAIRED;
        c->limit_margin = 0.0;
        if (c->type == ROZ_IF_POSITION) {
            c->limit_margin = random_margin(c->min, c->max);
            shape.pos_index[shape.n_pos++] = (uint16_t)s;
        }
    }
    for (uint32_t i = 0; i < ncmd; i++) {
        roz_channel_t *c = &cmds[i];
        snprintf(cmd_names[i], sizeof cmd_names[i], "c%u", (unsigned)i);
        c->name = cmd_names[i];
        c->unit = "";
        c->type = chance(0.5) ? ROZ_IF_VELOCITY
                  : chance(0.4) ? ROZ_IF_POSITION : (roz_interface_t)below(ROZ_IF_COUNT_);
        random_limits(&c->min, &c->max);
        c->default_value = pick_in(c->min, c->max);
        c->max_rate = random_rate(c->min, c->max);
        c->position_state = ROZ_CHANNEL_UNPAIRED;
        c->limit_margin = 0.0;
        if (shape.n_pos > 0 && chance(c->type == ROZ_IF_VELOCITY ? 0.8 : 0.4))
            c->position_state = shape.pos_index[below((uint32_t)shape.n_pos)];
        if ((c->type == ROZ_IF_VELOCITY || c->type == ROZ_IF_EFFORT) &&
            c->position_state != ROZ_CHANNEL_UNPAIRED && !(c->min <= 0.0 && 0.0 <= c->max)) {
            /* A paired velocity or effort that cannot be zero could not be
             * stopped at a position limit: manifests refuse it (rule
             * pairing-zero). */
            c->position_state = ROZ_CHANNEL_UNPAIRED;
        }
    }
    man = (roz_manifest_t){ "prop", "generic", rates[below(sizeof rates / sizeof rates[0])],
                            cmds, (uint16_t)ncmd, nst > 0 ? states : NULL, (uint16_t)nst, NULL, NULL, 0, 0, NULL, NULL };
}

/* ---- random inputs --------------------------------------------------------- */

static double wild(double min, double max)
{
    switch (below(16)) {
    case 0: return NAN;
    case 1: return INFINITY;
    case 2: return -INFINITY;
    case 3: return DBL_MAX;
    case 4: return -DBL_MAX;
    case 5: return chance(0.5) ? 1e308 : -1e308;
    case 6: return chance(0.5) ? DBL_TRUE_MIN : -DBL_TRUE_MIN;
    case 7: return max + fabs(max - min) * uniform(0.0, 10.0) + 1e-9;
    case 8: return min - fabs(max - min) * uniform(0.0, 10.0) - 1e-9;
    case 9: return min;
    case 10: return max;
    case 11: return -0.0;
    default: return uniform(min, max);
    }
}

/* A position state: mostly inside, often near the margins, sometimes out
 * or unknown. */
static double random_position(const roz_channel_t *s, double margin)
{
    double lo = s->min + margin, hi = s->max - margin;
    switch (below(12)) {
    case 0: return NAN;
    case 1: return chance(0.5) ? INFINITY : -INFINITY;
    case 2: return hi + fabs(s->max - s->min) * uniform(0.0, 0.5);
    case 3: return lo - fabs(s->max - s->min) * uniform(0.0, 0.5);
    case 4: return hi;
    case 5: return lo;
    case 6: return hi - fabs(hi) * 1e-12 - uniform(0.0, fabs(s->max - s->min) * 1e-3);
    case 7: return lo + fabs(lo) * 1e-12 + uniform(0.0, fabs(s->max - s->min) * 1e-3);
    default: return uniform(s->min, s->max);
    }
}

/* ---- the check ------------------------------------------------------------ */

static roz_filter_t filt;
static roz_abi_t abi;
static double target[ROZ_CFG_MAX_COMMANDS];
static double expect_target[ROZ_CFG_MAX_COMMANDS];
static double state[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
static double prev[ROZ_CFG_MAX_COMMANDS];
static double out[ROZ_CFG_MAX_COMMANDS];
static uint32_t stops_before[ROZ_CFG_MAX_COMMANDS];
static uint32_t run_before[ROZ_CFG_MAX_COMMANDS];

static uint64_t seed, tick_no;
static uint32_t run_no;

static const char *stop_name(roz_stop_t s)
{
    return s == ROZ_STOP_NONE ? "none" : (s == ROZ_STOP_CONTROLLED ? "controlled" : "e-stop");
}

static char detail[512];

#define VIOLATION(what, i, ...)                                                                \
    do {                                                                                       \
        snprintf(detail, sizeof detail, __VA_ARGS__);                                          \
        fail_msg("property %s violated: seed 0x%016" PRIx64 " (ROZ_PROPERTY_SEED=%" PRIu64      \
                 "), tick %" PRIu64 ", manifest %u, command %u: %s",                           \
                 what, seed, seed, tick_no, run_no, (unsigned)(i), detail);                    \
    } while (0)

static double clampd(double v, double lo, double hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

static double safe_default(uint16_t i)
{
    const roz_channel_t *c = &cmds[i];
    if (c->type == ROZ_IF_POSITION && c->position_state != ROZ_CHANNEL_UNPAIRED) {
        double p = state[c->position_state];
        return isfinite(p) ? clampd(p, c->min, c->max) : prev[i];
    }
    return c->default_value;
}

/* `to` approached from `from` by at most `rate` (0 = no cap). */
static double step_toward(double from, double to, double rate)
{
    if (rate <= 0.0)
        return to;
    return clampd(to, from - rate, from + rate);
}

static int close_enough(double a, double b)
{
    return a == b || fabs(a - b) <= 1e-12 * fmax(fabs(a), fabs(b));
}

static void check_channel(uint16_t i, roz_stop_t stop)
{
    const roz_channel_t *c = &cmds[i];
    double o = out[i];
    int limited = filt.channel_limit_stops[i] != stops_before[i];

    /* P1 */
    if (!isfinite(o) || o < c->min || o > c->max)
        VIOLATION("P1 (range)", i, "out %.17g outside [%.17g, %.17g]", o, c->min, c->max);

    /* a paired channel's position, and its range less the margin */
    int paired_velocity = c->type == ROZ_IF_VELOCITY && c->position_state != ROZ_CHANNEL_UNPAIRED;
    int paired_effort = c->type == ROZ_IF_EFFORT && c->position_state != ROZ_CHANNEL_UNPAIRED;
    double p = 0.0, lo = 0.0, hi = 0.0;
    if (paired_velocity || paired_effort) {
        const roz_channel_t *ps = &states[c->position_state];
        double margin = margin_of(ps);
        p = state[c->position_state];
        lo = ps->min + margin;
        hi = ps->max - margin;
    }

    /* P4 */
    if (paired_velocity) {
        double dt = 1.0 / (double)man.control_rate_hz;
        if (!isfinite(p)) {
            if (c->min <= 0.0 && 0.0 <= c->max && o != 0.0)
                VIOLATION("P4 (unknown position)", i, "state %d = %g, out %.17g, limits [%g, %g]",
                          c->position_state, p, o, c->min, c->max);
        } else if ((p >= hi && o > 0.0) || (p <= lo && o < 0.0)) {
            VIOLATION("P4 (further out)", i,
                      "position %.17g, range less margin [%.17g, %.17g], out %.17g, command "
                      "limits [%.17g, %.17g], stop %s",
                      p, lo, hi, o, c->min, c->max, stop_name(stop));
        } else if (p > lo && p < hi) {
            double next = p + o * dt;
            double tol = 1e-12 * (fabs(p) + fabs(hi) + fabs(lo) + fabs(o * dt)) + 1e-300;
            if (next > hi + tol || next < lo - tol)
                VIOLATION("P4 (lookahead)", i,
                          "position %.17g + out %.17g * dt %.17g = %.17g leaves [%.17g, %.17g]",
                          p, o, dt, next, lo, hi);
        }
    }

    /* P4e */
    if (paired_effort) {
        if (!isfinite(p) ? o != 0.0 : (p >= hi && o > 0.0) || (p <= lo && o < 0.0))
            VIOLATION("P4e (effort further out)", i,
                      "position %.17g, range less margin [%.17g, %.17g], out %.17g, stop %s",
                      p, lo, hi, o, stop_name(stop));
    }

    /* P7 */
    uint32_t run = filt.channel_stop_run[i];
    if (run != (limited ? run_before[i] + 1u : 0u) || filt.channel_stop_longest[i] < run)
        VIOLATION("P7 (stop runs)", i, "run %u after %u, limit stop %d, longest %u",
                  (unsigned)run, (unsigned)run_before[i], limited,
                  (unsigned)filt.channel_stop_longest[i]);

    /* P2, P3, P5 */
    double rate = c->max_rate;
    double expect;
    if (stop == ROZ_STOP_IMMEDIATE) {
        expect = safe_default(i);
    } else {
        double t = stop == ROZ_STOP_CONTROLLED ? safe_default(i) : target[i];
        if (!isfinite(t))
            t = safe_default(i);
        expect = step_toward(prev[i], clampd(t, c->min, c->max), rate);
    }
    if (!close_enough(o, expect)) {
        if (!((paired_velocity || paired_effort) && limited))
            VIOLATION(stop == ROZ_STOP_NONE ? "P2 (target, clamp, rate cap)" : "P3 (stop)", i,
                      "out %.17g, expected %.17g (last %.17g, target %.17g, max_rate %.17g, "
                      "stop %s, limit stop %d)",
                      o, expect, prev[i], target[i], rate, stop_name(stop), limited);
        /* the position limit won: it may only have pulled toward zero from
         * what the rate cap allowed (or held at a limit when zero is outside) */
        if (fabs(o) > fabs(expect) && !(o == c->min || o == c->max))
            VIOLATION("P5 (limit override)", i, "out %.17g moved away from zero, expected %.17g",
                      o, expect);
    }
}

/* ---- command.set ---------------------------------------------------------- */

static int32_t random_index(uint16_t n)
{
    switch (below(10)) {
    case 0: return -1;
    case 1: return (int32_t)n;
    case 2: return (int32_t)(next64() & 0xffffffffu); /* any i32 */
    case 3: return chance(0.5) ? INT32_MIN : INT32_MAX;
    default: return (int32_t)below(n);
    }
}

static void set_commands(void)
{
    uint32_t calls = below(3) == 0 ? 0 : below(2u * man.n_commands + 2u);
    for (uint32_t k = 0; k < calls; k++) {
        int32_t idx = random_index(man.n_commands);
        int valid = idx >= 0 && idx < (int32_t)man.n_commands;
        double v = valid ? wild(cmds[idx].min, cmds[idx].max) : wild(-1.0, 1.0);
        uint64_t bad_before = abi.counters.set_bad_index;
        int32_t rc = roz_abi_command_set(&abi, idx, v);
        if (!valid) {
            if (rc != ROZ_ABI_SET_REFUSED || abi.counters.set_bad_index != bad_before + 1)
                VIOLATION("P6 (bad index)", 0, "set(%d, %g) returned %d", idx, v, rc);
            continue;
        }
        const roz_channel_t *c = &cmds[idx];
        if (!isfinite(v)) {
            if (rc != ROZ_ABI_SET_REFUSED || isfinite(target[idx]))
                VIOLATION("P6 (non-finite)", idx, "set(%g) returned %d, target %g", v, rc,
                          target[idx]);
            expect_target[idx] = NAN;
        } else if (v < c->min || v > c->max) {
            double lim = v < c->min ? c->min : c->max;
            if (rc != ROZ_ABI_SET_CLAMPED || target[idx] != lim)
                VIOLATION("P6 (clamp)", idx, "set(%.17g) returned %d, target %.17g, limit %.17g",
                          v, rc, target[idx], lim);
            expect_target[idx] = lim;
        } else {
            if (rc != ROZ_ABI_SET_TAKEN || target[idx] != v)
                VIOLATION("P6 (taken)", idx, "set(%.17g) returned %d, target %.17g", v, rc,
                          target[idx]);
            expect_target[idx] = v;
        }
    }
    /* now and then a target written past command.set, as a broken engine
     * might: the filter's own non-finite and clamp steps are the backstop */
    if (below(10) == 0) {
        uint16_t i = (uint16_t)below(man.n_commands);
        target[i] = wild(cmds[i].min, cmds[i].max);
        expect_target[i] = target[i];
    }
    for (uint16_t i = 0; i < man.n_commands; i++) {
        int same = isnan(expect_target[i]) ? isnan(target[i]) : target[i] == expect_target[i];
        if (!same)
            VIOLATION("P6 (kept)", i, "target %.17g, expected %.17g", target[i], expect_target[i]);
    }
}

/* ---- the run --------------------------------------------------------------- */

static void random_states(int fresh)
{
    for (uint16_t s = 0; s < man.n_states; s++) {
        const roz_channel_t *c = &states[s];
        if (!fresh && chance(0.7))
            continue; /* held */
        state[s] = c->type == ROZ_IF_POSITION ? random_position(c, margin_of(c))
                                              : wild(c->min, c->max);
    }
}

static void run_manifest(uint32_t n_ticks)
{
    roz_manifest_problem_t why;
    roz_stop_t stop = ROZ_STOP_NONE;
    uint32_t stop_left = 0;

    random_manifest();
    if (roz_manifest_validate(&man, &why) != ROZ_OK)
        fail_msg("seed 0x%016" PRIx64 ", manifest %u: generator made an invalid manifest (rule "
                 "%d, %s %d)", seed, run_no, (int)why.rule, why.is_state ? "state" : "command",
                 why.index);
    for (uint16_t s = 0; s < man.n_states; s++) {
        double mg = roz_manifest_limit_margin(&states[s]);
        if (states[s].type == ROZ_IF_POSITION &&
            (mg != margin_of(&states[s]) || !(mg >= 0.0 && 2.0 * mg < states[s].max - states[s].min)))
            fail_msg("seed 0x%016" PRIx64 ", manifest %u, state %u: margin %.17g, expected "
                     "%.17g, limits [%.17g, %.17g]", seed, run_no, (unsigned)s, mg,
                     margin_of(&states[s]), states[s].min, states[s].max);
    }
    assert_int_equal(roz_filter_init(&filt, &man), ROZ_OK);
    roz_abi_init(&abi, &man, target, NULL);
    for (uint16_t i = 0; i < man.n_commands; i++)
        expect_target[i] = cmds[i].default_value;
    random_states(1);
    roz_filter_prime(&filt, state);
    memcpy(prev, filt.last, man.n_commands * sizeof prev[0]);
    memset(stops_before, 0, sizeof stops_before);
    memset(run_before, 0, sizeof run_before);

    for (uint32_t t = 0; t < n_ticks; t++, tick_no++) {
        random_states(0);
        roz_abi_begin_tick(&abi, 0, state);
        set_commands();
        if (stop_left == 0) {
            uint32_t r = below(100);
            stop = r < 90 ? ROZ_STOP_NONE : (r < 96 ? ROZ_STOP_CONTROLLED : ROZ_STOP_IMMEDIATE);
            stop_left = 1 + below(stop == ROZ_STOP_NONE ? 200 : 30);
        }
        stop_left--;
        roz_filter_apply(&filt, target, state, stop, out);
        for (uint16_t i = 0; i < man.n_commands; i++) {
            check_channel(i, stop);
            stops_before[i] = filt.channel_limit_stops[i];
            run_before[i] = filt.channel_stop_run[i];
        }
        memcpy(prev, out, man.n_commands * sizeof prev[0]);
        if (filt.counters.ticks != t + 1)
            fail_msg("seed 0x%016" PRIx64 ": filter tick counter %" PRIu64 ", expected %u", seed,
                     filt.counters.ticks, t + 1);
    }
}

static uint64_t env_u64(const char *name, uint64_t dflt)
{
    const char *s = getenv(name);
    char *end;
    if (s == NULL || *s == '\0')
        return dflt;
    uint64_t v = strtoull(s, &end, 0);
    if (*end != '\0')
        fail_msg("%s=\"%s\": not a number", name, s);
    return v;
}

static void test_property_filter_and_set(void **st)
{
    (void)st;
    seed = env_u64("ROZ_PROPERTY_SEED", DEFAULT_SEED);
    uint64_t total = env_u64("ROZ_PROPERTY_TICKS", ROZ_PROPERTY_DEFAULT_TICKS);
    print_message("property test: seed 0x%016" PRIx64 " (ROZ_PROPERTY_SEED=%" PRIu64
                  "), %" PRIu64 " ticks\n", seed, seed, total);
    rng = seed;
    tick_no = 0;
    run_no = 0;
    uint64_t channel_ticks = 0;
    roz_filter_counters_t sum = { 0 };
    while (tick_no < total) {
        uint64_t left = total - tick_no;
        uint32_t n = 200 + below(4800);
        if (n > left)
            n = (uint32_t)left;
        run_manifest(n);
        channel_ticks += (uint64_t)n * man.n_commands;
        sum.clamps += filt.counters.clamps;
        sum.nonfinite += filt.counters.nonfinite;
        sum.rate_caps += filt.counters.rate_caps;
        sum.limit_stops += filt.counters.limit_stops;
        run_no++;
    }
    print_message("%u manifests, %" PRIu64 " channel-ticks; filter: %" PRIu64 " clamps, %" PRIu64
                  " non-finite, %" PRIu64 " rate caps, %" PRIu64 " limit stops\n",
                  run_no, channel_ticks, sum.clamps, sum.nonfinite, sum.rate_caps,
                  sum.limit_stops);
    /* the generator reached every branch */
    assert_true(sum.clamps > 0 && sum.nonfinite > 0 && sum.rate_caps > 0 && sum.limit_stops > 0);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_property_filter_and_set))
