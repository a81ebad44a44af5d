/* SPDX-License-Identifier: Apache-2.0 */
/* The manifest model: interface names, look-up by name, validation rules,
 * the generic velocity manifest. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/manifest.h"
#include "support.h"

/* A channel holds no padding but its tail (a firmware's tables hold one
 * per channel): five doubles, two pointers, the type, a 16-bit pairing
 * and a byte, rounded up to the doubles' alignment. */
_Static_assert(sizeof(roz_channel_t) ==
                   (5 * sizeof(double) + 2 * sizeof(const char *) + sizeof(roz_interface_t) +
                    sizeof(int16_t) + sizeof(uint8_t) + _Alignof(roz_channel_t) - 1) /
                       _Alignof(roz_channel_t) * _Alignof(roz_channel_t),
               "roz_channel_t holds padding between its fields");

/* ---- a small valid manifest to break one rule at a time ----------------- */

static roz_channel_t cmds[2];
static roz_channel_t states[3];
static roz_manifest_t m;

static int setup_manifest(void **state)
{
    (void)state;
    cmds[0] = (roz_channel_t){ .name = "joint1/velocity", .type = ROZ_IF_VELOCITY,
                               .unit = "rad/s", .min = -2.0, .max = 2.0, .default_value = 0.0, .max_rate = 0.2,
                               .position_state = 0 };
    cmds[1] = (roz_channel_t){ .name = "joint2/velocity", .type = ROZ_IF_VELOCITY,
                               .unit = "rad/s", .min = -2.0, .max = 2.0, .default_value = 0.0, .max_rate = 0.2,
                               .position_state = 1 };
    states[0] = (roz_channel_t){ .name = "joint1/position", .type = ROZ_IF_POSITION,
                                 .unit = "rad", .min = -3.14, .max = 3.14, .default_value = 0.0, .max_rate = 0.0,
                                 .position_state = ROZ_CHANNEL_UNPAIRED };
    states[1] = (roz_channel_t){ .name = "joint2/position", .type = ROZ_IF_POSITION,
                                 .unit = "rad", .min = -3.14, .max = 3.14, .default_value = 0.0, .max_rate = 0.0,
                                 .position_state = ROZ_CHANNEL_UNPAIRED };
    states[2] = (roz_channel_t){ .name = "joint1/velocity", .type = ROZ_IF_VELOCITY,
                                 .unit = "rad/s", .min = -2.0, .max = 2.0, .default_value = 0.0, .max_rate = 0.0,
                                 .position_state = ROZ_CHANNEL_UNPAIRED };
    m = (roz_manifest_t){ "my_arm", "manipulator", 100, cmds, 2, states, 3, NULL, NULL, 0, 0, NULL, NULL };
    return 0;
}

static void test_manifest_interface_names(void **state)
{
    static const char *const names[] = { "position", "velocity", "effort", "stiffness",
                                         "damping", "acceleration", "orientation" };
    (void)state;
    assert_int_equal(sizeof names / sizeof names[0], ROZ_IF_COUNT_);
    for (int i = 0; i < (int)ROZ_IF_COUNT_; i++) {
        roz_interface_t t = ROZ_IF_COUNT_;
        assert_string_equal(roz_interface_name((roz_interface_t)i), names[i]);
        assert_int_equal(roz_interface_parse(names[i], &t), ROZ_OK);
        assert_int_equal(t, i);
    }
    roz_interface_t t = ROZ_IF_POSITION;
    assert_int_equal(roz_interface_parse("Velocity", &t), ROZ_EINVAL);
    assert_int_equal(roz_interface_parse("speed", &t), ROZ_EINVAL);
    assert_int_equal(roz_interface_parse(NULL, &t), ROZ_EINVAL);
    assert_int_equal(roz_interface_parse("velocity", NULL), ROZ_EINVAL);
    assert_string_equal(roz_interface_name(ROZ_IF_COUNT_), "?");
    assert_string_equal(roz_interface_name((roz_interface_t)-1), "?");
}

