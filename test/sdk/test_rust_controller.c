/* SPDX-License-Identifier: Apache-2.0 */
/* Rust controllers (sdk/rust, built by roz_add_rust_controller()) against
 * their C twins, each pair run side by side on two loopback UR5s:
 *  - twin.rs / twin.c (twin.h): the bulk pair, every math function, the
 *    host's sin/cos, a declared fuel, clamps: the same targets and commands
 *    bit for bit every tick on every channel, the same metrics, counters
 *    and identity;
 *  - reach.rs / reach.c (the examples): the same; and reach.zig (Zig from
 *    PyPI, its math roz_math.h compiled by Zig's C compiler) where it was
 *    built, which carries no identity;
 *  - math_probe.rs / math_probe.c: every function of the Rust SDK's math on
 *    the probe's inputs gives the C header's bits (and so the native ones);
 *  - reach.rs linked with rustc's default stack of 1 MiB is refused, the
 *    error naming the pages and the stack flag;
 *  - a Rust panic traps and an endless loop runs out of fuel: each latches
 *    its fault, and the robot gets the safe defaults. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "math_probe.h"
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support_runtime.h"
#include "twin.h"
#include "ulps.h"
#include "ur5_manifest.h"

typedef struct {
    roz_runtime_t    rt;
    roz_loopback_t   lb;
    roz_test_clock_t clk;
} side_t;

static side_t c_side, rs_side;

static void start(side_t *s)
{
    roz_runtime_config_t cfg;
    s->clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &s->lb, &roz_manifest_ur5, NULL, &s->clk);
    roz_test_runtime_start(&s->rt, &cfg, NULL);
}

static int teardown(void **st)
{
    (void)st;
    roz_runtime_deinit(&c_side.rt);
    roz_runtime_deinit(&rs_side.rt);
    return 0;
}

/* <name>.wasm from the examples' build folder (reach, reach_rs) or this
 * folder's (the rest) */
static const uint8_t *module(const char *name, size_t *len)
{
    return roz_test_wasm(strncmp(name, "reach", 5) == 0 ? ROZ_CONTROLLER_DIR : ROZ_SDK_TEST_DIR,
                         name, len);
}

static void load(side_t *s, const char *name, roz_verify_report_t *rep)
{
    size_t len;
    const uint8_t *w = module(name, &len);
    if (roz_runtime_load(&s->rt, w, len, rep) != ROZ_OK)
        fail_msg("%s: %s", name, roz_runtime_error(&s->rt));
    print_message("%-14s %5zu bytes, fuel %6llu units (most of a verify tick), declared %llu\n",
                  name, len, (unsigned long long)rep->max_fuel,
                  (unsigned long long)rep->fuel_declared);
}

/* Runs controller @c_name on one UR5 and @rs_name on another for @ticks;
 * fails at the first bit that differs. Returns the clamps counted. */
