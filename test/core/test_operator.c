/* SPDX-License-Identifier: Apache-2.0 */
/* Operator devices (roz/operator.h): the vocabulary of fields, the
 * manifest's rule on an input's source and scale, and a device frame
 * reaching exactly the inputs that name its fields, scaled, through the
 * inputs' rules (a NaN refused and counted). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/inputs.h"
#include "support.h"
#include "support_inputs.h"
#include "roz/operator.h"

static const roz_channel_t cmds[] = {
    ROZ_TEST_WHEEL_VELOCITY,
};
/* vx = 0.8 ly, vy = -0.5 lx, a button, a twist's yaw, and one only the API sets */
static const roz_channel_t ins[] = {
    { .name = "operator/velocity.x", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -0.8,
      .max = 0.8, .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/velocity.y", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -0.5,
      .max = 0.5, .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/walk", .type = ROZ_IF_POSITION, .unit = "", .min = 0.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/yaw_rate", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -1.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/mode", .type = ROZ_IF_POSITION, .unit = "", .min = 0.0, .max = 3.0,
      .default_value = 1.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
#define N_INS (sizeof ins / sizeof ins[0])
static const roz_input_rule_t rules[N_INS] = {
    { .stale_after_ms = 100, .source = ROZ_OPERATOR_REMOTE_LY, .scale = 0.8 },
    { .stale_after_ms = 100, .source = ROZ_OPERATOR_REMOTE_LX, .scale = -0.5 },
    { .stale_after_ms = 100, .source = ROZ_OPERATOR_REMOTE_BTN_A, .scale = 1.0 },
    { .stale_after_ms = 100, .source = ROZ_OPERATOR_TWIST_ANGULAR_Z, .scale = 1.0 },
    { .stale_after_ms = 100 },
};
static const roz_manifest_t man = { "op_bot", "generic", ROZ_TEST_INPUTS_RATE_HZ, cmds, 1,
                                    NULL, 0, NULL, ins, N_INS, 0, NULL, rules };

ROZ_TEST_INPUTS_BENCH(man)

static void test_vocabulary(void **st)
{
    roz_operator_field_t f;
    (void)st;
    for (int i = 1; i < (int)ROZ_OPERATOR_FIELD_COUNT_; i++) {
        const char *name = roz_operator_field_name((roz_operator_field_t)i);
        assert_int_equal(roz_operator_field_parse(name, strlen(name), &f), ROZ_OK);
        assert_int_equal(f, i);
        assert_int_not_equal(roz_operator_field_device(f), ROZ_OPERATOR_DEVICE_NONE);
    }
    assert_string_equal(roz_operator_field_name(ROZ_OPERATOR_REMOTE_BTN_SELECT),
                        "remote.btn.select");
    assert_string_equal(roz_operator_field_name(ROZ_OPERATOR_TWIST_LINEAR_Y), "twist.linear.y");
    assert_string_equal(roz_operator_field_name(ROZ_OPERATOR_FIELD_COUNT_), "?");
    assert_int_equal(roz_operator_field_parse("remote.lz", 9, &f), ROZ_EINVAL);
    assert_int_equal(roz_operator_field_parse("remote.l", 8, &f), ROZ_EINVAL);
    assert_int_equal(roz_operator_field_parse("", 0, &f), ROZ_EINVAL); /* not a source */
    assert_int_equal(roz_operator_field_parse("remote.lxx", 9, &f), ROZ_OK); /* by length */
    assert_int_equal(f, ROZ_OPERATOR_REMOTE_LX);
    /* Unitree's key union: R1 bit 0, start 2, select 3, A 8, left 15 */
    assert_int_equal(ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_R1), 0x0001);
    assert_int_equal(ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_START), 0x0004);
    assert_int_equal(ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_SELECT), 0x0008);
    assert_int_equal(ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_L2), 0x0020);
    assert_int_equal(ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_A), 0x0100);
    assert_int_equal(ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_B), 0x0200);
    assert_int_equal(ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_LEFT), 0x8000);
    assert_int_equal(roz_operator_field_device(ROZ_OPERATOR_NONE), ROZ_OPERATOR_DEVICE_NONE);
    assert_int_equal(roz_operator_field_device(ROZ_OPERATOR_REMOTE_BTN_LEFT),
                     ROZ_OPERATOR_DEVICE_REMOTE);
    assert_int_equal(roz_operator_field_device(ROZ_OPERATOR_TWIST_LINEAR_X),
                     ROZ_OPERATOR_DEVICE_TWIST);
}

