/* SPDX-License-Identifier: Apache-2.0 */
/* The bulk extension under wasm3: the G1 PD through state.get_all and
 * command.set_all gives the per-channel PD's targets and counters bit for
 * bit; hostile modules (pointers past the memory, wrapping and huge
 * counts, no memory at all, overlapping and unaligned arrays) are refused
 * call by call without a trap or a stray byte; the values moved are
 * charged as fuel before they move. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/controller.h"
#include "support.h"
#include "support_wat.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

static roz_controller_t ctl[2];
static roz_abi_t abi[2];
static double target[2][ROZ_CFG_MAX_COMMANDS];
static double state[ROZ_CFG_MAX_STATES];
static uint8_t wasm[4096];

static int teardown(void **st)
{
    (void)st;
    roz_controller_unload(&ctl[0]);
    roz_controller_unload(&ctl[1]);
    return 0;
}

static void load(int k, const roz_manifest_t *m, const uint8_t *w, size_t len, uint64_t fuel)
{
    roz_budget_t b = { fuel, ROZ_BUDGET_OFF, NULL, NULL };
    roz_controller_init(&ctl[k]);
    roz_abi_init(&abi[k], m, target[k], NULL);
    roz_abi_begin_tick(&abi[k], 0, state);
    if (roz_controller_load(&ctl[k], w, len, &abi[k]) != ROZ_OK)
        fail_msg("load: %s", roz_controller_error(&ctl[k]));
    assert_int_equal(roz_controller_set_budget(&ctl[k], &b), ROZ_OK);
}

/* A state sequence that takes every path of command.set: in range, outside
 * narrow limits (clamped), NaN and infinities (refused). */
static void fill_state(const roz_manifest_t *m, int64_t t)
{
    for (uint16_t i = 0; i < m->n_states; i++)
        state[i] = (double)(((int64_t)i * 37 + t * 11) % 2003) / 1000.0 - 1.0;
    if (t % 7 == 3)
        state[t % m->n_states] = NAN;
    if (t % 11 == 5)
        state[(t * 3) % m->n_states] = -INFINITY;
    if (t % 13 == 1)
        state[(t * 5) % m->n_states] = 1e300;
}

static void test_bulk_g1_pd_equals_per_channel(void **st)
{
    const roz_manifest_t *m = &roz_manifest_unitree_g1;
    size_t len[2];
    const uint8_t *w[2] = { roz_test_controller("g1_pd", &len[0]),
                            roz_test_controller("g1_pd_bulk", &len[1]) };
    roz_abi_counters_t c[2];
    (void)st;
    for (int k = 0; k < 2; k++)
        load(k, m, w[k], len[k], 1000000);
    for (int64_t t = 0; t < 2000; t++) {
        fill_state(m, t);
        for (int k = 0; k < 2; k++) {
            roz_abi_begin_tick(&abi[k], t, state);
            assert_int_equal(roz_controller_process(&ctl[k], t), ROZ_OK);
        }
        assert_memory_equal(target[0], target[1], m->n_commands * sizeof(double));
    }
    roz_abi_counters_get(&abi[0], &c[0]);
    roz_abi_counters_get(&abi[1], &c[1]);
    assert_memory_equal(&c[0], &c[1], sizeof c[0]);
    assert_int_equal(c[0].sets, 2000u * m->n_commands);
    assert_true(c[0].set_clamped > 0 && c[0].set_nonfinite > 0); /* every path was taken */
    /* the point of it: fewer units of fuel (a call per tick, not 203) */
    print_message("fuel per tick: per channel %llu, bulk %llu\n",
                  (unsigned long long)roz_controller_fuel_used(&ctl[0]),
                  (unsigned long long)roz_controller_fuel_used(&ctl[1]));
    assert_true(roz_controller_fuel_used(&ctl[1]) < roz_controller_fuel_used(&ctl[0]));
}

/* One bulk call with the given arguments; its result lands in command 0 of
 * the UR5 divided by 1000 (inside the limits of +-3.14). One page of memory
 * (65536 bytes) unless `memory` is 0. */
static int32_t bulk_call(const char *import, uint32_t ptr, int32_t count, int memory,
                         uint64_t *fuel)
{
    char text[1024];
    snprintf(text, sizeof text,
             "(module\n"
             "  (import \"%s\" \"%s\" (func $bulk (param i32 i32) (result i32)))\n"
             "  (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))\n"
             "  %s\n"
             "  (func (export \"process\") (param i64)\n"
             "    (drop (call $set (i32.const 0)\n"
             "      (f64.mul (f64.const 0.001)\n"
             "        (f64.convert_i32_s (call $bulk (i32.const %u) (i32.const %d))))))))\n",
             strcmp(import, "get_all") == 0 ? "state" : "command", import,
             memory ? "(memory 1)" : "", (unsigned)ptr, (int)count);
    size_t len = roz_test_wat(text, wasm, sizeof wasm);
    roz_controller_unload(&ctl[0]);
    load(0, &roz_manifest_ur5, wasm, len, 1000000);
    roz_abi_begin_tick(&abi[0], 0, state);
    assert_int_equal(roz_controller_process(&ctl[0], 0), ROZ_OK); /* never a trap */
    if (fuel != NULL)
        *fuel = roz_controller_fuel_used(&ctl[0]);
    return (int32_t)lround(target[0][0] * 1000.0);
}

