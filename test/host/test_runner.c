/* SPDX-License-Identifier: Apache-2.0 */
/* The host runner's thread never calls the log: with a log callback that
 * blocks forever and every wake-up over its jitter threshold, the ticks go
 * on, and the warnings come out where the application drains the runner's
 * monitor. The waits are bounded, as timeouts; no time is asserted. */
#define _GNU_SOURCE /* sched_getaffinity */
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h>

#include <cmocka.h>

#include "roz/runner.h"
#include "roz/hal/thread.h"
#include "support.h"
#include "support_blocking_log.h"

static atomic_uint ticks;

static int count_tick(void *ctx)
{
    (void)ctx;
    atomic_fetch_add(&ticks, 1u);
    return 0;
}

/* Wait until @p n ticks ran, at most about 20 s; 1 if they did. */
static int wait_ticks(unsigned n)
{
    struct timespec ms = { 0, 1000000 };
    for (int i = 0; i < 20000; i++) {
        if (atomic_load(&ticks) >= n)
            return 1;
        nanosleep(&ms, NULL);
    }
    return 0;
}

static void test_runner_blocking_log(void **st)
{
    static roz_runner_t r;
    roz_runner_config_t cfg = { .period_ns = 1000000, .log = roz_test_blocking_log };
    (void)st;
    atomic_store(&ticks, 0u);
    roz_test_blocking_log_arm();
    assert_int_equal(roz_runner_start(&r, &cfg, count_tick, NULL), ROZ_OK);
    /* every wake-up a warning: the thread's first one already */
    roz_monitor_set_threshold(&r.monitor, ROZ_MON_JITTER, 1);
    int went_on = wait_ticks(200);
    unsigned blocked = roz_test_blocking_log_blocked();
    size_t said = roz_monitor_drain(&r.monitor); /* the application's thread */
    roz_test_blocking_log_release();
    roz_runner_stop(&r);
    roz_runner_join(&r);
    assert_int_equal(blocked, 0);
    assert_true(went_on);
    roz_monitor_stat_t s;
    assert_int_equal(roz_monitor_snapshot(&r.monitor, ROZ_MON_JITTER, &s), ROZ_OK);
    assert_true(s.warned >= 1);
    assert_int_equal(said, 1);
    assert_true(roz_test_blocking_log_saw("runner: jitter took"));
}

/* The runner's thread carries the CPUs and stack it was given (and
 * SCHED_FIFO where permitted), read back from the running thread. */
static void test_runner_thread(void **st)
{
    static roz_runner_t r;
    roz_runner_config_t cfg = { .period_ns = 1000000, .stack_kib = 448, .realtime_priority = 3 };
    roz_thread_config_t got;
    cpu_set_t set;
    int cpu = 0;
    (void)st;
    assert_int_equal(sched_getaffinity(0, sizeof set, &set), 0);
    while (cpu < ROZ_THREAD_MAX_CPUS - 1 && !CPU_ISSET(cpu, &set))
        cpu++;
    cfg.cpus = 1ull << cpu;
    atomic_store(&ticks, 0u);
    assert_int_equal(roz_runner_start(&r, &cfg, count_tick, NULL), ROZ_OK);
    assert_int_equal(roz_thread_describe(r.thread, &got), ROZ_OK);
    int went_on = wait_ticks(5);
    roz_runner_stop(&r);
    roz_runner_join(&r);
    assert_true(went_on);
    assert_int_equal(got.cpus, 1ull << cpu);
    assert_int_equal(got.stack_kib, 448);
    assert_int_equal(got.sched, r.realtime ? ROZ_THREAD_FIFO : ROZ_THREAD_OTHER);
    if (!r.realtime)
        print_message("SCHED_FIFO not permitted here: the runner's CPUs and stack only\n");
}

ROZ_TEST_MAIN(cmocka_unit_test(test_runner_blocking_log),
              cmocka_unit_test(test_runner_thread))
