/* SPDX-License-Identifier: Apache-2.0 */
/* No heap while the socketcan port runs: malloc, calloc, realloc and free
 * are wrapped at link time (support_heap.h) and counted over 1000 ticks of
 * the leg's PD controller on the runtime, with the port's receive thread
 * and command writer running against fake actuators on a socketpair, an
 * actuator going silent and coming back in between (the stale fault, the
 * link fault, the start-up over again): every thread counts, not only the
 * tick. Opening, activating and stopping may allocate (threads); those are
 * outside the count. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "can_leg_manifest.h"
#include "can_test_support.h"
#include "roz/hal/clock.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_heap.h"

static roz_socketcan_t sc;
static fake_can_t bus;
static roz_test_can_t t;
static roz_runtime_t rt;

static void ticks(int n)
{
    for (int i = 0; i < n; i++) {
        int rc = roz_runtime_tick(&rt);
        (void)rc;
        struct timespec ts = { 0, 2000000 };
        nanosleep(&ts, NULL);
    }
}

static void test_alloc_socketcan_ticks(void **st)
{
    roz_runtime_config_t cfg;
    size_t len;
    const uint8_t *w = roz_test_controller("leg_pd", &len);
    const char *const params[] = { "command_writer_period_us", "2000", "reply_timeout_us",
                                   "10000", "command_timeout_us", "60000000", NULL };
    (void)st;
    roz_test_can_open(&t, &sc, &bus, &roz_manifest_can_leg, roz_test_leg_actuators, 3, 0.002, 0,
                      params);
    roz_runtime_config_default(&cfg);
    cfg.manifest = &roz_manifest_can_leg;
    cfg.port = t.port;
    cfg.clock = roz_clock_monotonic_ns;
    cfg.budget_ns = ROZ_BUDGET_OFF;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    ticks(50); /* the swap-in, the start-up */

    roz_heap_count_start();
    ticks(400);
    fake_can_mute(&bus, 2, 1);
    ticks(100); /* silent: STALE */
    fake_can_mute(&bus, 2, 0);
    ticks(100); /* back: LINK */
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(400);
    roz_heap_count_stop();

    roz_socketcan_counters_t c;
    roz_socketcan_counters(&sc, &c);
    assert_true(c.lost >= 1);
    assert_true(c.commands_sent > 300);
    roz_runtime_stats_t stats;
    assert_int_equal(roz_runtime_stats(&rt, &stats), ROZ_OK);
    assert_true(stats.runtime.faults[2] >= 1); /* STALE */
    assert_true(stats.runtime.faults[5] >= 1); /* LINK */
    print_message("%llu allocations, %llu frees over 1000 ticks, every thread\n",
                  (unsigned long long)roz_heap_allocations(),
                  (unsigned long long)roz_heap_frees());
    assert_int_equal(roz_heap_allocations(), 0);
    assert_int_equal(roz_heap_frees(), 0);
    roz_test_can_close(&t);
    roz_runtime_deinit(&rt);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_alloc_socketcan_ticks))