static void test_bulk_hostile_arguments(void **st)
{
    static const struct {
        uint32_t ptr;
        int32_t count;
        int ok;
    } cases[] = {
        { 0, 6, 1 },               /* fits */
        { 65536 - 48, 6, 1 },      /* ends at the last byte */
        { 65536 - 47, 6, 0 },      /* one byte past it */
        { 65536, 1, 0 },           /* starts past it */
        { 0xFFFFFFFFu, 1, 0 },     /* -1 as an address */
        { 0xFFFFFFF8u, 1, 0 },     /* ptr + 8 wraps in 32 bits */
        { 0, 0x20000000, 0 },      /* 8 count is 2^32 */
        { 0, 0x7FFFFFFF, 0 },      /* huge */
        { 0, -1, 0 },
        { 0, (int32_t)0x80000000u, 0 },
        { 0, 7, 0 },               /* more commands than the UR5 has */
        { 3, 6, 1 },               /* unaligned */
        { 0, 0, 1 },
    };
    (void)st;
    memset(state, 0, sizeof state);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        for (int g = 0; g < 2; g++) {
            const char *imp = g ? "get_all" : "set_all";
            int32_t want = cases[k].ok ? (g ? cases[k].count : 0) : -1;
            if (g && cases[k].count == 7) /* the UR5 has 12 states */
                want = 7;
            int32_t got = bulk_call(imp, cases[k].ptr, cases[k].count, 1, NULL);
            if (got != want)
                fail_msg("%s(%u, %d): %d, expected %d", imp, (unsigned)cases[k].ptr,
                         (int)cases[k].count, (int)got, (int)want);
        }
    }
    /* a module without memory: every bulk call refused, even a count of 0 */
    assert_int_equal(bulk_call("get_all", 0, 0, 0, NULL), -1);
    assert_int_equal(bulk_call("set_all", 0, 0, 0, NULL), -1);
}

/* A refused call changes no target; a state copy and a command read from
 * overlapping bytes give the state back. */
static void test_bulk_refused_writes_nothing(void **st)
{
    static const char text[] =
        "(module\n"
        "  (import \"state\" \"get_all\" (func $get (param i32 i32) (result i32)))\n"
        "  (import \"command\" \"set_all\" (func $set (param i32 i32) (result i32)))\n"
        "  (memory 1)\n"
        "  (func (export \"process\") (param i64)\n"
        "    (f64.store (i32.const 65528) (f64.const 2.0))\n"
        "    (drop (call $set (i32.const 65528) (i32.const 2)))\n" /* past the end: refused */
        "    (drop (call $get (i32.const 101) (i32.const 12)))\n"  /* unaligned */
        "    (drop (call $set (i32.const 101) (i32.const 6)))))\n"; /* the same bytes */
    size_t len = roz_test_wat(text, wasm, sizeof wasm);
    roz_abi_counters_t c;
    (void)st;
    for (int i = 0; i < 12; i++)
        state[i] = 0.25 * i;
    state[2] = 9.0; /* clamped to 3.14 on the way back */
    load(0, &roz_manifest_ur5, wasm, len, 1000000);
    roz_abi_begin_tick(&abi[0], 0, state);
    assert_int_equal(roz_controller_process(&ctl[0], 0), ROZ_OK);
    for (int i = 0; i < 6; i++)
        assert_true(target[0][i] == (i == 2 ? 3.14 : 0.25 * i));
    roz_abi_counters_get(&abi[0], &c);
    assert_int_equal(c.sets, 7); /* one refused call, six values */
    assert_int_equal(c.set_bad_index, 1);
    assert_int_equal(c.set_clamped, 1);
}

/* Fuel: the values moved are charged (1 unit each out, 2 each in), so a
 * bulk call's cost grows with its count and a budget stops a flood. */
static void test_bulk_fuel(void **st)
{
    uint64_t f0, f6, g0, g12;
    static const char flood[] =
        "(module\n"
        "  (import \"command\" \"set_all\" (func $set (param i32 i32) (result i32)))\n"
        "  (memory 1)\n"
        "  (func (export \"process\") (param i64)\n"
        "    (loop $l (drop (call $set (i32.const 0) (i32.const 6))) (br $l))))\n";
    (void)st;
    memset(state, 0, sizeof state);
    bulk_call("set_all", 0, 0, 1, &f0);
    bulk_call("set_all", 0, 6, 1, &f6);
    bulk_call("get_all", 0, 0, 1, &g0);
    bulk_call("get_all", 0, 12, 1, &g12);
    assert_int_equal(f6 - f0, 6 * 2);
    assert_int_equal(g12 - g0, 12 * 1);
    size_t len = roz_test_wat(flood, wasm, sizeof wasm);
    roz_controller_unload(&ctl[0]);
    load(0, &roz_manifest_ur5, wasm, len, 100000);
    roz_abi_begin_tick(&abi[0], 0, state);
    assert_int_equal(roz_controller_process(&ctl[0], 0), ROZ_ETIMEDOUT);
    assert_non_null(strstr(roz_controller_error(&ctl[0]), "fuel exhausted"));
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_bulk_g1_pd_equals_per_channel, teardown),
              cmocka_unit_test_teardown(test_bulk_hostile_arguments, teardown),
              cmocka_unit_test_teardown(test_bulk_refused_writes_nothing, teardown),
              cmocka_unit_test_teardown(test_bulk_fuel, teardown))
