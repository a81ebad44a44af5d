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

#include "alloc_ticks.h"
#include "engineai_pm01_manifest.h"
#include "port_fixture.h"
#include "ros2_fixture.h"
#include "roz/runtime.h"
#include "support.h"
#ifdef ROZ_TEST_HAVE_AGIBOT_X2
#include "agibot_x2_manifest.h"
#endif

#define TICKS 100000

static void ros2_counters(roz_alloc_port_counts_t *out)
{
    roz_ros2_counters_t c;
    roz_ros2_counters(roz_ros2fx_bridge(), &c);
    /* received: the fewest samples of any topic (the X2's port has no
     * frame until every group has delivered, and the run's first ticks
     * must find one: waiting on the first topic alone let them write
     * nothing on a loaded machine) */
    uint64_t fewest = UINT64_MAX;
    for (uint16_t t = 0; t < c.n_topics; t++)
        if (c.topic[t].samples < fewest)
            fewest = c.topic[t].samples;
    out->received = c.n_topics > 0 ? fewest : 0;
    out->frames = c.frames;
    out->writes = c.writes;
    out->published = c.published;
}

static const char *midway_request;

static void ask_midway(void)
{
    roz_ros2fx_ask("%s", midway_request);
}

/* @p midway: the fake's request half-way; @p fault: what it latches. */
static void run(const roz_port_fixture_t *fx, const roz_manifest_t *m, const char *controller,
                const char *midway, unsigned fault)
{
    roz_port_t port;
    char err[300] = "";

    static const char *const periodic[] = { "--period-us", "2000", NULL };
    roz_ros2fx_set_fake_args(periodic);
    /* the writer also spins for the tick's command after each sample */
    roz_param_t spin[] = { { "command_writer_spin_us", "200" } };
    roz_params_t params = { spin, 1 };
    if (fx->open(m, &params, &port, err, sizeof err) != ROZ_OK)
        fail_msg("open: %s", err);
    midway_request = midway;
    roz_alloc_case_t c = { m, port, controller, TICKS, ros2_counters, ask_midway, fault };
    roz_alloc_run(&c);
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