static uint64_t run_twins(const char *c_name, const char *rs_name, int ticks,
                          uint64_t *fuel_declared)
{
    roz_verify_report_t rc, rr;
    roz_runtime_stats_t sc, sr;
    const size_t n = roz_manifest_ur5.n_commands;
    uint64_t metrics = 0;

    start(&c_side);
    start(&rs_side);
    load(&c_side, c_name, &rc);
    load(&rs_side, rs_name, &rr);
    assert_int_equal(rc.ticks_run, rr.ticks_run);
    assert_int_equal(rc.clamped, rr.clamped);
    assert_int_equal(rc.fuel_declared, rr.fuel_declared);
    *fuel_declared = rr.fuel_declared;
    if (strstr(rs_name, "_zig") != NULL) { /* no identity outside C and Rust */
        assert_int_equal(rr.identity.present, 0);
        assert_int_equal(rr.identity_match, ROZ_IDENTITY_NONE);
    } else { /* the same identity record: the generated module's bytes are the header's */
        assert_int_equal(rc.identity.present, rr.identity.present);
        assert_string_equal(rc.identity.robot_id, rr.identity.robot_id);
        assert_true(rc.identity.hash == rr.identity.hash);
        assert_int_equal(rr.identity_match, ROZ_IDENTITY_SAME);
    }
    for (int t = 0; t < ticks; t++) {
        roz_metric_t mc, mr;
        const double *tc, *tr, *cc, *cr;
        assert_int_equal(roz_runtime_tick(&c_side.rt), ROZ_OK);
        assert_int_equal(roz_runtime_tick(&rs_side.rt), ROZ_OK);
        tc = roz_runtime_last_targets(&c_side.rt);
        tr = roz_runtime_last_targets(&rs_side.rt);
        cc = roz_runtime_last_commands(&c_side.rt);
        cr = roz_runtime_last_commands(&rs_side.rt);
        for (size_t i = 0; i < n; i++) {
            if (bits_of(tc[i]) != bits_of(tr[i]))
                fail_msg("tick %d, channel %zu: target C %.17g, Rust %.17g", t, i, tc[i], tr[i]);
            if (bits_of(cc[i]) != bits_of(cr[i]))
                fail_msg("tick %d, channel %zu: command C %.17g, Rust %.17g", t, i, cc[i], cr[i]);
        }
        while (roz_runtime_metric_pop(&c_side.rt, &mc)) {
            if (!roz_runtime_metric_pop(&rs_side.rt, &mr))
                fail_msg("tick %d: Rust emitted fewer metrics", t);
            assert_int_equal(mc.tick, mr.tick);
            if (bits_of(mc.value) != bits_of(mr.value))
                fail_msg("tick %d: metric C %.17g, Rust %.17g", t, mc.value, mr.value);
            metrics++;
        }
        assert_false(roz_runtime_metric_pop(&rs_side.rt, &mr));
    }
    assert_int_equal(roz_runtime_faults(&c_side.rt), 0);
    assert_int_equal(roz_runtime_faults(&rs_side.rt), 0);
    assert_int_equal(roz_runtime_stats(&c_side.rt, &sc), ROZ_OK);
    assert_int_equal(roz_runtime_stats(&rs_side.rt, &sr), ROZ_OK);
    assert_memory_equal(&sc.abi, &sr.abi, sizeof sc.abi);
    assert_memory_equal(&sc.filter, &sr.filter, sizeof sc.filter);
    assert_true(metrics >= (uint64_t)ticks);
    assert_int_equal(roz_loopback_counters(&c_side.lb).violations, 0);
    assert_int_equal(roz_loopback_counters(&rs_side.lb).violations, 0);
    return sc.abi.set_clamped;
}

static void test_rust_twin_bit_identical(void **st)
{
    uint64_t fuel;
    (void)st;
    /* the first joint's command goes beyond its limits: clamped alike */
    assert_true(run_twins("twin", "twin_rs", 2000, &fuel) > 0);
    assert_int_equal(fuel, TWIN_FUEL); /* roz_controller::fuel_per_tick! */
}

static void test_rust_reach_bit_identical(void **st)
{
    uint64_t fuel;
    (void)st;
    run_twins("reach", "reach_rs", 1500, &fuel);
    assert_int_equal(fuel, 0);
}

#ifdef ROZ_TEST_ZIG
static void test_zig_reach_bit_identical(void **st)
{
    uint64_t fuel;
    (void)st;
    run_twins("reach", "reach_zig", 1500, &fuel);
}
#endif

