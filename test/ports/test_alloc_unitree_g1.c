/* SPDX-License-Identifier: Apache-2.0 */
/* No heap on the tick thread with the G1 port active: 100,000 ticks of the
 * G1 PD controller through unitree/G1 against the fake G1 (publishing
 * LowState_ every 2 ms), the port's writer event-driven (every write wakes
 * it) and Cyclone's threads receiving and sending meanwhile; half-way the
 * robot reports a motor fault, so the fault path (ROZ_EROBOT, the ROBOT
 * latch, the safe defaults) runs too.
 *
 * alloc_ticks.c counts every allocation of the process, and those on the
 * tick thread. The ticks run back to back, not at 500 Hz: most read no
 * fresh frame, so stale_ticks is set past the run. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../support.h"
#include "alloc_ticks.h"
#include "port_fixture.h"
#include "roz/runtime.h"
#include "roz/unitree_g1.h"
#include "unitree_g1_fixture.h"
#include "unitree_g1_manifest.h"

#define TICKS 100000

static roz_runtime_t rt;

static void motor_fault(void *ctx)
{
    (void)ctx;
    roz_g1fx_ask("motorstate 5 7"); /* left_ankle_roll_joint reports a fault */
}

static void test_alloc_unitree_g1(void **st)
{
    roz_runtime_config_t cfg;
    roz_port_t port;
    size_t len;
    char err[300] = "";
    (void)st;

    /* the port, event-driven, and a robot that publishes by itself */
    static const char *const periodic[] = { "--period-us", "2000", NULL };
    roz_g1fx_set_fake_args(periodic);
    if (roz_fixture_unitree_g1.open(&roz_manifest_unitree_g1, NULL, &port, err, sizeof err) !=
        ROZ_OK)
        fail_msg("open: %s", err);

    const uint8_t *w = roz_test_controller("g1_pd", &len);
    roz_runtime_config_default(&cfg);
    cfg.manifest = &roz_manifest_unitree_g1;
    cfg.port = port;
    cfg.stale_ticks = 10u * TICKS; /* back to back: most reads are not fresh */
    cfg.monitor_jitter = 0;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    /* the robot's frames arrive */
    roz_unitree_g1_counters_t c0;
    for (int i = 0; i < 10000; i++) {
        roz_unitree_g1_counters(roz_g1fx_port(), &c0);
        if (c0.frames >= 10)
            break;
        roz_fake_g1_sleep_ms(1);
    }
    assert_true(c0.frames >= 10);

    roz_alloc_counts_t n;
    assert_int_equal(roz_alloc_ticks(&rt, TICKS, motor_fault, NULL, &n), 0);

    roz_unitree_g1_counters_t c;
    roz_unitree_g1_counters(roz_g1fx_port(), &c);
    print_message("%d ticks: %llu allocations and %llu frees on the tick thread; %llu elsewhere "
                  "(Cyclone's threads, the test); %llu frames in, %llu commands out\n",
                  TICKS, (unsigned long long)n.tick_allocations,
                  (unsigned long long)n.tick_frees, (unsigned long long)n.other_allocations,
                  (unsigned long long)(c.frames - c0.frames), (unsigned long long)c.published);
    assert_int_equal(n.tick_allocations, 0);
    assert_int_equal(n.tick_frees, 0);
    /* the port was busy meanwhile, and so was Cyclone */
    assert_true(c.frames - c0.frames > 10);
    assert_true(c.writes >= TICKS);
    assert_true(c.published > 100);
    assert_true(n.other_allocations > 0);
    roz_runtime_stats_t rs;
    assert_int_equal(roz_runtime_stats(&rt, &rs), ROZ_OK);
    assert_true(rs.runtime.controller_ticks > TICKS / 4);
    assert_true(roz_runtime_faults(&rt) & ROZ_FAULT_ROBOT);
    roz_runtime_deinit(&rt);
    roz_fixture_unitree_g1.close();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alloc_unitree_g1),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
