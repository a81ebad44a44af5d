/* SPDX-License-Identifier: Apache-2.0 */
/* Random fault schedules through the loopback port: every fault kind the
 * loopback injects (drop, freeze, delay, NaN, out-of-range state, replay,
 * corrupt state and command frames, a robot that dies and boots again), up
 * to eight at once over random windows, on the UR5 (velocity commands) and
 * the G1 (MIT mode), the application clearing faults now and then. On every
 * tick:
 *  - what the runtime hands the port, and what the robot applies, is finite
 *    and inside the manifest;
 *  - the robot's command changes only when a good command frame arrives,
 *    and never faster than max_rate per tick, counted over the ticks since
 *    the good frame before (limit stops, the immediate stop of a LINK fault
 *    and a robot that rebooted excepted);
 *  - a fault latches whenever stale_ticks reads in a row brought no fresh
 *    frame (after the first one), and LINK latches on the tick the port
 *    reports a restart;
 *  - while any fault is latched the controller does not run.
 * Seeded and reproducible: the seed is printed; ROZ_FAULT_SEED=N reruns one. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support_stats.h"
#include "support_thin.h"
#include "support.h"
#include "support_runtime.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

/* RUNS seeds in a row; under an emulator fewer (support_thin.h) */
enum { TICKS = 4000, RUNS = 40 / ROZ_TEST_THIN(5), CLEAR_EVERY = 400 };

/* what the runs went through, summed */
static struct {
    uint64_t stale, link, crc, replays, restarts, cmd_crc, cmds_lost, limit_stops, clears;
} seen;

static roz_runtime_t rt;
static roz_loopback_t lb;

static uint64_t rng;

