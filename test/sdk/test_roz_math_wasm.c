/* SPDX-License-Identifier: Apache-2.0 */
/* roz_math.h built for wasm32 and run through the runtime on the loopback
 * simulator (UR5):
 *  - the math probe (math_probe.c) emits every function's result on the
 *    inputs of math_probe.h each tick: the same bits as the header built
 *    natively (the f64.sqrt/floor/ceil/trunc/abs instructions and the
 *    portable C agree, and so does everything built on them), and within
 *    the documented error of the host's libm (long double);
 *  - the reach example (examples/controllers/reach.c) drives the arm along
 *    its inverse kinematics: no fault, nothing outside the manifest, and the
 *    joints where the same kinematics computed with libm put them. */
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
#include "support.h"
#include "support_runtime.h"
#include "ulps.h"
#include "ur5_manifest.h"

#define PROBE_TICKS 3000

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;

static void start(void)
{
    roz_runtime_config_t cfg;
    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, &clk);
    roz_test_runtime_start(&rt, &cfg, NULL);
}

static int teardown(void **st)
{
    (void)st;
    roz_runtime_deinit(&rt);
    return 0;
}

/* libm's value of function @f on the probe's inputs of tick @t */
static long double reference(int f, long long t)
{
    double x = probe_input(t, 0), y = probe_input(t, 1);
    switch (f) {
    case PROBE_SIN:   return sinl(x);
    case PROBE_COS:   return cosl(x);
    case PROBE_ATAN2: return atan2l(y, x);
    case PROBE_EXP:   return expl(x);
    case PROBE_LOG:   return logl(x);
    case PROBE_POW:   return powl(t % 2 ? fabs(x) : x, t % 4 == 2 ? y / 64.0 : y);
    case PROBE_TANH:  return tanhl(x);
    default:          return 0.0L;
    }
}

static void test_math_wasm_probe(void **st)
{
    static const char *const names[PROBE_COUNT] = {
        "fabs", "sqrt", "floor", "ceil", "trunc", "fmin", "fmax", "clamp",
        "sin", "cos", "atan2", "exp", "log", "pow", "tanh",
    };
    double worst[PROBE_COUNT] = { 0 };
    roz_verify_report_t rep;
    size_t len;
    const uint8_t *w = roz_test_wasm_file(ROZ_MATH_PROBE, &len);
    (void)st;

    start();
    assert_int_equal(roz_runtime_load(&rt, w, len, &rep), ROZ_OK);
    print_message("math probe: %llu fuel units for one call of each of the %d functions "
                  "(the most of any verify tick)\n", (unsigned long long)rep.max_fuel,
                  PROBE_COUNT);
    for (long long t = 0; t < PROBE_TICKS; t++) {
        double native[PROBE_COUNT];
        roz_metric_t m;
        assert_int_equal(roz_runtime_tick(&rt), ROZ_OK);
        probe_results(t, native);
        for (int f = 0; f < PROBE_COUNT; f++) {
            if (!roz_runtime_metric_pop(&rt, &m))
                fail_msg("tick %lld: %d metrics, expected %d", t, f, PROBE_COUNT);
            assert_int_equal(m.tick, t);
            /* the wasm build gives the native build's bits (any NaN for NaN) */
            if (bits_of(m.value) != bits_of(native[f]) && !(isnan(m.value) && isnan(native[f])))
                fail_msg("tick %lld: %s(%.17g, %.17g): wasm %.17g, native %.17g", t, names[f],
                         probe_input(t, 0), probe_input(t, 1), m.value, native[f]);
            if (f >= PROBE_SIN && isfinite(m.value) && isfinite((double)reference(f, t))) {
                double e = ulps(m.value, reference(f, t));
                if (e > worst[f])
                    worst[f] = e;
            }
        }
        assert_false(roz_runtime_metric_pop(&rt, &m));
    }
    for (int f = PROBE_SIN; f < PROBE_COUNT; f++) {
        print_message("math probe in wasm: %-5s max error %.3f ulp\n", names[f], worst[f]);
        assert_true(worst[f] < 1.0); /* the documented bound of every function */
    }
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* The reach example's joint targets at time t, with libm. */
static void reach_targets(double t, double q[6])
{
    const double l1 = 0.425, l2 = 0.39225;
    double r = 0.55 + 0.10 * cos(0.5 * t), h = 0.15 + 0.10 * sin(0.5 * t);
    double c = (r * r + h * h - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    double elbow = acos(c);
    double lift = atan2(h, r) + atan2(l2 * sin(elbow), l1 + l2 * cos(elbow));
    q[0] = 0.4 * sin(0.2 * t);
    q[1] = -lift;
    q[2] = elbow;
    q[3] = lift - elbow;
    q[4] = 0.0;
    q[5] = 0.0;
}

static void test_math_wasm_reach_drives_ur5(void **st)
{
    size_t len;
    const uint8_t *w = roz_test_controller("reach", &len);
    double state[ROZ_CFG_MAX_STATES], want[6];
    roz_metric_t m = { 0, NAN };
    (void)st;

    start();
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    for (int i = 0; i < 1500; i++) { /* 15 s */
        assert_int_equal(roz_runtime_tick(&rt), ROZ_OK);
        assert_int_equal(roz_loopback_counters(&lb).violations, 0);
        while (roz_runtime_metric_pop(&rt, &m)) {
        }
    }
    assert_int_equal(roz_runtime_faults(&rt), 0);
    /* tick 1499 commanded toward the targets of t = 14.99 s; the simulator
     * has moved the arm since by one period at that speed */
    roz_loopback_true_state(&lb, state);
    reach_targets(14.99, want);
    for (int j = 0; j < 6; j++)
        if (!(fabs(state[j] - want[j]) < 0.01))
            fail_msg("joint %d at %.6f rad, the kinematics want %.6f", j, state[j], want[j]);
    /* and the controller's own tracking error, its last metric, says so */
    assert_int_equal(m.tick, 1499);
    assert_true(m.value < 0.01);
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_math_wasm_probe, teardown),
              cmocka_unit_test_teardown(test_math_wasm_reach_drives_ur5, teardown))
