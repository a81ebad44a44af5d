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
    assert_int_equal(roz_abi_import_count, 16);
    assert_string_equal(roz_abi_find_import("nn", "matvec")->signature, "i(iiiiiii)");
    assert_string_equal(roz_abi_find_import("nn", "act")->signature, "i(iii)");
    assert_string_equal(roz_abi_find_import("state", "get_all")->signature, "i(ii)");
    assert_string_equal(roz_abi_find_import("command", "set_all")->signature, "i(ii)");
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

/* ---- the bulk extension, on a fake linear memory ---------------------------- */

static uint8_t mem[256];

static void put_f64(uint8_t *p, double v)
{
    uint64_t b;
    memcpy(&b, &v, 8);
    for (int i = 0; i < 8; i++)
        p[i] = (uint8_t)(b >> (8 * i)); /* little-endian, as WebAssembly */
}

static double get_f64(const uint8_t *p)
{
    uint64_t b = 0;
    double v;
    for (int i = 0; i < 8; i++)
        b |= (uint64_t)p[i] << (8 * i);
    memcpy(&v, &b, 8);
    return v;
}

/* state.get_all copies the snapshot, little-endian, at any alignment. */
static void test_abi_bulk_get_all(void **st)
{
    (void)st;
    memset(mem, 0xAA, sizeof mem);
    assert_int_equal(roz_abi_state_get_all(&abi, mem, sizeof mem, 3, 12), 12); /* unaligned */
    for (int i = 0; i < 12; i++)
        assert_true(get_f64(mem + 3 + 8 * i) == 0.1 * i);
    assert_int_equal(mem[2], 0xAA);       /* nothing before */
    assert_int_equal(mem[3 + 96], 0xAA);  /* nothing after */
    assert_int_equal(roz_abi_state_get_all(&abi, mem, sizeof mem, 0, 0), 0);
    assert_int_equal(roz_abi_state_get_all(&abi, mem, sizeof mem, 256 - 40, 5), 5); /* to the end */
    assert_int_equal(abi.counters.get_bad_index, 0);
}

/* Hostile arguments: refused, nothing written, counted. */
static void test_abi_bulk_get_all_hostile(void **st)
{
    static const struct {
        uint32_t ptr;
        int32_t count;
    } bad[] = {
        { 256 - 39, 5 },       /* one byte past the end */
        { 256, 1 },            /* starts at the end */
        { UINT32_MAX, 1 },     /* the top of a 32-bit address space */
        { UINT32_MAX - 7, 1 }, /* ptr + 8 wraps in 32 bits */
        { 0, 13 },             /* more than the manifest's 12 states */
        { 0, -1 },
        { 0, INT32_MIN },
        { 0, INT32_MAX },      /* 8 * count wraps in 32 bits */
        { 0, 0x20000000 },     /* 8 * count is exactly 2^32 */
    };
    (void)st;
    memset(mem, 0x55, sizeof mem);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        assert_int_equal(roz_abi_state_get_all(&abi, mem, sizeof mem, bad[k].ptr, bad[k].count), -1);
    for (size_t i = 0; i < sizeof mem; i++)
        assert_int_equal(mem[i], 0x55);
    assert_int_equal(abi.counters.get_bad_index, sizeof bad / sizeof bad[0]);
    /* no memory at all, and no snapshot */
    assert_int_equal(roz_abi_state_get_all(&abi, NULL, 0, 0, 1), -1);
    roz_abi_begin_tick(&abi, 1, NULL);
    assert_int_equal(roz_abi_state_get_all(&abi, mem, sizeof mem, 0, 1), -1);
    assert_int_equal(roz_abi_state_get_all(&abi, mem, sizeof mem, 0, 0), -1);
}

/* command.set_all is command.set per value: the same targets and counters
 * as separate calls, on values that are taken, clamped and refused. */
static void test_abi_bulk_set_all_equals_set(void **st)
{
    static const double v[6] = { 1.0, 4.0, NAN, -1e308, INFINITY, -0.0 };
    static double target2[ROZ_CFG_MAX_COMMANDS];
    roz_abi_t one;
    (void)st;
    roz_abi_init(&one, &roz_manifest_ur5, target2, NULL);
    target[5] = target2[5] = 0.5; /* channels past count keep theirs */
    for (int i = 0; i < 6; i++)
        put_f64(mem + 1 + 8 * i, v[i]); /* unaligned */
    int refused_or_clamped = 0;
    for (int i = 0; i < 5; i++)
        refused_or_clamped += roz_abi_command_set(&one, i, v[i]) != ROZ_ABI_SET_TAKEN;
    assert_int_equal(roz_abi_command_set_all(&abi, mem, sizeof mem, 1, 5), refused_or_clamped);
    assert_int_equal(refused_or_clamped, 4);
    assert_memory_equal(target, target2, sizeof target); /* bit for bit, NaN included */
    assert_memory_equal(&abi.counters, &one.counters, sizeof one.counters);
    assert_true(target[5] == 0.5);
    /* all six, -0.0 taken as it is */
    assert_int_equal(roz_abi_command_set_all(&abi, mem, sizeof mem, 1, 6), 4);
    assert_true(target[5] == 0.0 && signbit(target[5]));
    assert_int_equal(abi.counters.sets, 11);
}

/* Hostile arguments: refused as a whole, no target touched, one bad set. */
static void test_abi_bulk_set_all_hostile(void **st)
{
    static const struct {
        uint32_t ptr;
        int32_t count;
    } bad[] = {
        { 256 - 47, 6 }, { 256, 1 }, { UINT32_MAX, 1 }, { UINT32_MAX - 7, 1 },
        { 0, 7 },        { 0, -1 },  { 0, INT32_MIN },  { 0, INT32_MAX }, { 0, 0x20000000 },
    };
    double before[ROZ_CFG_MAX_COMMANDS];
    (void)st;
    for (int i = 0; i < 32; i++)
        put_f64(mem + 8 * i, 1.0);
    memcpy(before, target, sizeof before);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        assert_int_equal(roz_abi_command_set_all(&abi, mem, sizeof mem, bad[k].ptr, bad[k].count),
                         -1);
    assert_int_equal(roz_abi_command_set_all(&abi, NULL, 0, 0, 1), -1);
    assert_memory_equal(before, target, sizeof before);
    assert_int_equal(abi.counters.sets, sizeof bad / sizeof bad[0] + 1);
    assert_int_equal(abi.counters.set_bad_index, sizeof bad / sizeof bad[0] + 1);
    assert_int_equal(abi.counters.set_clamped + abi.counters.set_nonfinite, 0);
    /* the state copied out and the commands read from the same bytes */
    assert_int_equal(roz_abi_state_get_all(&abi, mem, sizeof mem, 8, 6), 6);
    assert_int_equal(roz_abi_command_set_all(&abi, mem, sizeof mem, 8, 6), 0);
    for (int i = 0; i < 6; i++)
        assert_true(target[i] == 0.1 * i);
}

ROZ_TEST_MAIN(cmocka_unit_test_setup(test_abi_bulk_get_all, setup),
              cmocka_unit_test_setup(test_abi_bulk_get_all_hostile, setup),
              cmocka_unit_test_setup(test_abi_bulk_set_all_equals_set, setup),
              cmocka_unit_test_setup(test_abi_bulk_set_all_hostile, setup),
              cmocka_unit_test(test_abi_import_table),
              cmocka_unit_test_setup(test_abi_command_set, setup),
              cmocka_unit_test_setup(test_abi_queries, setup),
              cmocka_unit_test_setup(test_abi_timing, setup),
              cmocka_unit_test_setup(test_abi_estop_and_metrics, setup))
