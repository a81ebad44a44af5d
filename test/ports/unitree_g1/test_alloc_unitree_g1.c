/* SPDX-License-Identifier: Apache-2.0 */
/* No heap on the tick thread with the G1 port active: 100,000 ticks of the
 * G1 PD controller through unitree/G1 against the fake G1 (publishing
 * LowState_ every 2 ms), the port's writer event-driven (every write wakes
 * it) and spinning for the tick's command after each frame
 * (command_writer_spin_us), and Cyclone's threads receiving and sending
 * meanwhile; half-way the
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

#include "alloc_ticks.h"
#include "port_fixture.h"
#include "roz/port/unitree_g1.h"
#include "roz/runtime.h"
#include "support.h"
#include "unitree_g1_fixture.h"
#include "unitree_g1_manifest.h"

#define TICKS 100000

static void g1_counters(roz_alloc_port_counts_t *out)
{
    roz_unitree_g1_counters_t c;
    roz_unitree_g1_counters(roz_g1fx_port(), &c);
    out->received = c.frames;
    out->frames = c.frames;
    out->writes = c.writes;
    out->published = c.published;
}

static void motor_fault(void)
{
    roz_g1fx_ask("motorstate 5 7"); /* left_ankle_roll_joint reports a fault */
}

static void test_alloc_unitree_g1(void **st)
{
    roz_port_t port;
    char err[300] = "";
    (void)st;

    /* the port, event-driven, and a robot that publishes by itself */
    static const char *const periodic[] = { "--period-us", "2000", NULL };
    roz_g1fx_set_fake_args(periodic);
    roz_param_t spin[] = { { "command_writer_spin_us", "200" } };
    roz_params_t params = { spin, 1 };
    if (roz_fixture_unitree_g1.open(&roz_manifest_unitree_g1, &params, &port, err, sizeof err) !=
        ROZ_OK)
        fail_msg("open: %s", err);
    roz_alloc_case_t c = { &roz_manifest_unitree_g1, port, "g1_pd", TICKS, g1_counters,
                           motor_fault, ROZ_FAULT_ROBOT };
    roz_alloc_run(&c);
    roz_fixture_unitree_g1.close();
}

ROZ_TEST_MAIN(cmocka_unit_test(test_alloc_unitree_g1))
