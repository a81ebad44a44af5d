/* SPDX-License-Identifier: Apache-2.0 */
/* No heap on the tick thread with a ROS 2 port active: 100,000 ticks of the
 * robot's stand controller through engineai/PM01 (and agibot/X2) against
 * the fake robot (publishing every state topic every 2 ms), the port's
 * writer event-driven (every write wakes it) and Cyclone's threads
 * receiving and sending meanwhile, the samples' sequences and strings
 * filled in place. Half-way the robot restarts (the PM01: LINK, the hold
 * again) or reports an error state (the X2: ROBOT), so the fault paths run
 * too.
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
#include "engineai_pm01_manifest.h"
#include "port_fixture.h"
#include "ros2_fixture.h"
#include "roz/runtime.h"
#ifdef ROZ_TEST_HAVE_AGIBOT_X2
#include "agibot_x2_manifest.h"
#endif

#define TICKS 100000

static roz_runtime_t rt;

static void ask_midway(void *ctx)
{
    roz_ros2fx_ask("%s", (const char *)ctx);
}

/* @p midway: the fake's request half-way; @p fault: what it latches. */
static void run(const roz_port_fixture_t *fx, const roz_manifest_t *m, const char *controller,
                const char *midway, unsigned fault)
{
    roz_runtime_config_t cfg;
    roz_port_t port;
    size_t len;
    char err[300] = "";

    static const char *const periodic[] = { "--period-us", "2000", NULL };
    roz_ros2fx_set_fake_args(periodic);
    if (fx->open(m, NULL, &port, err, sizeof err) != ROZ_OK)
        fail_msg("open: %s", err);

    const uint8_t *w = roz_test_controller(controller, &len);
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = port;
    cfg.stale_ticks = 10u * TICKS; /* back to back: most reads are not fresh */
    cfg.monitor_jitter = 0;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    roz_ros2_counters_t c0;
    for (int i = 0; i < 10000; i++) {
        roz_ros2_counters(roz_ros2fx_bridge(), &c0);
        if (c0.topic[0].samples >= 10)
            break;
        roz_fake_sleep_ms(1);
    }
    assert_true(c0.topic[0].samples >= 10);

    roz_alloc_counts_t n;
    assert_int_equal(roz_alloc_ticks(&rt, TICKS, ask_midway, (void *)(uintptr_t)midway, &n), 0);

    roz_ros2_counters_t c;
    roz_ros2_counters(roz_ros2fx_bridge(), &c);
    print_message("%s: %d ticks: %llu allocations and %llu frees on the tick thread; %llu "
                  "elsewhere (Cyclone's threads, the test); %llu frames in, %llu passes out\n",
                  m->robot_id, TICKS, (unsigned long long)n.tick_allocations,
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
    assert_true(roz_runtime_faults(&rt) & fault);
    roz_runtime_deinit(&rt);
    fx->close();
}

static void test_alloc_engineai_pm01(void **st)
{
    (void)st;
    run(&roz_fixture_engineai_pm01, &roz_manifest_engineai_pm01, "pm01_stand", "restart",
        ROZ_FAULT_LINK);
}

#ifdef ROZ_TEST_HAVE_AGIBOT_X2
static void test_alloc_agibot_x2(void **st)
{
    (void)st;
    run(&roz_fixture_agibot_x2, &roz_manifest_agibot_x2, "x2_stand", "error arm 1",
        ROZ_FAULT_ROBOT);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alloc_engineai_pm01),
#ifdef ROZ_TEST_HAVE_AGIBOT_X2
        cmocka_unit_test(test_alloc_agibot_x2),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
