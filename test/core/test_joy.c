/* SPDX-License-Identifier: Apache-2.0 */
/* The Joy rule (roz/joy.h), in the core alone (this test links no port, no
 * DDS): a map's grammar and its errors, naming where the map came from; a
 * Joy's axes and buttons as the remote's fields; a Joy through the rule
 * reaching the inputs whose source is the remote, as rozrun --teleop and
 * the ROS 2 ports' /joy hand it. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/joy.h"
#include "support_inputs.h"

/* a browser's standard gamepad as Foxglove's Joystick panel sends it (every
 * axis negated): rozrun --teleop's map (tools/rozrun/teleop.h) */
#define PANEL_MAP                                                                             \
    "lx=-a0 ly=a1 rx=-a2 ry=a3 l2=b6 r2=b7 btn.r1=b5 btn.l1=b4 btn.start=b9 btn.select=b8 "   \
    "btn.r2=b7 btn.l2=b6 btn.a=b0 btn.b=b1 btn.x=b2 btn.y=b3 btn.up=b12 btn.right=b15 "        \
    "btn.down=b13 btn.left=b14"

static void test_joy_map_and_frame(void **st)
{
    roz_joy_map_t map;
    roz_operator_remote_t r;
    char err[300] = "";
    float axes[4] = { 0.5f, 0.25f, -1.0f, 1.0f };
    int32_t buttons[17] = { 0 };
    (void)st;
    assert_int_equal(roz_joy_map_parse("panel", PANEL_MAP, &map, err, sizeof err), ROZ_OK);
    buttons[0] = 1;  /* A */
    buttons[6] = 1;  /* the left trigger */
    buttons[15] = 1; /* D-pad right */
    assert_int_equal(roz_joy_remote(&map, axes, 4, buttons, 17, &r), ROZ_OK);
    assert_true(r.lx == -0.5f && r.ly == 0.25f && r.rx == 1.0f && r.ry == 1.0f);
    assert_true(r.l2 == 1.0f && r.r2 == 0.0f);
    assert_int_equal(r.buttons, ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_A) |
                                    ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_L2) |
                                    ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_RIGHT));
    /* a keyboard's two axes: the map names four */
    assert_int_equal(roz_joy_remote(&map, axes, 2, buttons, 17, &r), ROZ_ERANGE);
    assert_int_equal(roz_joy_remote(&map, axes, 4, buttons, 15, &r), ROZ_ERANGE);
    axes[2] = NAN;
    assert_int_equal(roz_joy_remote(&map, axes, 4, buttons, 17, &r), ROZ_EINVAL);
    /* an axis above half way presses a button mapped to it */
    assert_int_equal(roz_joy_map_parse("panel", "btn.x=-a1 btn.y=a1", &map, err, sizeof err),
                     ROZ_OK);
    axes[1] = -0.75f;
    assert_int_equal(roz_joy_remote(&map, axes, 2, buttons, 0, &r), ROZ_OK);
    assert_int_equal(r.buttons, ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_X));
    /* more than ROZ_JOY_MAX axes or buttons: refused whole, whatever the
     * map names, nothing set */
    static float many_axes[ROZ_JOY_MAX + 1];
    static int32_t many_buttons[ROZ_JOY_MAX + 1];
    many_axes[1] = -0.75f;
    assert_int_equal(roz_joy_remote(&map, many_axes, ROZ_JOY_MAX, many_buttons, ROZ_JOY_MAX, &r),
                     ROZ_OK);
    assert_int_equal(r.buttons, ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_X));
    assert_int_equal(
        roz_joy_remote(&map, many_axes, ROZ_JOY_MAX + 1, many_buttons, ROZ_JOY_MAX, &r),
        ROZ_ENOSPC);
    assert_int_equal(r.buttons, 0);
    assert_int_equal(
        roz_joy_remote(&map, many_axes, ROZ_JOY_MAX, many_buttons, ROZ_JOY_MAX + 1, &r),
        ROZ_ENOSPC);
}

static void test_joy_map_errors_name_the_map(void **st)
{
    roz_joy_map_t map;
    char err[300];
    (void)st;
    assert_int_equal(roz_joy_map_parse("the panel's map", "ly=a1 btn.q=b0", &map, err,
                                       sizeof err),
                     ROZ_EINVAL);
    assert_string_equal(err, "the panel's map = \"ly=a1 btn.q=b0\": \"btn.q=b0\": not a field of "
                             "the remote (lx, ly, rx, ry, l2, r2, btn.r1, btn.l1, btn.start, "
                             "btn.select, btn.r2, btn.l2, btn.f1, btn.f2, btn.a, btn.b, btn.x, "
                             "btn.y, btn.up, btn.right, btn.down, btn.left)");
    /* refused whole: nothing of it kept */
    assert_true(map.field[ROZ_OPERATOR_REMOTE_LY].kind == 0);
    assert_int_equal(roz_joy_map_parse("m", "lx=a32", &map, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "m = \"lx=a32\": \"lx=a32\": expected aN"));
    assert_int_equal(roz_joy_map_parse("m", NULL, &map, err, sizeof err), ROZ_EINVAL);
}

/* A Joy through the rule into the inputs: the remote's fields scaled, a
 * NaN-bearing Joy refused before it reaches them. */
static const roz_channel_t cmds[] = { ROZ_TEST_WHEEL_VELOCITY };
static const roz_channel_t ins[] = {
    { .name = "operator/velocity.x", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -0.5,
      .max = 0.5, .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/walk", .type = ROZ_IF_POSITION, .unit = "", .min = 0.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_input_rule_t rules[] = {
    { .stale_after_ms = 100, .source = ROZ_OPERATOR_REMOTE_LY, .scale = 0.5 },
    { .stale_after_ms = 100, .source = ROZ_OPERATOR_REMOTE_BTN_A, .scale = 1.0 },
};
static const roz_manifest_t man = { "joy_bot", "generic", ROZ_TEST_INPUTS_RATE_HZ, cmds, 1,
                                    NULL, 0, NULL, ins, 2, 0, NULL, rules };

static void test_joy_reaches_the_inputs(void **st)
{
    static roz_test_inputs_t ib;
    roz_joy_map_t map;
    roz_operator_remote_t r;
    char err[300];
    float axes[4] = { 0.0f, 0.5f, 0.0f, 0.0f };
    int32_t buttons[17] = { 1 };
    (void)st;
    roz_test_inputs_init(&ib, &man);
    assert_int_equal(roz_joy_map_parse("panel", PANEL_MAP, &map, err, sizeof err), ROZ_OK);
    assert_int_equal(roz_joy_remote(&map, axes, 4, buttons, 17, &r), ROZ_OK);
    assert_int_equal(roz_inputs_remote(&ib.in, &r), ROZ_OK);
    roz_test_inputs_step(&ib);
    assert_true(ib.out[0] == 0.25 && ib.out[1] == 1.0);
    axes[1] = NAN;
    buttons[0] = 0;
    assert_int_equal(roz_joy_remote(&map, axes, 4, buttons, 17, &r), ROZ_EINVAL);
    roz_test_inputs_step(&ib);
    assert_true(ib.out[0] == 0.25 && ib.out[1] == 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_joy_map_and_frame),
        cmocka_unit_test(test_joy_map_errors_name_the_map),
        cmocka_unit_test(test_joy_reaches_the_inputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