static void test_manifest_find(void **state)
{
    (void)state;
    assert_int_equal(roz_manifest_find_command(&m, "joint1/velocity"), 0);
    assert_int_equal(roz_manifest_find_command(&m, "joint2/velocity"), 1);
    assert_int_equal(roz_manifest_find_command(&m, "joint3/velocity"), ROZ_ENOENT);
    assert_int_equal(roz_manifest_find_command(&m, "joint1/position"), ROZ_ENOENT);
    /* same name in both lists: each look-up searches its own list */
    assert_int_equal(roz_manifest_find_state(&m, "joint1/velocity"), 2);
    assert_int_equal(roz_manifest_find_state(&m, "joint2/position"), 1);
    assert_int_equal(roz_manifest_find_state(&m, ""), ROZ_ENOENT);
    assert_int_equal(roz_manifest_find_command(NULL, "x"), ROZ_EINVAL);
    assert_int_equal(roz_manifest_find_command(&m, NULL), ROZ_EINVAL);
    m.n_states = 0;
    m.states = NULL;
    assert_int_equal(roz_manifest_find_state(&m, "joint1/position"), ROZ_EINVAL);
}

/* One row per rule: what to break, and what validate must say. */
typedef struct {
    const char         *what;
    void              (*breakit)(void);
    roz_manifest_rule_t rule;
    int                 is_state;
    int32_t             index;
} rule_case_t;

static void b_id_upper(void) { m.robot_id = "My_arm"; }
static void b_id_null(void) { m.robot_id = NULL; }
static void b_id_digit(void) { m.robot_id = "1arm"; }
static void b_rate(void) { m.control_rate_hz = 0; }
static void b_no_commands(void) { m.n_commands = 0; }
static void b_too_many(void) { m.n_commands = ROZ_CFG_MAX_COMMANDS + 1; }
static void b_name_empty(void) { cmds[1].name = ""; }
static void b_name_null(void) { states[0].name = NULL; }
static void b_dup(void) { cmds[1].name = "joint1/velocity"; }
static void b_type(void) { cmds[0].type = ROZ_IF_COUNT_; }
static void b_limits_order(void) { cmds[1].min = 2.0; cmds[1].max = -2.0; }
static void b_limits_equal(void) { cmds[1].min = 2.0; cmds[1].default_value = 2.0; }
static void b_limits_nan(void) { cmds[0].max = NAN; }
static void b_limits_inf(void) { states[1].min = -INFINITY; }
static void b_default_out(void) { cmds[0].default_value = 2.5; }
static void b_default_nan(void) { cmds[0].default_value = NAN; }
static void b_rate_neg(void) { cmds[0].max_rate = -0.1; }
static void b_rate_inf(void) { cmds[1].max_rate = INFINITY; }
static void b_pair_range(void) { cmds[1].position_state = 3; }
static void b_pair_neg(void) { cmds[1].position_state = -2; }
static void b_pair_type(void) { cmds[0].position_state = 2; }
static void b_pair_on_state(void) { states[2].position_state = 0; }
static void b_pair_no_zero(void) { cmds[1].min = 0.5; cmds[1].default_value = 1.0; }
static void b_pair_effort_no_zero(void)
{
    cmds[1].type = ROZ_IF_EFFORT;
    cmds[1].max = -0.5;
    cmds[1].default_value = -1.0;
}
/* a position command may be paired whatever its limits: it holds the state */
static void b_pair_position_no_zero(void)
{
    cmds[1].type = ROZ_IF_POSITION;
    cmds[1].min = 0.5;
    cmds[1].default_value = 1.0;
}
/* state 0's limits are [-3.14, 3.14]: a margin must be below 3.14 */
static void b_margin_neg(void) { states[0].limit_margin = -0.01; }
static void b_margin_nan(void) { states[0].limit_margin = NAN; }
static void b_margin_inf(void) { states[1].limit_margin = INFINITY; }
static void b_margin_half(void) { states[1].limit_margin = 3.14; }
static void b_margin_more(void) { states[1].limit_margin = 5.0; }
static void b_margin_huge(void) { states[1].limit_margin = 1e308; }
static void b_margin_command(void) { cmds[0].limit_margin = 0.01; }
static void b_margin_vel_state(void) { states[2].limit_margin = 0.01; }
/* a hold latches a setpoint: only a paired position command has one */
static void b_hold_velocity(void) { cmds[0].safe_default = ROZ_SAFE_HOLD; }
static void b_hold_state(void) { states[0].safe_default = ROZ_SAFE_HOLD; }
static void b_hold_unknown(void) { cmds[1].safe_default = (roz_safe_default_t)7; }
static void b_hold_unpaired(void)
{
    cmds[1].type = ROZ_IF_POSITION;
    cmds[1].position_state = ROZ_CHANNEL_UNPAIRED;
    cmds[1].safe_default = ROZ_SAFE_HOLD;
}