static void test_rust_math_probe(void **st)
{
    roz_verify_report_t rc, rr;
    (void)st;
    start(&c_side);
    start(&rs_side);
    load(&c_side, "math_probe", &rc);
    load(&rs_side, "math_probe_rs", &rr);
    for (long long t = 0; t < 3000; t++) {
        double native[PROBE_COUNT];
        assert_int_equal(roz_runtime_tick(&c_side.rt), ROZ_OK);
        assert_int_equal(roz_runtime_tick(&rs_side.rt), ROZ_OK);
        probe_results(t, native);
        for (int f = 0; f < PROBE_COUNT; f++) {
            roz_metric_t mc, mr;
            assert_true(roz_runtime_metric_pop(&c_side.rt, &mc));
            if (!roz_runtime_metric_pop(&rs_side.rt, &mr))
                fail_msg("tick %lld: the Rust probe emitted %d metrics", t, f);
            /* any NaN for NaN: WebAssembly leaves a NaN's sign and payload open */
            if (bits_of(mc.value) != bits_of(mr.value) && !(isnan(mc.value) && isnan(mr.value)))
                fail_msg("tick %lld, function %d (%.17g, %.17g): C %.17g, Rust %.17g", t, f,
                         probe_input(t, 0), probe_input(t, 1), mc.value, mr.value);
            if (bits_of(native[f]) != bits_of(mr.value) && !(isnan(native[f]) && isnan(mr.value)))
                fail_msg("tick %lld, function %d: native %.17g, Rust %.17g", t, f, native[f],
                         mr.value);
        }
    }
    assert_int_equal(roz_runtime_faults(&rs_side.rt), 0);
}

static void test_rust_default_stack_refused(void **st)
{
    size_t len;
    const uint8_t *w = module("reach_rs_default_stack", &len);
    const char *err;
    (void)st;
    start(&rs_side);
    assert_int_equal(roz_runtime_load(&rs_side.rt, w, len, NULL), ROZ_EINVAL);
    err = roz_runtime_error(&rs_side.rt);
    print_message("refused: %s\n", err);
    assert_non_null(strstr(err, "linear memory too large: 17 pages of 64 KiB"));
    assert_non_null(strstr(err, "stack-size"));
}

/* @name faults at tick 150 with @fault; until then it drove the arm */
static void check_fault(const char *name, unsigned fault, const char *text)
{
    roz_verify_report_t rep;
    start(&rs_side);
    load(&rs_side, name, &rep);
    for (int t = 0; t < 200; t++) /* OK until tick 150 faults, then EFAULT */
        assert_int_equal(roz_runtime_tick(&rs_side.rt), t < 150 ? ROZ_OK : ROZ_EFAULT);
    assert_int_equal(roz_runtime_faults(&rs_side.rt), fault);
    print_message("%s: %s\n", name, roz_runtime_fault_message(&rs_side.rt));
    assert_non_null(strstr(roz_runtime_fault_message(&rs_side.rt), text));
    /* the safe default of a velocity channel is 0, ramped by the rate cap */
    for (size_t i = 0; i < roz_manifest_ur5.n_commands; i++)
        assert_true(roz_runtime_last_commands(&rs_side.rt)[i] == 0.0);
    assert_int_equal(roz_loopback_counters(&rs_side.lb).violations, 0);
}

static void test_rust_panic_traps(void **st)
{
    (void)st;
    check_fault("bad_panic_rs", ROZ_FAULT_TRAP, "trap at tick 150");
}

static void test_rust_spin_runs_out_of_fuel(void **st)
{
    (void)st;
    check_fault("bad_spin_rs", ROZ_FAULT_OVERRUN, "at tick 150");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_teardown(test_rust_twin_bit_identical, teardown),
        cmocka_unit_test_teardown(test_rust_reach_bit_identical, teardown),
#ifdef ROZ_TEST_ZIG
        cmocka_unit_test_teardown(test_zig_reach_bit_identical, teardown),
#endif
        cmocka_unit_test_teardown(test_rust_math_probe, teardown),
        cmocka_unit_test_teardown(test_rust_default_stack_refused, teardown),
        cmocka_unit_test_teardown(test_rust_panic_traps, teardown),
        cmocka_unit_test_teardown(test_rust_spin_runs_out_of_fuel, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
