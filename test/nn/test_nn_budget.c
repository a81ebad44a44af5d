/* SPDX-License-Identifier: Apache-2.0 */
/* A controller's declared fuel (custom section roz.fuel, ROZ_FUEL_PER_TICK
 * of roz_controller.h) on the G1 (500 Hz: a default budget of 20,000 units
 * a tick, a ceiling of 80,000): a module heavy every 10th tick fails
 * verification on the default and passes with its declaration, which
 * verification holds it to; a declaration above the ceiling, or malformed,
 * is refused at load; the next controller without one gets the default
 * again; the example policy (g1_policy.c) runs with its declaration. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/identity.h"
#include "roz/runtime.h"
#include "support_runtime.h"
#include "support_wat.h"
#include "unitree_g1_manifest.h"

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;
static uint8_t wasm[8192];

static int teardown(void **st)
{
    (void)st;
    roz_runtime_deinit(&rt);
    return 0;
}

static void start(uint64_t fuel_max)
{
    roz_runtime_config_t cfg;
    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_unitree_g1, NULL, &clk);
    cfg.fuel_per_tick_max = fuel_max;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
}

/* A loop of `iters` iterations on every 10th tick (10 units each),
 * nothing on the others. */
static size_t heavy_module(int iters)
{
    char text[1024];
    snprintf(text, sizeof text,
             "(module\n"
             "  (func (export \"process\") (param $t i64) (local $i i32)\n"
             "    (if (i64.eqz (i64.rem_u (local.get $t) (i64.const 10)))\n"
             "      (then (loop $l\n"
             "        (local.set $i (i32.add (local.get $i) (i32.const 1)))\n"
             "        (br_if $l (i32.lt_u (local.get $i) (i32.const %d))))))))\n",
             iters);
    return roz_test_wat(text, wasm, sizeof wasm);
}

/* Appends a custom section roz.fuel with `payload` to the module. */
static size_t with_section(size_t len, const uint8_t *payload, size_t n)
{
    static const char name[] = ROZ_FUEL_SECTION;
    size_t body = 1 + (sizeof name - 1) + n;
    assert_true(body < 128 && len + 2 + body <= sizeof wasm);
    wasm[len++] = 0;
    wasm[len++] = (uint8_t)body;
    wasm[len++] = (uint8_t)(sizeof name - 1);
    memcpy(wasm + len, name, sizeof name - 1);
    len += sizeof name - 1;
    memcpy(wasm + len, payload, n);
    return len + n;
}

static size_t declare(size_t len, uint64_t units)
{
    uint8_t rec[9] = { ROZ_FUEL_VERSION };
    for (int i = 0; i < 8; i++)
        rec[1 + i] = (uint8_t)(units >> (8 * i));
    return with_section(len, rec, sizeof rec);
}

static void test_nn_budget_declared_fuel(void **st)
{
    roz_verify_report_t rep;
    (void)st;
    start(0);
    /* about 30,000 units on ticks 0, 10, ..., 90: over the default */
    size_t len = heavy_module(3000);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_EVERIFY);
    assert_non_null(strstr(roz_runtime_error(&rt), "fuel exhausted at tick 0"));
    assert_int_equal(rep.fuel_budget, 20000);
    assert_int_equal(rep.fuel_declared, 0);

    /* declared: granted, and verification ran its heavy ticks under it */
    len = declare(heavy_module(3000), 60000);
    if (roz_runtime_load(&rt, wasm, len, &rep) != ROZ_OK)
        fail_msg("load: %s", roz_runtime_error(&rt));
    assert_int_equal(rep.fuel_declared, 60000);
    assert_int_equal(rep.fuel_budget, 60000);
    assert_int_equal(rep.ticks_run, ROZ_RUNTIME_VERIFY_TICKS);
    assert_true(rep.fuel[0] > 20000 && rep.fuel[90] == rep.fuel[0] && rep.fuel[5] < 100);
    for (int t = 0; t < 50; t++)
        assert_int_equal(roz_runtime_tick(&rt), ROZ_OK);

    /* declared too little for its heavy ticks: held to it */
    len = declare(heavy_module(3000), 25000);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_EVERIFY);
    assert_int_equal(rep.fuel_budget, 25000);

    /* above the ceiling (80,000 at 500 Hz): refused before it runs */
    len = declare(heavy_module(10), 80001);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_EINVAL);
    assert_non_null(strstr(roz_runtime_error(&rt), "declares 80001 fuel units per tick"));
    assert_non_null(strstr(roz_runtime_error(&rt), "fuel_per_tick_max 80000"));
    len = declare(heavy_module(10), 80000);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_OK);

    /* the next controller without a declaration: the default again */
    for (int t = 0; t < 2; t++)
        assert_int_equal(roz_runtime_tick(&rt), ROZ_OK);
    len = heavy_module(10);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_OK);
    assert_int_equal(rep.fuel_budget, 20000);
}

