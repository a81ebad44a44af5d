/* SPDX-License-Identifier: Apache-2.0 */
/* Operator inputs (roz/inputs.h): the rules a tick applies to the latest
 * value a source set (clamped and non-finite values counted, a stale input
 * back to its default, every change within the rate cap), on hand-picked
 * and random sequences; and a source thread setting while the tick takes
 * (run under ThreadSanitizer by the tsan build). */
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/inputs.h"
#include "support.h"
#include "support_inputs.h"

static const roz_channel_t cmds[] = {
    ROZ_TEST_WHEEL_VELOCITY,
};
static const roz_channel_t states[] = {
    { .name = "wheel/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -10.0,
      .max = 10.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
/* vx: rate 0.01 a tick, stale after 100 ms (50 ticks); a button: default 1 */
static const roz_channel_t ins[] = {
    { .name = "operator/velocity.x", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -1.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 0.01, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/mode", .type = ROZ_IF_POSITION, .unit = "", .min = 0.0, .max = 3.0,
      .default_value = 1.0, .max_rate = 0.5, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_input_rule_t rules[] = { { .stale_after_ms = 100 }, { .stale_after_ms = 20 } };
static const roz_manifest_t man = { "op_bot", "generic", ROZ_TEST_INPUTS_RATE_HZ, cmds, 1,
                                    states, 1, NULL, ins, 2, 0, NULL, rules };

ROZ_TEST_INPUTS_BENCH(man)

static void test_manifest_with_inputs_is_valid(void **st)
{
    roz_manifest_problem_t p;
    roz_channel_t bad[2] = { ins[0], ins[1] };
    roz_input_rule_t bad_rules[2] = { rules[0], rules[1] };
    roz_manifest_t m = man;
    (void)st;
    assert_int_equal(roz_manifest_validate(&man, &p), ROZ_OK);
    m.input_rules = NULL; /* inputs without their rules */
    assert_int_equal(roz_manifest_validate(&m, &p), ROZ_EINVAL);
    assert_int_equal(p.rule, ROZ_MANIFEST_RULE_INPUT);
    assert_int_equal(p.is_state, 2);
    assert_int_equal(p.index, -1);
    m.inputs = bad;
    m.input_rules = bad_rules;
    bad_rules[0].stale_after_ms = 0; /* no staleness rule */
    assert_int_equal(roz_manifest_validate(&m, &p), ROZ_EINVAL);
    assert_int_equal(p.rule, ROZ_MANIFEST_RULE_INPUT);
    assert_int_equal(p.is_state, 2);
    bad_rules[0] = rules[0];
    bad[0].max_rate = 0.0; /* it would jump back */
    assert_int_equal(roz_manifest_validate(&m, &p), ROZ_EINVAL);
    assert_int_equal(p.rule, ROZ_MANIFEST_RULE_INPUT);
    bad[0] = ins[0];
    bad[0].name = "wheel/position"; /* a state's name */
    assert_int_equal(roz_manifest_validate(&m, &p), ROZ_EINVAL);
    assert_int_equal(p.rule, ROZ_MANIFEST_RULE_INPUT);
}

static void test_default_before_any_value(void **st)
{
    (void)st;
    for (int i = 0; i < 200; i++)
        step();
    assert_true(ib.out[0] == 0.0 && ib.out[1] == 1.0);
    assert_int_equal(ib.in.counters.stale, 0);
    assert_int_equal(roz_inputs_set(&ib.in, 2, 0.0), ROZ_EINVAL);
}

static void test_follows_at_the_rate_cap(void **st)
{
    (void)st;
    assert_int_equal(roz_inputs_set(&ib.in, 0, 0.5), ROZ_OK);
    step();
    assert_true(fabs(ib.out[0] - 0.01) < 1e-12);
    for (int i = 0; i < 48; i++) {
        double before = ib.out[0];
        step();
        assert_true(ib.out[0] - before <= 0.01 + 1e-12);
    }
    step(); /* 50 ticks x 0.01: there, exactly */
    assert_true(ib.out[0] == 0.5);
    assert_int_equal(ib.in.counters.clamped + ib.in.counters.nonfinite, 0);
}

static void test_out_of_range_clamped_and_counted(void **st)
{
    (void)st;
    assert_int_equal(roz_inputs_set(&ib.in, 1, 7.0), ROZ_OK);
    step();
    assert_int_equal(ib.in.counters.clamped, 1);
    step();
    step();
    assert_true(ib.out[1] == 2.5);
    step();
    assert_true(ib.out[1] == 3.0); /* the limit, never beyond */
    step();
    assert_true(ib.out[1] == 3.0);
    assert_int_equal(roz_inputs_set(&ib.in, 1, -1e300), ROZ_OK);
    step();
    assert_int_equal(ib.in.counters.clamped, 2);
    assert_true(ib.out[1] == 2.5);
}

static void test_nonfinite_refused_and_counted(void **st)
{
    (void)st;
    assert_int_equal(roz_inputs_set(&ib.in, 0, 0.3), ROZ_OK);
    for (int i = 0; i < 30; i++)
        step();
    assert_true(ib.out[0] == 0.3);
    assert_int_equal(roz_inputs_set(&ib.in, 0, NAN), ROZ_OK);
    step();
    assert_true(ib.out[0] == 0.3);
    assert_int_equal(roz_inputs_set(&ib.in, 0, INFINITY), ROZ_OK);
    step();
    assert_int_equal(roz_inputs_set(&ib.in, 0, -INFINITY), ROZ_OK);
    step();
    assert_true(ib.out[0] == 0.3);
    assert_int_equal(ib.in.counters.nonfinite, 3);
    assert_int_equal(ib.in.counters.clamped, 0);
    /* a refused value does not keep the input fresh: 100 ms after the last
     * good value it goes stale */
    for (int i = 0; i < 50 - 33; i++)
        step();
    assert_int_equal(ib.in.counters.stale, 0);
    for (int i = 0; i < 20; i++)
        step();
    assert_int_equal(ib.in.counters.stale, 1);
}

static void test_stale_returns_to_default_by_the_rate_cap(void **st)
{
    int moved = 0;
    (void)st;
    uint64_t taken = 0;
    for (int i = 0; i < 90; i++) { /* the source repeats its value every 10 ticks */
        if (i % 10 == 0) {
            assert_int_equal(roz_inputs_set(&ib.in, 0, -0.8), ROZ_OK);
            taken = ib.tick + 1;
        }
        step();
    }
    assert_true(ib.out[0] == -0.8);
    /* no update: held for stale_after_ms (50 ticks), then back to 0 at 0.01 a
     * tick, never a jump */
    while (ib.tick < taken + 50) {
        step();
        assert_true(ib.out[0] == -0.8);
    }
    assert_int_equal(ib.in.counters.stale, 0);
    for (int i = 0; i < 100; i++) {
        double before = ib.out[0];
        step();
        assert_true(fabs(ib.out[0] - before) <= 0.01 + 1e-12);
        moved += ib.out[0] != before;
    }
    assert_int_equal(ib.in.counters.stale, 1);
    assert_true(ib.out[0] == 0.0);
    assert_int_equal(moved, 80); /* 0.8 at 0.01 a tick */
    /* a fresh value takes over again */
    assert_int_equal(roz_inputs_set(&ib.in, 0, 0.02), ROZ_OK);
    step();
    step();
    assert_true(ib.out[0] == 0.02);
}

/* Random sources: any value, any time; the output stays within the limits,
 * moves at most the rate cap a tick, and reads the default after staleness. */
static void test_never_a_jump_random(void **st)
{
    uint64_t x = 0x9e3779b97f4a7c15ull;
    double prev[2] = { 0.0, 1.0 };
    (void)st;
    for (int t = 0; t < 200000; t++) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        if ((x & 15u) == 0u) {
            uint32_t k = (uint32_t)(x >> 8) & 1u;
            double v;
            switch ((x >> 12) & 7u) {
            case 0: v = NAN; break;
            case 1: v = (x >> 16) & 1u ? INFINITY : -INFINITY; break;
            case 2: v = (double)(int64_t)(x >> 20) * 1e-3; break; /* far outside */
            default: v = (double)((x >> 24) % 4000u) / 1000.0 - 1.0; break;
            }
            assert_int_equal(roz_inputs_set(&ib.in, k, v), ROZ_OK);
        }
        if ((x & 0xfffu) == 1u) /* a silence long enough to go stale */
            ib.tick += 200;
        step();
        for (int k = 0; k < 2; k++) {
            assert_true(isfinite(ib.out[k]));
            assert_true(ib.out[k] >= ins[k].min && ib.out[k] <= ins[k].max);
            assert_true(fabs(ib.out[k] - prev[k]) <= ins[k].max_rate + 1e-12);
            prev[k] = ib.out[k];
        }
    }
    assert_true(ib.in.counters.nonfinite > 0 && ib.in.counters.clamped > 0 &&
                ib.in.counters.stale > 0);
}

/* A source thread sets while this one ticks (ThreadSanitizer: no race). */
static _Atomic int stop_setting;

static void *setter(void *arg)
{
    uint32_t i = 0;
    (void)arg;
    while (!stop_setting) {
        (void)roz_inputs_set(&ib.in, i & 1u, (double)(i % 200u) / 100.0 - 1.0);
        i++;
    }
    return NULL;
}

static void test_setter_thread_vs_tick(void **st)
{
    pthread_t th;
    double prev[2] = { 0.0, 1.0 };
    (void)st;
    stop_setting = 0;
    assert_int_equal(pthread_create(&th, NULL, setter, NULL), 0);
    for (int t = 0; t < 20000; t++) {
        step();
        for (int k = 0; k < 2; k++) {
            assert_true(ib.out[k] >= ins[k].min && ib.out[k] <= ins[k].max);
            assert_true(fabs(ib.out[k] - prev[k]) <= ins[k].max_rate + 1e-12);
            prev[k] = ib.out[k];
        }
    }
    stop_setting = 1;
    pthread_join(th, NULL);
    assert_int_equal(ib.in.counters.nonfinite, 0);
}

ROZ_TEST_MAIN(cmocka_unit_test_setup(test_manifest_with_inputs_is_valid, setup),
              cmocka_unit_test_setup(test_default_before_any_value, setup),
              cmocka_unit_test_setup(test_follows_at_the_rate_cap, setup),
              cmocka_unit_test_setup(test_out_of_range_clamped_and_counted, setup),
              cmocka_unit_test_setup(test_nonfinite_refused_and_counted, setup),
              cmocka_unit_test_setup(test_stale_returns_to_default_by_the_rate_cap, setup),
              cmocka_unit_test_setup(test_never_a_jump_random, setup),
              cmocka_unit_test_setup(test_setter_thread_vs_tick, setup))