/* Input 1 with the rule @p bad (the other inputs' as they are). */
static void expect_source_rule(const roz_input_rule_t *bad)
{
    roz_manifest_problem_t p;
    roz_input_rule_t list[N_INS];
    roz_manifest_t m = man;
    memcpy(list, rules, sizeof list);
    list[1] = *bad;
    m.input_rules = list;
    assert_int_equal(roz_manifest_validate(&m, &p), ROZ_EINVAL);
    assert_int_equal(p.rule, ROZ_MANIFEST_RULE_SOURCE);
    assert_int_equal(p.is_state, 2);
    assert_int_equal(p.index, 1);
}

static void test_manifest_rule(void **st)
{
    roz_manifest_problem_t p;
    roz_input_rule_t c;
    (void)st;
    assert_int_equal(roz_manifest_validate(&man, &p), ROZ_OK);
    c = rules[1];
    c.scale = 0.0; /* it would never move */
    expect_source_rule(&c);
    c.scale = NAN;
    expect_source_rule(&c);
    c.scale = INFINITY;
    expect_source_rule(&c);
    c = rules[1];
    c.source = ROZ_OPERATOR_FIELD_COUNT_; /* outside the vocabulary */
    expect_source_rule(&c);
    c = rules[4];
    c.scale = 2.0; /* a scale without a source */
    expect_source_rule(&c);
    c = rules[1];
    c.source = ROZ_OPERATOR_REMOTE_LY; /* input 0's: one field, one input */
    expect_source_rule(&c);
}

static void test_remote_frame_scaled(void **st)
{
    roz_operator_remote_t r = { .lx = 0.4f, .ly = 0.5f, .rx = -1.0f,
                                .buttons = ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_A) };
    (void)st;
    assert_int_equal(roz_inputs_remote(&ib.in, &r), ROZ_OK);
    step();
    assert_true(ib.out[0] == 0.8 * (double)0.5f);
    assert_true(ib.out[1] == -0.5 * (double)0.4f);
    assert_true(ib.out[2] == 1.0);
    assert_true(ib.out[3] == 0.0); /* a twist's: untouched */
    assert_true(ib.out[4] == 1.0); /* no source: its default */
    r.ly = 1.0f; /* beyond max_cmd after the scale: 0.8, no clamp */
    r.buttons = 0;
    assert_int_equal(roz_inputs_remote(&ib.in, &r), ROZ_OK);
    step();
    assert_true(ib.out[0] == 0.8);
    assert_true(ib.out[2] == 0.0);
    assert_int_equal(ib.in.counters.clamped, 0);
}

static void test_nan_refused_and_counted(void **st)
{
    roz_operator_remote_t r = { .lx = 0.4f, .ly = 0.5f };
    (void)st;
    assert_int_equal(roz_inputs_remote(&ib.in, &r), ROZ_OK);
    step();
    r.ly = NAN;
    r.lx = INFINITY;
    assert_int_equal(roz_inputs_remote(&ib.in, &r), ROZ_OK);
    step();
    assert_true(ib.out[0] == 0.8 * (double)0.5f); /* each keeps its value */
    assert_true(ib.out[1] == -0.5 * (double)0.4f);
    assert_int_equal(ib.in.counters.nonfinite, 2);
}

static void test_twist_frame(void **st)
{
    roz_operator_twist_t t = { .linear = { 9.0, 9.0, 9.0 }, .angular = { 0.0, 0.0, -0.75 } };
    (void)st;
    assert_int_equal(roz_inputs_twist(&ib.in, &t), ROZ_OK);
    step();
    assert_true(ib.out[3] == -0.75);
    /* the remote's: untouched */
    assert_true(ib.out[0] == 0.0 && ib.out[1] == 0.0 && ib.out[2] == 0.0);
    assert_int_equal(ib.in.counters.clamped, 0);
}

/* A silent remote: its inputs go stale and return to their defaults. */
static void test_silent_remote_goes_stale(void **st)
{
    roz_operator_remote_t r = { .ly = 0.5f };
    (void)st;
    assert_int_equal(roz_inputs_remote(&ib.in, &r), ROZ_OK);
    for (int i = 0; i < 60; i++) /* 100 ms: 50 ticks */
        step();
    assert_true(ib.out[0] == 0.0);
    assert_true(ib.in.counters.stale >= 1);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_vocabulary),
              cmocka_unit_test(test_manifest_rule),
              cmocka_unit_test_setup(test_remote_frame_scaled, setup),
              cmocka_unit_test_setup(test_nan_refused_and_counted, setup),
              cmocka_unit_test_setup(test_twist_frame, setup),
              cmocka_unit_test_setup(test_silent_remote_goes_stale, setup))