static const rule_case_t rule_cases[] = {
    { "robot_id upper case", b_id_upper, ROZ_MANIFEST_RULE_ID, 0, -1 },
    { "robot_id NULL", b_id_null, ROZ_MANIFEST_RULE_ID, 0, -1 },
    { "robot_id leading digit", b_id_digit, ROZ_MANIFEST_RULE_ID, 0, -1 },
    { "control_rate_hz 0", b_rate, ROZ_MANIFEST_RULE_RATE, 0, -1 },
    { "no commands", b_no_commands, ROZ_MANIFEST_RULE_COUNT, 0, -1 },
    { "too many commands", b_too_many, ROZ_MANIFEST_RULE_COUNT, 0, -1 },
    { "empty name", b_name_empty, ROZ_MANIFEST_RULE_NAME, 0, 1 },
    { "NULL state name", b_name_null, ROZ_MANIFEST_RULE_NAME, 1, 0 },
    { "duplicate name", b_dup, ROZ_MANIFEST_RULE_DUPLICATE, 0, 1 },
    { "unknown type", b_type, ROZ_MANIFEST_RULE_TYPE, 0, 0 },
    { "min above max", b_limits_order, ROZ_MANIFEST_RULE_LIMITS, 0, 1 },
    { "min equals max", b_limits_equal, ROZ_MANIFEST_RULE_LIMITS, 0, 1 },
    { "NaN limit", b_limits_nan, ROZ_MANIFEST_RULE_LIMITS, 0, 0 },
    { "infinite state limit", b_limits_inf, ROZ_MANIFEST_RULE_LIMITS, 1, 1 },
    { "default outside", b_default_out, ROZ_MANIFEST_RULE_DEFAULT, 0, 0 },
    { "default NaN", b_default_nan, ROZ_MANIFEST_RULE_DEFAULT, 0, 0 },
    { "negative max_rate", b_rate_neg, ROZ_MANIFEST_RULE_MAX_RATE, 0, 0 },
    { "infinite max_rate", b_rate_inf, ROZ_MANIFEST_RULE_MAX_RATE, 0, 1 },
    { "pairing out of range", b_pair_range, ROZ_MANIFEST_RULE_PAIRING, 0, 1 },
    { "pairing negative", b_pair_neg, ROZ_MANIFEST_RULE_PAIRING, 0, 1 },
    { "pairing to velocity state", b_pair_type, ROZ_MANIFEST_RULE_PAIRING, 0, 0 },
    { "pairing on a state", b_pair_on_state, ROZ_MANIFEST_RULE_PAIRING, 1, 2 },
    { "paired velocity excluding 0", b_pair_no_zero, ROZ_MANIFEST_RULE_PAIRING, 0, 1 },
    { "paired effort excluding 0", b_pair_effort_no_zero, ROZ_MANIFEST_RULE_PAIRING, 0, 1 },
    { "negative margin", b_margin_neg, ROZ_MANIFEST_RULE_MARGIN, 1, 0 },
    { "NaN margin", b_margin_nan, ROZ_MANIFEST_RULE_MARGIN, 1, 0 },
    { "infinite margin", b_margin_inf, ROZ_MANIFEST_RULE_MARGIN, 1, 1 },
    { "margin of half the range", b_margin_half, ROZ_MANIFEST_RULE_MARGIN, 1, 1 },
    { "margin wider than the range", b_margin_more, ROZ_MANIFEST_RULE_MARGIN, 1, 1 },
    { "margin whose double overflows", b_margin_huge, ROZ_MANIFEST_RULE_MARGIN, 1, 1 },
    { "margin on a command", b_margin_command, ROZ_MANIFEST_RULE_MARGIN, 0, 0 },
    { "margin on a velocity state", b_margin_vel_state, ROZ_MANIFEST_RULE_MARGIN, 1, 2 },
    { "hold on a velocity command", b_hold_velocity, ROZ_MANIFEST_RULE_SAFE_DEFAULT, 0, 0 },
    { "hold on a state", b_hold_state, ROZ_MANIFEST_RULE_SAFE_DEFAULT, 1, 0 },
    { "safe_default not a kind", b_hold_unknown, ROZ_MANIFEST_RULE_SAFE_DEFAULT, 0, 1 },
    { "hold on an unpaired position", b_hold_unpaired, ROZ_MANIFEST_RULE_SAFE_DEFAULT, 0, 1 },
};

