/* SPDX-License-Identifier: Apache-2.0 */
/* A Linux gamepad as the operator's remote (roz/gamepad.h), without a
 * device: struct input_event records as the kernel sends them (an Xbox-like
 * pad's absinfo: sticks -32768..32767 with a flat of 128, triggers
 * 0..1023), fed to the decoder, then through a pipe to the reader thread,
 * whose frames reach operator inputs while the tick takes them (TSan). */
#define _DEFAULT_SOURCE /* usleep */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/gamepad.h"
#include "roz/inputs.h"
#include "support.h"
#include "support_inputs.h"

static const struct input_absinfo xbox[ROZ_GAMEPAD_AXES] = {
    { .minimum = -32768, .maximum = 32767, .flat = 128 },
    { .minimum = -32768, .maximum = 32767, .flat = 128 },
    { .minimum = -32768, .maximum = 32767, .flat = 128 },
    { .minimum = -32768, .maximum = 32767, .flat = 128 },
    { .minimum = 0, .maximum = 1023 },
    { .minimum = 0, .maximum = 1023 },
};

static roz_gamepad_t gp;

static int ev(uint16_t type, uint16_t code, int32_t value)
{
    struct input_event e;
    memset(&e, 0, sizeof e);
    e.type = type;
    e.code = code;
    e.value = value;
    return roz_gamepad_event(&gp, &e);
}

static int syn(void)
{
    return ev(EV_SYN, SYN_REPORT, 0);
}

static uint16_t k(roz_operator_field_t f)
{
    return ROZ_REMOTE_KEY(f);
}

static void test_standard_codes(void **st)
{
    (void)st;
    roz_gamepad_init(&gp, xbox);
    assert_int_equal(ev(EV_ABS, ABS_X, 32767), 0);
    assert_int_equal(ev(EV_ABS, ABS_Y, -32768), 0); /* pushed up */
    assert_int_equal(ev(EV_ABS, ABS_RX, -32768), 0);
    assert_int_equal(ev(EV_ABS, ABS_RY, 16384), 0); /* half down */
    assert_int_equal(ev(EV_ABS, ABS_Z, 1023), 0);
    assert_int_equal(ev(EV_ABS, ABS_RZ, 256), 0);
    assert_int_equal(ev(EV_KEY, BTN_SOUTH, 1), 0);
    assert_int_equal(ev(EV_KEY, BTN_EAST, 1), 0);
    assert_int_equal(ev(EV_KEY, BTN_TL, 1), 0);
    assert_int_equal(ev(EV_KEY, BTN_SELECT, 1), 0);
    assert_int_equal(ev(EV_ABS, ABS_HAT0Y, -1), 0);
    assert_int_equal(gp.have_frame, 0); /* nothing before SYN_REPORT */
    assert_int_equal(syn(), 1);
    assert_true(gp.frame.lx == 1.0f);
    assert_true(gp.frame.ly == 1.0f); /* up is positive, as on the remote */
    assert_true(gp.frame.rx == -1.0f);
    assert_true(fabsf(gp.frame.ry + 0.5f) < 1e-4f);
    assert_true(gp.frame.l2 == 1.0f);
    assert_true(fabsf(gp.frame.r2 - 0.25f) < 1e-3f);
    /* the L2 trigger past half travel is the L2 button too; R2 is not */
    assert_int_equal(gp.frame.buttons,
                     k(ROZ_OPERATOR_REMOTE_BTN_A) | k(ROZ_OPERATOR_REMOTE_BTN_B) |
                         k(ROZ_OPERATOR_REMOTE_BTN_L1) | k(ROZ_OPERATOR_REMOTE_BTN_SELECT) |
                         k(ROZ_OPERATOR_REMOTE_BTN_L2) | k(ROZ_OPERATOR_REMOTE_BTN_UP));
    /* by position: north is Y, west is X; the d-pad buttons and the hat */
    ev(EV_KEY, BTN_SOUTH, 0);
    ev(EV_KEY, BTN_EAST, 0);
    ev(EV_KEY, BTN_TL, 0);
    ev(EV_KEY, BTN_SELECT, 0);
    ev(EV_ABS, ABS_Z, 0);
    ev(EV_ABS, ABS_HAT0Y, 0);
    ev(EV_ABS, ABS_HAT0X, 1);
    ev(EV_KEY, BTN_NORTH, 1);
    ev(EV_KEY, BTN_WEST, 1);
    ev(EV_KEY, BTN_START, 2); /* autorepeat: held */
    ev(EV_KEY, BTN_TR2, 1);
    ev(EV_KEY, BTN_DPAD_DOWN, 1);
    ev(EV_KEY, BTN_THUMBR, 1);
    assert_int_equal(syn(), 1);
    assert_int_equal(gp.frame.buttons,
                     k(ROZ_OPERATOR_REMOTE_BTN_Y) | k(ROZ_OPERATOR_REMOTE_BTN_X) |
                         k(ROZ_OPERATOR_REMOTE_BTN_START) | k(ROZ_OPERATOR_REMOTE_BTN_R2) |
                         k(ROZ_OPERATOR_REMOTE_BTN_DOWN) | k(ROZ_OPERATOR_REMOTE_BTN_RIGHT) |
                         k(ROZ_OPERATOR_REMOTE_BTN_F2));
    assert_true(gp.frame.l2 == 0.0f);
}