static uint64_t next(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

static uint64_t below(uint64_t n)
{
    return next() % n;
}

static void random_faults(const roz_manifest_t *m)
{
    uint32_t n = (uint32_t)below(ROZ_LOOPBACK_MAX_FAULTS + 1);
    for (uint32_t i = 0; i < n; i++) {
        roz_loopback_fault_t f = { 0 };
        f.kind = (roz_inject_kind_t)(ROZ_INJECT_DROP + below(ROZ_INJECT_RESTART));
        f.from = below(TICKS);
        f.to = below(4) == 0 ? 0 : f.from + 1 + below(below(2) ? 20 : 150);
        f.channel = -1;
        f.arg = 0;
        if (f.kind == ROZ_INJECT_NAN) {
            f.channel = (int32_t)below(m->n_states);
        } else if (f.kind == ROZ_INJECT_RANGE) {
            /* a position state (the loopback adds 0.5 past its upper limit) */
            do
                f.channel = (int32_t)below(m->n_states);
            while (m->states[f.channel].type != ROZ_IF_POSITION);
        } else if (f.kind == ROZ_INJECT_DELAY) {
            f.arg = 1 + (uint32_t)below(ROZ_LOOPBACK_MAX_DELAY);
        }
        assert_int_equal(roz_loopback_inject(&lb, &f), ROZ_OK);
    }
}

static void run(const roz_manifest_t *m, const char *controller, uint64_t seed, uint64_t salt)
{
    roz_runtime_config_t cfg;
    roz_test_clock_t clk = { 1000000, 1000 };
    double applied[ROZ_CFG_MAX_COMMANDS];
    uint32_t stops[ROZ_CFG_MAX_COMMANDS];
    int have_applied = 0, cleared = 0, jumped = 0, started = 0;
    uint64_t applied_at = 0, quiet = 0;

    rng = seed * 2 + salt;
    roz_test_loopback_config(&cfg, &lb, m, NULL, &clk);
    random_faults(m);
    roz_test_runtime_start(&rt, &cfg, controller);
    memset(stops, 0, sizeof stops);

    for (uint64_t t = 0; t < TICKS; t++) {
        roz_loopback_counters_t was = roz_loopback_counters(&lb);
        uint64_t delivered = was.frames_delivered, events = was.link_events;
        uint64_t good_cmds = roz_loopback_peer_link(&lb).accepted;
        uint64_t ran = RT_COUNT(&rt, controller_ticks);
        unsigned before = roz_runtime_faults(&rt);
        int rc = roz_runtime_tick(&rt);
        unsigned faults = roz_runtime_faults(&rt);

        if (rc != ROZ_OK && rc != ROZ_EFAULT)
            fail_msg("seed %llu tick %llu: tick returned %d", (unsigned long long)seed,
                     (unsigned long long)t, rc);
        roz_loopback_counters_t now = roz_loopback_counters(&lb);
        if (now.violations != 0)
            fail_msg("seed %llu tick %llu: a value outside the manifest reached the port",
                     (unsigned long long)seed, (unsigned long long)t);
        /* staleness and link faults */
        int fresh = now.frames_delivered != delivered && now.link_events == events;
        started |= fresh; /* staleness counts from the first frame */
        quiet = fresh || cleared || !started ? 0 : quiet + 1; /* a clear restarts the count */
        if (quiet >= cfg.stale_ticks && (faults & ROZ_FAULT_STALE) == 0)
            fail_msg("seed %llu tick %llu: %llu reads without a fresh frame, no STALE",
                     (unsigned long long)seed, (unsigned long long)t, (unsigned long long)quiet);
        if (now.link_events != events && (faults & ROZ_FAULT_LINK) == 0)
            fail_msg("seed %llu tick %llu: the port reported a restart, no LINK",
                     (unsigned long long)seed, (unsigned long long)t);
        /* (a clear takes effect at the start of the next tick) */
        if (before != 0 && !cleared && RT_COUNT(&rt, controller_ticks) != ran)
            fail_msg("seed %llu tick %llu: the controller ran with faults 0x%x latched",
                     (unsigned long long)seed, (unsigned long long)t, before);
        /* what the robot applies; an immediate stop (LINK) may jump */
        jumped |= (faults & ROZ_FAULT_IMMEDIATE_MASK) != 0;
        const double *cmd = roz_loopback_last_command(&lb);
        if (cmd == NULL) {
            have_applied = 0; /* not started, or rebooted: it forgot */
        } else {
            int changed = roz_loopback_peer_link(&lb).accepted != good_cmds;
            for (uint16_t i = 0; i < m->n_commands; i++) {
                const roz_channel_t *c = &m->commands[i];
                if (!isfinite(cmd[i]) || cmd[i] < c->min || cmd[i] > c->max)
                    fail_msg("seed %llu tick %llu: the robot applies %g on command %u, outside "
                             "[%g, %g]", (unsigned long long)seed, (unsigned long long)t, cmd[i],
                             i, c->min, c->max);
                if (have_applied && !changed && memcmp(&cmd[i], &applied[i], sizeof cmd[i]) != 0)
                    fail_msg("seed %llu tick %llu: the robot's command %u changed without a "
                             "good frame", (unsigned long long)seed, (unsigned long long)t, i);
                int limited = roz_test_channel(&rt, i).limit_stops != stops[i];
                double gap = (double)(t - applied_at);
                if (changed && have_applied && !limited && !jumped && c->max_rate > 0.0 &&
                    fabs(cmd[i] - applied[i]) > c->max_rate * gap + 1e-9)
                    fail_msg("seed %llu tick %llu: command %u went %g -> %g in %.0f ticks, "
                             "max_rate %g", (unsigned long long)seed, (unsigned long long)t, i,
                             applied[i], cmd[i], gap, c->max_rate);
            }
            if (changed || !have_applied) {
                memcpy(applied, cmd, m->n_commands * sizeof applied[0]);
                for (uint16_t k = 0; k < m->n_commands; k++)
                    stops[k] = roz_test_channel(&rt, k).limit_stops;
                have_applied = 1;
                applied_at = t;
                jumped = 0;
            }
        }
        cleared = 0;
        if (t % CLEAR_EVERY == CLEAR_EVERY - 1 && faults != 0) {
            assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
            cleared = 1;
            seen.clears++;
        }
    }
    seen.stale += RT_COUNT(&rt, faults[2]);
    seen.link += RT_COUNT(&rt, faults[5]);
    roz_link_t link = roz_loopback_link(&lb);
    seen.crc += link.crc_errors;
    seen.replays += link.replays;
    seen.restarts += link.restarts + link.returns;
    seen.cmd_crc += roz_loopback_peer_link(&lb).crc_errors;
    seen.cmds_lost += roz_loopback_counters(&lb).cmds_lost;
    seen.limit_stops += FILTER_COUNT(&rt, limit_stops);
    roz_runtime_deinit(&rt);
}

static uint64_t first_seed(void)
{
    const char *env = getenv("ROZ_FAULT_SEED");
    return env != NULL ? strtoull(env, NULL, 0) : 0x5EEDF00Dull;
}

static void test_fault_schedule(void **st)
{
    uint64_t seed = first_seed();
    int one = getenv("ROZ_FAULT_SEED") != NULL;
    (void)st;
    for (int r = 0; r < (one ? 1 : RUNS); r++, seed++) {
        print_message("seed %llu\n", (unsigned long long)seed);
        run(&roz_manifest_ur5, r % 2 ? "sine" : "constant_velocity", seed, 1);
        run(&roz_manifest_unitree_g1, "g1_pd", seed, 2);
    }
    print_message("STALE %llu, LINK %llu latched; %llu bad-CRC and %llu replayed state frames, "
                  "%llu peer restarts; %llu bad-CRC and %llu lost command frames; %llu limit "
                  "stops; %llu clears\n",
                  (unsigned long long)seen.stale, (unsigned long long)seen.link,
                  (unsigned long long)seen.crc, (unsigned long long)seen.replays,
                  (unsigned long long)seen.restarts, (unsigned long long)seen.cmd_crc,
                  (unsigned long long)seen.cmds_lost, (unsigned long long)seen.limit_stops,
                  (unsigned long long)seen.clears);
    if (!one) /* the schedules went through every kind of fault */
        assert_true(seen.stale && seen.link && seen.crc && seen.replays && seen.restarts &&
                    seen.cmd_crc && seen.cmds_lost && seen.limit_stops && seen.clears);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_fault_schedule))