/* 0 is the default: the smaller of 0.05 and 5 % of the range; a margin
 * leaving any room at all is the state's own. */
static void test_manifest_limit_margin(void **state)
{
    roz_channel_t gripper = { .name = "gripper/position", .type = ROZ_IF_POSITION, .unit = "m",
                              .min = 0.0, .max = 0.08, .default_value = 0.04, .max_rate = 0.0,
                              .position_state = ROZ_CHANNEL_UNPAIRED };
    (void)state;
    assert_true(roz_manifest_limit_margin(&states[0]) == 0.05);      /* [-3.14, 3.14] rad */
    assert_true(roz_manifest_limit_margin(&gripper) == 0.05 * 0.08); /* [0, 0.08] m */
    assert_true(roz_manifest_limit_margin(&gripper) < 0.0041);
    gripper.max = 2.0; /* 5 % of 2 is 0.1: the 0.05 cap applies */
    assert_true(roz_manifest_limit_margin(&gripper) == 0.05);
    gripper.max = 0.08;
    gripper.limit_margin = 0.002;
    assert_true(roz_manifest_limit_margin(&gripper) == 0.002);

    m.states = &gripper;
    m.n_states = 1;
    cmds[0].position_state = 0;
    cmds[1].position_state = ROZ_CHANNEL_UNPAIRED;
    gripper.limit_margin = 0.0399; /* 0.2 mm of room */
    assert_int_equal(roz_manifest_validate(&m, NULL), ROZ_OK);
    gripper.limit_margin = 0.04;   /* none */
    assert_int_equal(roz_manifest_validate(&m, NULL), ROZ_EINVAL);
    gripper.limit_margin = -0.0;   /* -0 is 0: the default */
    assert_int_equal(roz_manifest_validate(&m, NULL), ROZ_OK);
    assert_true(roz_manifest_limit_margin(&gripper) == 0.05 * 0.08);
}

static void test_manifest_validate_rules(void **state)
{
    roz_manifest_problem_t p;

    assert_int_equal(roz_manifest_validate(&m, &p), ROZ_OK);
    assert_int_equal(p.rule, ROZ_MANIFEST_RULE_OK);
    assert_int_equal(roz_manifest_validate(&m, NULL), ROZ_OK);
    for (size_t i = 0; i < sizeof rule_cases / sizeof rule_cases[0]; i++) {
        const rule_case_t *c = &rule_cases[i];
        setup_manifest(state);
        c->breakit();
        memset(&p, 0xff, sizeof p);
        print_message("rule case: %s\n", c->what);
        assert_int_equal(roz_manifest_validate(&m, &p), ROZ_EINVAL);
        assert_int_equal(p.rule, c->rule);
        assert_int_equal(p.is_state, c->is_state);
        assert_int_equal(p.index, c->index);
    }
    setup_manifest(state);
    b_pair_position_no_zero();
    assert_int_equal(roz_manifest_validate(&m, NULL), ROZ_OK);
    cmds[1].safe_default = ROZ_SAFE_HOLD; /* a paired position command may hold */
    assert_int_equal(roz_manifest_validate(&m, NULL), ROZ_OK);
    setup_manifest(state);
}

