/* SPDX-License-Identifier: Apache-2.0 */
/* Faults, e-stop and clear from four threads at once, for ThreadSanitizer
 * (SAFETY.md §4): the tick; an ISR-like thread pressing and releasing the
 * e-stop; a supervisor clearing faults and reading the fault message; a
 * loader swapping controllers. The controller traps on purpose at random
 * ticks. Asserted: a trapped instance never runs again (its next call would
 * count on from its old count), every e-stop press is seen latched by the
 * tick after it, a published fault always has its message, and TSan sees no
 * race. ROZ_LATCH_STRESS_TICKS=N runs N ticks (default 50000, a few
 * seconds under TSan on two cores); nothing here asserts a time. */
#define _POSIX_C_SOURCE 200809L
/* white-box in part: reads the runtime's controller slots (a trapped
 * instance must never run again), which no public function exposes */
#define ROZ_PRIVATE_ACCESS
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "roz/hal/clock.h"
#include "roz/runtime.h"
#include "support_stats.h"
#include "support.h"
#include "support_runtime.h"
#include "support_wat.h"

static const roz_channel_t commands[] = {
    { .name = "j0/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -3.0, .max = 3.0,
      .default_value = 1.0, .max_rate = 0.1, .position_state = 0 },
};
static const roz_channel_t states[] = {
    { .name = "j0/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -3.0, .max = 3.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "trigger/effort", .type = ROZ_IF_EFFORT, .unit = "", .min = -1e12, .max = 1e12,
      .default_value = -1.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_manifest_t manifest = {
    "latch_stress", "manipulator", 1000, commands, 1, states, 2, NULL, NULL, 0, 0, NULL, NULL
};

/* Emits its own call count, traps when its tick equals state[1]. */
static const char *const controller_wat =
    "(module\n"
    "  (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))\n"
    "  (import \"state\" \"get\" (func $get (param i32) (result f64)))\n"
    "  (import \"telemetry\" \"emit_metric\" (func $emit (param f64)))\n"
    "  (global $n (mut i32) (i32.const 0))\n"
    "  (func (export \"process\") (param $tick i64)\n"
    "    (global.set $n (i32.add (global.get $n) (i32.const 1)))\n"
    "    (call $emit (f64.convert_i32_u (global.get $n)))\n"
    "    (drop (call $set (i32.const 0) (f64.const 0.5)))\n"
    "    (if (f64.eq (f64.convert_i64_s (local.get $tick)) (call $get (i32.const 1)))\n"
    "      (then unreachable))))\n";

static uint8_t wasm[2048];
static size_t wasm_len;
static roz_runtime_t rt;
static atomic_int stop;
static atomic_ullong ticks_done;      /* ticks completed */
static atomic_ullong last_estop_tick; /* last tick that ended with ESTOP latched */
static uint64_t rng_tick = 88172645463325252ull;

static uint64_t xorshift(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

/* ---- the port (called by the tick) --------------------------------------- */

static int sp_read(void *self, double *state, size_t n)
{
    (void)self;
    (void)n;
    state[0] = 0.2;
    /* a trap at this tick, now and then (never in verification: tick >= 100) */
    state[1] = rt.ctrl_tick >= 100 && xorshift(&rng_tick) % 97u == 0 ? (double)rt.ctrl_tick : -1.0;
    return 1;
}

static int sp_write(void *self, const double *cmd, size_t n)
{
    (void)self;
    (void)cmd;
    (void)n;
    return ROZ_OK;
}

static const roz_port_ops_t stress_ops = { .name = "stress", .read = sp_read, .write = sp_write };

/* ---- threads --------------------------------------------------------------- */

static void pause_us(long us)
{
    struct timespec ts = { 0, us * 1000L };
    nanosleep(&ts, NULL);
}

static uint64_t reused, traps, estop_checks, estop_lost, msg_checks, msg_missing;
static uint64_t clears, clears_refused, loads, stats_checks, stats_bad;

static void *tick_main(void *arg)
{
    uint64_t n = *(const uint64_t *)arg;
    int expect_fresh = 0;
    for (uint64_t i = 0; i < n; i++) {
        uint64_t trapped = RT_COUNT(&rt, faults[0]);
        roz_test_tick(&rt);
        roz_metric_t m;
        while (roz_runtime_metric_pop(&rt, &m)) {
            if (expect_fresh && m.value != 1.0)
                reused++;
            expect_fresh = 0;
        }
        if (RT_COUNT(&rt, faults[0]) != trapped &&
            strstr(rt.slot[atomic_load(&rt.active)].ctrl.error, "unreachable") != NULL) {
            expect_fresh = 1;
            traps++;
        }
        if (roz_runtime_faults(&rt) & ROZ_FAULT_ESTOP)
            atomic_store(&last_estop_tick, i + 1u);
        atomic_store(&ticks_done, i + 1u);
        if (i % 8u == 0)
            pause_us(1);
    }
    atomic_store(&stop, 1);
    return NULL;
}

static void wait_ticks(uint64_t until)
{
    while (atomic_load(&ticks_done) < until && !atomic_load(&stop))
        pause_us(20);
}

/* Presses (level or edge) and releases; after each press, a tick that ended
 * after the press began must have ended with ESTOP latched. */
static void *isr_main(void *arg)
{
    uint64_t s = 0x9e3779b97f4a7c15ull;
    (void)arg;
    while (!atomic_load(&stop)) {
        pause_us((long)(xorshift(&s) % 3000u));
        /* p: ticks done before the press; q: after it. The press is taken
         * by a tick that ends at p + 1 at the earliest (one already running
         * when p was read) and q + 2 at the latest (the one running when q
         * was read, or the next). Waiting from p alone would let a thread
         * preempted between reading p and pressing check too early. */
        uint64_t p = atomic_load(&ticks_done);
        int level = (int)(xorshift(&s) & 1u);
        if (level)
            roz_runtime_estop_set(&rt, 1);
        else
            roz_runtime_estop(&rt);
        uint64_t q = atomic_load(&ticks_done);
        wait_ticks(q + 2u);
        if (atomic_load(&stop))
            break;
        estop_checks++;
        if (atomic_load(&last_estop_tick) < p + 1u)
            estop_lost++;
        if (level) {
            pause_us((long)(xorshift(&s) % 500u));
            roz_runtime_estop_set(&rt, 0);
        }
    }
    roz_runtime_estop_set(&rt, 0);
    return NULL;
}

/* Clears and reads the message: a fault published is never without it. */
static void *supervisor_main(void *arg)
{
    char msg[ROZ_CFG_ERROR_LEN + 64];
    uint64_t s = 0x2545f4914f6cdd1dull;
    (void)arg;
    while (!atomic_load(&stop)) {
        unsigned w1 = atomic_load(&rt.faults);
        int rc = roz_runtime_fault_message_copy(&rt, msg, sizeof msg);
        unsigned w2 = atomic_load(&rt.faults);
        if (rc == ROZ_OK && w1 == w2 && (w1 & 0xffu) != 0u) {
            msg_checks++;
            if (msg[0] == '\0')
                msg_missing++;
        }
        /* the figures, taken while the tick publishes them: each snapshot
         * consistent (one tick's) and never going backwards */
        roz_runtime_stats_t a, b;
        roz_monitor_stat_t ms;
        if (roz_runtime_stats(&rt, &a) == ROZ_OK && roz_runtime_stats(&rt, &b) == ROZ_OK &&
            roz_monitor_snapshot(roz_runtime_monitor(&rt), ROZ_MON_TICK, &ms) == ROZ_OK) {
            stats_checks++;
            uint64_t hist = 0;
            for (unsigned k = 0; k < ROZ_MONITOR_BUCKETS; k++)
                hist += ms.hist[k];
            if (b.runtime.ticks < a.runtime.ticks ||
                a.runtime.controller_ticks > a.runtime.ticks ||
                a.runtime.writes + a.runtime.write_errors + a.runtime.waiting_ticks !=
                    a.runtime.ticks ||
                a.filter.ticks != a.runtime.writes + a.runtime.write_errors || hist != ms.count) {
                stats_bad++;
                fprintf(stderr,
                        "inconsistent figures: ticks %llu then %llu, controller %llu, writes %llu, "
                        "write errors %llu, waiting %llu, filter ticks %llu, tick samples %llu, "
                        "histogram %llu\n",
                        (unsigned long long)a.runtime.ticks, (unsigned long long)b.runtime.ticks,
                        (unsigned long long)a.runtime.controller_ticks,
                        (unsigned long long)a.runtime.writes,
                        (unsigned long long)a.runtime.write_errors,
                        (unsigned long long)a.runtime.waiting_ticks,
                        (unsigned long long)a.filter.ticks, (unsigned long long)ms.count,
                        (unsigned long long)hist);
            }
        }
        if (xorshift(&s) % 4u == 0) {
            if (roz_runtime_clear_faults(&rt) != ROZ_OK)
                clears_refused++;
            clears++;
        }
        pause_us((long)(xorshift(&s) % 400u));
    }
    return NULL;
}

static void *loader_main(void *arg)
{
    uint64_t s = 0xda942042e4dd58b5ull;
    (void)arg;
    while (!atomic_load(&stop)) {
        pause_us(2000 + (long)(xorshift(&s) % 8000u));
        if (roz_runtime_load(&rt, wasm, wasm_len, NULL) == ROZ_OK)
            loads++;
    }
    return NULL;
}

static void test_latch_threads_stress(void **st)
{
    roz_runtime_config_t cfg;
    pthread_t th[4];
    uint64_t n = 50000;
    const char *env = getenv("ROZ_LATCH_STRESS_TICKS");
    (void)st;

    if (env != NULL && strtoull(env, NULL, 10) > 0)
        n = strtoull(env, NULL, 10);
    wasm_len = roz_test_wat(controller_wat, wasm, sizeof wasm);
    roz_test_runtime_config(&cfg, &manifest, (roz_port_t){ &stress_ops, NULL, 0 }, NULL);
    cfg.clock = roz_clock_monotonic_ns;
    cfg.budget_ns = 500000000; /* sanitizers are slow; this test is about races */
    cfg.monitor_jitter = 0;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, wasm, wasm_len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    atomic_store(&stop, 0);
    assert_int_equal(pthread_create(&th[0], NULL, tick_main, &n), 0);
    assert_int_equal(pthread_create(&th[1], NULL, isr_main, NULL), 0);
    assert_int_equal(pthread_create(&th[2], NULL, supervisor_main, NULL), 0);
    assert_int_equal(pthread_create(&th[3], NULL, loader_main, NULL), 0);
    for (int i = 0; i < 4; i++)
        pthread_join(th[i], NULL);
    roz_runtime_log_drain(&rt);

    print_message("ticks %llu, controller %llu, traps %llu, clears %llu, loads %llu, rebuilds %llu, "
                  "e-stop checks %llu, message checks %llu, stats checks %llu\n",
                  (unsigned long long)n, (unsigned long long)RT_COUNT(&rt, controller_ticks),
                  (unsigned long long)traps, (unsigned long long)clears,
                  (unsigned long long)loads, (unsigned long long)RT_COUNT(&rt, rebuilds),
                  (unsigned long long)estop_checks, (unsigned long long)msg_checks,
                  (unsigned long long)stats_checks);
    assert_int_equal(reused, 0);
    assert_int_equal(stats_bad, 0);
    assert_true(stats_checks > 0);
    assert_int_equal(estop_lost, 0);
    assert_int_equal(msg_missing, 0);
    assert_true(traps > 0);
    assert_true(estop_checks > 0);
    roz_runtime_deinit(&rt);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_latch_threads_stress))