static void test_nn_budget_configured_ceiling(void **st)
{
    roz_verify_report_t rep;
    (void)st;
    start(200000);
    size_t len = declare(heavy_module(12000), 150000);
    if (roz_runtime_load(&rt, wasm, len, &rep) != ROZ_OK)
        fail_msg("load: %s", roz_runtime_error(&rt));
    assert_int_equal(rep.fuel_budget, 150000);
}

static void test_nn_budget_malformed(void **st)
{
    static const struct {
        uint8_t payload[20];
        size_t n;
        const char *why;
    } cases[] = {
        { { 0 }, 0, "empty" },
        { { 2, 1 }, 9, "record version 2" },
        { { 1, 0x10, 0x27 }, 5, "cut short" },
        { { 1 }, 9, "0 units" },
        { { 1, 0x10, 0x27, 0, 0, 0, 0, 0, 0, 1, 0x11, 0x27 }, 18, "two different" },
    };
    roz_verify_report_t rep;
    (void)st;
    start(0);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        size_t len = with_section(heavy_module(10), cases[k].payload, cases[k].n);
        assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_EINVAL);
        if (strstr(roz_runtime_error(&rt), cases[k].why) == NULL)
            fail_msg("%s: %s", cases[k].why, roz_runtime_error(&rt));
    }
    /* two copies of one record (one per object file): accepted */
    uint8_t twice[18] = { 1, 0x10, 0x27, 0, 0, 0, 0, 0, 0, 1, 0x10, 0x27 };
    size_t len = with_section(heavy_module(10), twice, sizeof twice);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_OK);
    assert_int_equal(rep.fuel_declared, 10000);
    assert_int_equal(roz_runtime_tick(&rt), ROZ_OK);
    /* two sections */
    len = declare(declare(heavy_module(10), 10000), 10000);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_EINVAL);
    assert_non_null(strstr(roz_runtime_error(&rt), "two custom sections"));
    /* 2^64 - 1 units is ROZ_BUDGET_OFF: a module never declares itself
     * unmetered, not even without a ceiling (rozrun --fuel-max off) */
    roz_runtime_deinit(&rt);
    start(ROZ_BUDGET_OFF);
    len = declare(heavy_module(10), UINT64_MAX);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_EINVAL);
    if (strstr(roz_runtime_error(&rt), "18446744073709551615 units declared") == NULL)
        fail_msg("%s", roz_runtime_error(&rt));
    len = declare(heavy_module(10), UINT64_MAX - 1);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, &rep), ROZ_OK);
    assert_int_equal(rep.fuel_budget, UINT64_MAX - 1);
}

#if ROZ_NN_HAVE_POLICY
/* The example policy: its declaration is what its inference ticks need;
 * 1,000 ticks (2 s) on the loopback G1 without a fault. */
static void test_nn_budget_policy_example(void **st)
{
    roz_verify_report_t rep;
    roz_runtime_stats_t stats;
    size_t len;
    (void)st;
    start(0);
    const uint8_t *w = roz_test_controller("g1_policy", &len);
    if (roz_runtime_load(&rt, w, len, &rep) != ROZ_OK)
        fail_msg("load: %s", roz_runtime_error(&rt));
    assert_int_equal(rep.fuel_declared, rep.fuel_budget);
    assert_true(rep.fuel[0] > 20000 && rep.fuel[0] <= rep.fuel_declared);
    assert_true(rep.fuel[1] < 5000);
    print_message("g1_policy: inference tick %llu units, other ticks %llu, declared %llu\n",
                  (unsigned long long)rep.fuel[10], (unsigned long long)rep.fuel[1],
                  (unsigned long long)rep.fuel_declared);
    for (int t = 0; t < 1000; t++)
        assert_int_equal(roz_runtime_tick(&rt), ROZ_OK);
    assert_int_equal(roz_runtime_stats(&rt, &stats), ROZ_OK);
    assert_int_equal(stats.abi.nn_refused, 0);
    assert_int_equal(stats.abi.nn_calls, 100u * 9u); /* 9 calls an inference, 50 Hz */
    assert_true(stats.runtime.max_fuel <= rep.fuel_declared);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_teardown(test_nn_budget_declared_fuel, teardown),
        cmocka_unit_test_teardown(test_nn_budget_configured_ceiling, teardown),
        cmocka_unit_test_teardown(test_nn_budget_malformed, teardown),
#if ROZ_NN_HAVE_POLICY
        cmocka_unit_test_teardown(test_nn_budget_policy_example, teardown),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
