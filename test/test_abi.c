/* SPDX-License-Identifier: Apache-2.0 */
/* Every import's semantics, including bad indices and NaN/Inf. */
/* white-box: this test reads the private fields of the module it tests */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/abi.h"
#include "support.h"
#include "ur5_manifest.h"

static roz_abi_t abi;
static double target[ROZ_CFG_MAX_COMMANDS];
static double state[ROZ_CFG_MAX_STATES];
static roz_metric_ring_t ring;

static int setup(void **st)
{
    (void)st;
    memset(&ring, 0, sizeof ring);
    roz_abi_init(&abi, &roz_manifest_ur5, target, &ring);
    for (int i = 0; i < 12; i++)
        state[i] = 0.1 * i;
    roz_abi_begin_tick(&abi, 0, state);
    return 0;
}

static void test_abi_import_table(void **st)
{
    (void)st;
    assert_int_equal(roz_abi_import_count, 12);
    assert_string_equal(roz_abi_find_import("command", "set")->signature, "i(iF)");
    assert_string_equal(roz_abi_find_import("state", "get")->signature, "F(i)");
    assert_string_equal(roz_abi_find_import("timing", "sim_time_ns")->signature, "I()");
    assert_string_equal(roz_abi_find_import("safety", "request_estop")->signature, "v()");
    assert_null(roz_abi_find_import("command", "get"));
    assert_null(roz_abi_find_import("env", "set"));
    assert_null(roz_abi_find_import(NULL, "set"));
}

static void test_abi_command_set(void **st)
{
    (void)st;
    for (int i = 0; i < 6; i++)
        assert_true(target[i] == 0.0); /* defaults */
    assert_int_equal(roz_abi_command_set(&abi, 0, 1.0), ROZ_ABI_SET_TAKEN);
    assert_true(target[0] == 1.0);
    assert_int_equal(roz_abi_command_set(&abi, 0, 3.14), ROZ_ABI_SET_TAKEN);
    assert_int_equal(roz_abi_command_set(&abi, 1, 4.0), ROZ_ABI_SET_CLAMPED);
    assert_true(target[1] == 3.14);
    assert_int_equal(roz_abi_command_set(&abi, 1, -1e308), ROZ_ABI_SET_CLAMPED);
    assert_true(target[1] == -3.14);
    assert_int_equal(roz_abi_command_set(&abi, 2, NAN), ROZ_ABI_SET_REFUSED);
    assert_true(isnan(target[2])); /* the filter turns it into the safe default */
    assert_int_equal(roz_abi_command_set(&abi, 3, INFINITY), ROZ_ABI_SET_REFUSED);
    assert_int_equal(roz_abi_command_set(&abi, 3, -INFINITY), ROZ_ABI_SET_REFUSED);
    assert_int_equal(roz_abi_command_set(&abi, -1, 0.0), ROZ_ABI_SET_REFUSED);
    assert_int_equal(roz_abi_command_set(&abi, 6, 0.0), ROZ_ABI_SET_REFUSED);
    assert_int_equal(roz_abi_command_set(&abi, INT32_MIN, 0.0), ROZ_ABI_SET_REFUSED);
    assert_int_equal(roz_abi_command_set(&abi, INT32_MAX, 0.0), ROZ_ABI_SET_REFUSED);
    assert_true(target[5] == 0.0); /* refused indices wrote nothing */
    assert_int_equal(abi.counters.sets, 11);
    assert_int_equal(abi.counters.set_clamped, 2);
    assert_int_equal(abi.counters.set_nonfinite, 3);
    assert_int_equal(abi.counters.set_bad_index, 4);
}

static void test_abi_queries(void **st)
{
    (void)st;
    assert_int_equal(roz_abi_command_count(&abi), 6);
    assert_int_equal(roz_abi_state_count(&abi), 12);
    assert_true(roz_abi_command_limit_min(&abi, 3) == -3.14);
    assert_true(roz_abi_command_limit_max(&abi, 3) == 3.14);
    assert_true(isnan(roz_abi_command_limit_min(&abi, 6)));
    assert_true(isnan(roz_abi_command_limit_max(&abi, -1)));
    assert_true(roz_abi_state_get(&abi, 11) == 0.1 * 11);
    assert_true(isnan(roz_abi_state_get(&abi, 12)));
    assert_true(isnan(roz_abi_state_get(&abi, -5)));
    assert_int_equal(abi.counters.get_bad_index, 4);
    assert_true(roz_abi_math_sin(0.0) == 0.0);
    assert_near(roz_abi_math_cos(3.141592653589793), -1.0, 1e-15);
    assert_true(isnan(roz_abi_math_sin(INFINITY)));
}

static void test_abi_timing(void **st)
{
    roz_test_clock_t clk = { 5000, 7 };
    (void)st;
    assert_int_equal(roz_abi_timing_now_ns(&abi), 0); /* no clock */
    abi.clock = roz_test_clock;
    abi.clock_ctx = &clk;
    assert_int_equal(roz_abi_timing_now_ns(&abi), 5000);
    assert_int_equal(roz_abi_timing_now_ns(&abi), 5007);
    abi.tick = 0;
    assert_int_equal(roz_abi_timing_sim_time_ns(&abi), 0);
    abi.tick = 250; /* 100 Hz: 2.5 s */
    assert_int_equal(roz_abi_timing_sim_time_ns(&abi), 2500000000ll);
}

static void test_abi_estop_and_metrics(void **st)
{
    roz_metric_t m;
    (void)st;
    assert_false(abi.estop_requested);
    roz_abi_safety_request_estop(&abi);
    assert_true(abi.estop_requested);
    assert_int_equal(abi.counters.estop_requests, 1);
    roz_abi_reset(&abi);
    assert_false(abi.estop_requested);

    abi.tick = 3;
    roz_abi_telemetry_emit_metric(&abi, 1.5);
    roz_abi_telemetry_emit_metric(&abi, NAN); /* kept as is: it is telemetry */
    assert_int_equal(roz_metric_ring_pop(&ring, &m), 1);
    assert_int_equal(m.tick, 3);
    assert_true(m.value == 1.5);
    assert_int_equal(roz_metric_ring_pop(&ring, &m), 1);
    assert_true(isnan(m.value));
    assert_int_equal(roz_metric_ring_pop(&ring, &m), 0);
    /* a full ring drops and counts, never blocks */
    for (int i = 0; i < ROZ_CFG_TELEMETRY_RING + 10; i++)
        roz_abi_telemetry_emit_metric(&abi, i);
    assert_int_equal(ring.dropped, 10);
    assert_int_equal(abi.counters.metrics, ROZ_CFG_TELEMETRY_RING + 12);
    int popped = 0;
    while (roz_metric_ring_pop(&ring, &m))
        assert_true(m.value == popped++);
    assert_int_equal(popped, ROZ_CFG_TELEMETRY_RING);
    /* without a ring metrics are only counted */
    abi.metrics = NULL;
    roz_abi_telemetry_emit_metric(&abi, 2.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_abi_import_table),
        cmocka_unit_test_setup(test_abi_command_set, setup),
        cmocka_unit_test_setup(test_abi_queries, setup),
        cmocka_unit_test_setup(test_abi_timing, setup),
        cmocka_unit_test_setup(test_abi_estop_and_metrics, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