static void test_flat_and_absent_axes(void **st)
{
    struct input_absinfo no_right[ROZ_GAMEPAD_AXES];
    (void)st;
    memcpy(no_right, xbox, sizeof no_right);
    memset(&no_right[2], 0, sizeof no_right[2]); /* no ABS_RX */
    roz_gamepad_init(&gp, no_right);
    ev(EV_ABS, ABS_X, 100); /* within the flat of the middle */
    ev(EV_ABS, ABS_Y, -129 - 1);
    ev(EV_ABS, ABS_RX, 32767); /* an axis the device does not have */
    assert_int_equal(syn(), 1);
    assert_true(gp.frame.lx == 0.0f);
    assert_true(gp.frame.ly > 0.0f && gp.frame.ly < 0.01f); /* just past the flat */
    assert_true(gp.frame.rx == 0.0f);
    assert_true(gp.frame.l2 == 0.0f && gp.frame.r2 == 0.0f); /* at rest */
}

/* After SYN_DROPPED, the events up to SYN_REPORT are not trusted; a pipe
 * cannot be asked for the state: every control released and centred. */
static void test_syn_dropped(void **st)
{
    (void)st;
    roz_gamepad_init(&gp, xbox);
    ev(EV_ABS, ABS_Y, -32768);
    ev(EV_KEY, BTN_SOUTH, 1);
    assert_int_equal(syn(), 1);
    assert_true(gp.frame.ly == 1.0f);
    assert_int_equal(ev(EV_SYN, SYN_DROPPED, 0), 0);
    ev(EV_ABS, ABS_X, 32767); /* half a report: discarded */
    assert_int_equal(syn(), 1);
    assert_true(gp.frame.lx == 0.0f && gp.frame.ly == 0.0f);
    assert_int_equal(gp.frame.buttons, 0);
    assert_int_equal(atomic_load(&gp.drops), 1);
}

/* ---- the reader thread, through a pipe, into operator inputs ------------ */

static const roz_channel_t cmds[] = {
    ROZ_TEST_WHEEL_VELOCITY,
};
static const roz_channel_t ins[] = {
    { .name = "operator/velocity.x", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -0.8,
      .max = 0.8, .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/walk", .type = ROZ_IF_POSITION, .unit = "", .min = 0.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_input_rule_t rules[] = {
    { .stale_after_ms = 100, .source = ROZ_OPERATOR_REMOTE_LY, .scale = 0.8 },
    { .stale_after_ms = 100, .source = ROZ_OPERATOR_REMOTE_BTN_A, .scale = 1.0 },
};
static const roz_manifest_t man = { "pad_bot", "generic", 500, cmds, 1, NULL, 0, NULL, ins, 2, 0, NULL,
                                    rules };
static roz_inputs_t in;

static int to_inputs(void *ctx, const roz_operator_remote_t *r)
{
    return roz_inputs_remote(ctx, r);
}

static void put(int fd, uint16_t type, uint16_t code, int32_t value)
{
    struct input_event e;
    memset(&e, 0, sizeof e);
    e.type = type;
    e.code = code;
    e.value = value;
    assert_int_equal(write(fd, &e, sizeof e), (ssize_t)sizeof e);
}

/* Until @p cond, ticking the inputs (the tick's thread against the reader);
 * a hang guard of 60 s, never a time asserted. */
#define TICK_UNTIL(cond)                                                                  \
    ROZ_TEST_WAIT(cond, (roz_inputs_tick(&in, ++tick * 2000000ull, out), usleep(1000)), 60000)

static void test_reader_through_a_pipe(void **st)
{
    int p[2];
    double out[2] = { 0.0, 0.0 };
    uint64_t tick = 0;
    char err[128];
    roz_operator_sink_t sink = { to_inputs, NULL, &in };
    (void)st;
    roz_inputs_init(&in, &man);
    assert_int_equal(pipe(p), 0);
    roz_gamepad_open_fd(&gp, p[0], xbox);
    assert_int_equal(roz_gamepad_start(&gp, &sink, err, sizeof err), 0);
    put(p[1], EV_ABS, ABS_Y, -32768); /* full forward */
    put(p[1], EV_KEY, BTN_SOUTH, 1);
    put(p[1], EV_SYN, SYN_REPORT, 0);
    TICK_UNTIL(out[0] == 0.8 && out[1] == 1.0);
    /* held still, the device quiet: the frame is handed on again (what
     * keeps the inputs, stale after 100 ms of ticks, where the stick is) */
    uint64_t repeats = atomic_load(&gp.repeats);
    TICK_UNTIL(atomic_load(&gp.repeats) >= repeats + 3);
    assert_int_equal(atomic_load(&gp.frames), 1); /* one report, handed on again */
    /* the device goes away: no more frames, the inputs go back to rest */
    close(p[1]);
    TICK_UNTIL(atomic_load(&gp.gone) != 0);
    assert_int_equal(atomic_load(&gp.gone), -1); /* end of file */
    TICK_UNTIL(out[0] == 0.0 && out[1] == 0.0);
    roz_gamepad_close(&gp);
    roz_gamepad_close(&gp); /* idempotent */
    assert_int_equal(in.counters.nonfinite + in.counters.clamped, 0);
}

static void test_open_refuses_what_is_no_gamepad(void **st)
{
    char err[256];
    (void)st;
    assert_int_equal(roz_gamepad_open(&gp, "/nonexistent/event99", err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent/event99"));
    assert_int_equal(roz_gamepad_open(&gp, "/dev/null", err, sizeof err), -1);
    assert_non_null(strstr(err, "not an evdev input device"));
}

ROZ_TEST_MAIN(cmocka_unit_test(test_standard_codes),
              cmocka_unit_test(test_flat_and_absent_axes),
              cmocka_unit_test(test_syn_dropped),
              cmocka_unit_test(test_reader_through_a_pipe),
              cmocka_unit_test(test_open_refuses_what_is_no_gamepad))