static roz_manifest_storage_t storage;

static void test_manifest_generic_velocity(void **state)
{
    (void)state;
    assert_int_equal(roz_manifest_generic_velocity(12, 1.5, &storage), ROZ_OK);
    const roz_manifest_t *g = &storage.manifest;
    assert_int_equal(roz_manifest_validate(g, NULL), ROZ_OK);
    assert_string_equal(g->robot_class, "generic");
    assert_int_equal(g->control_rate_hz, 100);
    assert_int_equal(g->n_commands, 12);
    assert_int_equal(g->n_states, 0);
    assert_null(g->hardware);
    assert_string_equal(g->commands[0].name, "joint0/velocity");
    assert_string_equal(g->commands[11].name, "joint11/velocity");
    for (int i = 0; i < 12; i++) {
        const roz_channel_t *c = &g->commands[i];
        assert_int_equal(c->type, ROZ_IF_VELOCITY);
        assert_string_equal(c->unit, "rad/s");
        assert_true(c->min == -1.5 && c->max == 1.5);
        assert_true(c->default_value == 0.0 && c->max_rate == 0.0);
        assert_int_equal(c->position_state, ROZ_CHANNEL_UNPAIRED);
        assert_true(c->limit_margin == 0.0);
    }
    assert_int_equal(roz_manifest_find_command(g, "joint7/velocity"), 7);

    /* the largest n fits the default arena, and names stay distinct */
    assert_int_equal(roz_manifest_generic_velocity(ROZ_CFG_MAX_COMMANDS, 3.0, &storage), ROZ_OK);
    assert_int_equal(roz_manifest_validate(&storage.manifest, NULL), ROZ_OK);
    assert_int_equal(roz_manifest_find_command(&storage.manifest, "joint255/velocity"), 255);

    assert_int_equal(roz_manifest_generic_velocity(0, 1.0, &storage), ROZ_EINVAL);
    assert_int_equal(roz_manifest_generic_velocity(ROZ_CFG_MAX_COMMANDS + 1, 1.0, &storage),
                     ROZ_EINVAL);
    assert_int_equal(roz_manifest_generic_velocity(3, 0.0, &storage), ROZ_EINVAL);
    assert_int_equal(roz_manifest_generic_velocity(3, -1.0, &storage), ROZ_EINVAL);
    assert_int_equal(roz_manifest_generic_velocity(3, NAN, &storage), ROZ_EINVAL);
    assert_int_equal(roz_manifest_generic_velocity(3, INFINITY, &storage), ROZ_EINVAL);
    assert_int_equal(roz_manifest_generic_velocity(3, 1.0, NULL), ROZ_EINVAL);
}

static void test_manifest_strerror(void **state)
{
    (void)state;
    assert_string_equal(roz_strerror(ROZ_OK), "success");
    assert_string_equal(roz_strerror(ROZ_ENOENT), "no such entry");
    assert_string_equal(roz_strerror(ROZ_ELINK), "the robot restarted or came back after it was lost");
    assert_string_equal(roz_strerror(-1000), "unknown error");
}

ROZ_TEST_MAIN(cmocka_unit_test(test_manifest_interface_names),
              cmocka_unit_test_setup(test_manifest_find, setup_manifest),
              cmocka_unit_test_setup(test_manifest_validate_rules, setup_manifest),
              cmocka_unit_test_setup(test_manifest_limit_margin, setup_manifest),
              cmocka_unit_test(test_manifest_generic_velocity),
              cmocka_unit_test(test_manifest_strerror))
