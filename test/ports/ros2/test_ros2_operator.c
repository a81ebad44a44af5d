/* SPDX-License-Identifier: Apache-2.0 */
/* The ROS 2 bridge's operator topics: geometry_msgs/Twist on /cmd_vel and
 * sensor_msgs/Joy on /joy, published by the fake robot's operator (as a ROS
 * 2 teleop node and joy node put them on Cyclone DDS: rt/cmd_vel, rt/joy,
 * no type information, ROS 2's default QoS), reach a runtime's inputs
 * through roz_runtime_operator_twist() / _remote() and a controller sees
 * them; a non-finite value, a Joy that does not fit joy_map and one longer
 * than ROZ_ROS2_JOY_MAX are refused and counted; silence makes an input stale, back to
 * its default at its rate cap. The PM01's manifest (the X2's, built as
 * test_ros2_operator_x2) with its inputs replaced by the test's own (the
 * built-ins' are the walking command and four buttons, manifests/). The
 * runtime's time is its
 * ticks: nothing here depends on a clock. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "port_fixture.h"
#include "ros2_fixture.h"
#ifdef ROZ_TEST_OPERATOR_X2 /* the same cases on the X2 (test_ros2_operator_x2) */
#include "agibot_x2_manifest.h"
#define FIXTURE roz_fixture_agibot_x2
#define BASE_MANIFEST roz_manifest_agibot_x2
#else
#include "engineai_pm01_manifest.h"
#define FIXTURE roz_fixture_engineai_pm01
#define BASE_MANIFEST roz_manifest_engineai_pm01
#endif
#include "roz/runtime.h"
#include "support.h" /* assert_near */
#include "support_wat.h"

#define WAIT_MS 10000u
#define STALE_MS 100u /* k = 0: 50 ticks at 500 Hz */

/* ---- the manifest: the robot's and five inputs --------------------------------------- */

enum { VX = 0, YAW, LY, L2, BTN_A, N_IN };

static const roz_channel_t inputs[N_IN] = {
    { .name = "operator/velocity.x", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -0.4,
      .max = 0.4, .default_value = 0.0, .max_rate = 0.01,
      .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/yaw_rate", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -1.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/forward", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -1.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/trigger", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = 0.0,
      .max = 2.0, .default_value = 0.0, .max_rate = 2.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/a", .type = ROZ_IF_VELOCITY, .unit = "1", .min = 0.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 1.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_input_rule_t input_rules[N_IN] = {
    { .stale_after_ms = STALE_MS, .source = ROZ_OPERATOR_TWIST_LINEAR_X, .scale = 0.5 },
    { .stale_after_ms = 60000u, .source = ROZ_OPERATOR_TWIST_ANGULAR_Z, .scale = -1.0 },
    { .stale_after_ms = 60000u, .source = ROZ_OPERATOR_REMOTE_LY, .scale = 1.0 },
    { .stale_after_ms = 60000u, .source = ROZ_OPERATOR_REMOTE_L2, .scale = 2.0 },
    { .stale_after_ms = 60000u, .source = ROZ_OPERATOR_REMOTE_BTN_A, .scale = 1.0 },
};

static roz_manifest_t m_op;
static uint16_t n_states;

static const roz_manifest_t *with_inputs(uint16_t n)
{
    m_op = BASE_MANIFEST;
    m_op.inputs = inputs;
    m_op.input_rules = input_rules;
    m_op.n_inputs = n;
    m_op.fall = NULL; /* the fake robot's IMU pattern tilts past the fall rule: inputs here */
    n_states = m_op.n_states;
    assert_int_equal(roz_manifest_validate(&m_op, NULL), ROZ_OK);
    return &m_op;
}

/* ---- the runtime: a controller that copies input 0 into its target 0 ----------------- */

static roz_runtime_t rt;
static roz_port_t port;
static int have_rt;

static const char copy_wat[] =
    "(module"
    " (import \"state\" \"count\" (func $count (result i32)))"
    " (import \"state\" \"get\" (func $get (param i32) (result f64)))"
    " (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))"
    " (func (export \"process\") (param i64)"
    "  (drop (call $set (i32.const 0) (call $get (i32.sub (call $count) (i32.const 5)))))))";

static void open_robot(const roz_manifest_t *m, const roz_params_t *p)
{
    char err[400] = "";
    if (FIXTURE.open(m, p, &port, err, sizeof err) != ROZ_OK)
        fail_msg("open: %s", err);
}

static void start_runtime(const roz_manifest_t *m)
{
    static uint8_t wasm[512];
    roz_runtime_config_t cfg;
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = port;
    cfg.monitor_jitter = 0;
    cfg.stale_ticks = 1000000u; /* the state is one frame: the inputs are under test */
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    have_rt = 1;
    roz_operator_sink_t sink = roz_runtime_operator_sink(&rt);
    assert_int_equal(roz_port_set_operator(&port, &sink), ROZ_OK);
    assert_int_equal(roz_port_set_operator(&port, &sink), ROZ_ESTATE); /* once */
    roz_ros2fx_send(); /* a state frame: the controller runs from the first tick */
    size_t len = roz_test_wat(copy_wat, wasm, sizeof wasm);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
}

static void ticks(int n)
{
    for (int i = 0; i < n; i++) {
        int rc = roz_runtime_tick(&rt);
        assert_true(rc == ROZ_OK || rc == ROZ_EFAULT);
    }
}

static double input(int k)
{
    return roz_runtime_last_state(&rt)[n_states + k];
}

static int teardown(void **st)
{
    (void)st;
    if (have_rt)
        roz_runtime_deinit(&rt);
    have_rt = 0;
    FIXTURE.close();
    return 0;
}

/* ---- the fake operator ------------------------------------------------------------- */

/* The fake's operator writers each matched @p want readers (the port's). */
static void wait_operator_matched(unsigned want)
{
    for (unsigned ms = 0;; ms++) {
        unsigned tw = 0, jo = 0;
        roz_ros2fx_ask("operator_matched");
        assert_int_equal(sscanf(roz_ros2fx_fake()->proc.line, "ok %u %u", &tw, &jo), 2);
        if (tw >= want && jo >= want)
            return;
        if (ms >= WAIT_MS)
            fail_msg("the operator's writers matched %u and %u readers, not %u", tw, jo, want);
        roz_fake_sleep_ms(1);
    }
}

/* Waits until the port's operator topic @p k received @p n samples. */
static roz_ros2_counters_t wait_samples(int k, uint64_t n)
{
    roz_ros2_counters_t c;
    for (unsigned ms = 0;; ms++) {
        roz_ros2_counters(roz_ros2fx_bridge(), &c);
        if (c.operator_samples[k] >= n)
            return c;
        if (ms >= WAIT_MS)
            fail_msg("operator topic %d: %llu samples, not %llu", k,
                     (unsigned long long)c.operator_samples[k], (unsigned long long)n);
        roz_fake_sleep_ms(1);
    }
}

/* A twist on /cmd_vel, taken by the port */
static roz_ros2_counters_t twist(uint64_t nth, const char *six)
{
    roz_ros2fx_ask("twist %s", six);
    return wait_samples(0, nth);
}

/* ---- /cmd_vel ------------------------------------------------------------------------ */

/* A twist reaches the inputs scaled (velocity.x = 0.5 linear.x, yaw_rate =
 * -angular.z) and the controller's target; a NaN is refused by the inputs'
 * rule and counted, the input unchanged; then silence: stale after 100 ms
 * of ticks, back to 0 at 0.01 a tick, never a jump. */
static void test_ros2_twist_reaches_a_controller(void **st)
{
    (void)st;
    const roz_manifest_t *m = with_inputs(N_IN);
    open_robot(m, NULL);
    start_runtime(m);
    wait_operator_matched(1);
    ticks(1);
    assert_true(input(VX) == 0.0);

    roz_ros2_counters_t c = twist(1, "0.6 0 0 0 0 -0.25");
    assert_int_equal(c.operator_handed[0], 1);
    ticks(1);
    assert_near(input(VX), 0.01, 1e-12); /* the rate cap */
    assert_near(input(YAW), 0.25, 1e-12);
    ticks(40);
    assert_near(input(VX), 0.3, 1e-12);
    /* the controller's target is the input: what it was handed */
    assert_near(roz_runtime_last_targets(&rt)[0], 0.3, 1e-12);

    /* out of range: clamped (0.5 x 2 = 1 > 0.4), counted */
    twist(2, "2 0 0 0 0 0");
    ticks(10);
    assert_near(input(VX), 0.4, 1e-12);
    assert_int_equal(roz_runtime_input_counters(&rt)->clamped, 1);

    /* NaN: refused, counted; the input keeps its value */
    twist(3, "nan 0 0 0 0 nan");
    ticks(1);
    assert_near(input(VX), 0.4, 1e-12);
    assert_int_equal(roz_runtime_input_counters(&rt)->nonfinite, 2);

    /* silence: 50 ticks after the last good value (tick 52), stale; then
     * 0.4 to 0 at 0.01 a tick */
    uint64_t stale_before = roz_runtime_input_counters(&rt)->stale;
    int moved_at = -1;
    for (int i = 0; i < 200; i++) {
        double before = input(VX);
        ticks(1);
        assert_true(fabs(input(VX) - before) <= 0.01 + 1e-12);
        if (moved_at < 0 && input(VX) != before)
            moved_at = i;
    }
    assert_true(moved_at > 0);
    assert_true(input(VX) == 0.0);
    assert_true(roz_runtime_input_counters(&rt)->stale > stale_before);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* /cmd_vel under another name (parameter cmd_vel_topic) */
static void test_ros2_cmd_vel_topic_renamed(void **st)
{
    (void)st;
    static const char *const fake_args[] = { "--cmd-vel-topic", "rt/teleop/cmd_vel", NULL };
    roz_param_t items[] = { { "cmd_vel_topic", "/teleop/cmd_vel" } };
    roz_params_t p = { items, 1 };
    const roz_manifest_t *m = with_inputs(N_IN);
    roz_ros2fx_set_fake_args(fake_args);
    open_robot(m, &p);
    start_runtime(m);
    wait_operator_matched(1);
    twist(1, "0 0 0 0 0 0.5");
    ticks(1);
    assert_near(input(YAW), -0.5, 1e-12);
}

/* ---- /joy ---------------------------------------------------------------------------- */

/* A Joy through the default joy_map (ROS 2 joy's pad layout): left stick up
 * (axis 1) is remote.ly, the left trigger (axis 4, 0 released to -1
 * pressed) remote.l2, button 0 remote.btn.a. */
static void test_ros2_joy_reaches_the_inputs(void **st)
{
    (void)st;
    const roz_manifest_t *m = with_inputs(N_IN);
    open_robot(m, NULL);
    start_runtime(m);
    wait_operator_matched(1);
    roz_ros2fx_ask("joy_axis 1 0.75");
    roz_ros2fx_ask("joy_axis 4 -0.25");
    roz_ros2fx_ask("joy_button 0 1");
    roz_ros2fx_ask("joy");
    roz_ros2_counters_t c = wait_samples(1, 1);
    assert_int_equal(c.operator_handed[1], 1);
    assert_int_equal(c.operator_refused[1], 0);
    ticks(1);
    assert_near(input(LY), 0.75, 1e-7);
    assert_near(input(L2), 0.5, 1e-7); /* 2 x 0.25 */
    assert_true(input(BTN_A) == 1.0);

    /* a NaN on a mapped axis: the whole message refused, counted */
    roz_ros2fx_ask("joy_axis 1 nan");
    roz_ros2fx_ask("joy_button 0 0");
    roz_ros2fx_ask("joy");
    c = wait_samples(1, 2);
    assert_int_equal(c.operator_refused[1], 1);
    assert_int_equal(c.operator_handed[1], 1);
    ticks(1);
    assert_near(input(LY), 0.75, 1e-7);
    assert_true(input(BTN_A) == 1.0);

    /* fewer axes than the map names (a joystick with 2): refused, counted */
    roz_ros2fx_ask("joy_axis 1 0.5");
    roz_ros2fx_ask("joy_length 2 21");
    roz_ros2fx_ask("joy");
    c = wait_samples(1, 3);
    assert_int_equal(c.operator_refused[1], 2);

    /* more axes, or buttons, than ROZ_ROS2_JOY_MAX (33 axes: ROS 2 joy's
     * message is unbounded): each refused whole and counted as oversized,
     * the inputs unchanged; the next good one, written after them on the
     * same reliable writer, is handed */
    assert_int_equal(c.operator_oversized, 0);
    roz_ros2fx_ask("joy_axis %d 0.25", ROZ_ROS2_JOY_MAX);
    roz_ros2fx_ask("joy_length %d 21", ROZ_ROS2_JOY_MAX + 1);
    roz_ros2fx_ask("joy");
    c = wait_samples(1, 4);
    assert_int_equal(c.operator_oversized, 1);
    assert_int_equal(c.operator_refused[1], 3);
    assert_int_equal(c.operator_handed[1], 1);
    roz_ros2fx_ask("joy_length 6 %d", ROZ_ROS2_JOY_MAX + 8);
    roz_ros2fx_ask("joy");
    c = wait_samples(1, 5);
    assert_int_equal(c.operator_oversized, 2);
    assert_int_equal(c.operator_refused[1], 4);
    ticks(1);
    assert_near(input(LY), 0.75, 1e-7); /* neither moved anything */
    roz_ros2fx_ask("joy_length 6 21");
    roz_ros2fx_ask("joy_axis 1 -0.5");
    roz_ros2fx_ask("joy");
    c = wait_samples(1, 6);
    assert_int_equal(c.operator_samples[1], 6);
    assert_int_equal(c.operator_handed[1], 2);
    assert_int_equal(c.operator_refused[1], 4);
    assert_int_equal(c.operator_oversized, 2);
    ticks(2); /* 0.75 to -0.5: two ticks at 1 a tick */
    assert_near(input(LY), -0.5, 1e-7);
    assert_true(input(BTN_A) == 0.0);
    assert_int_equal(roz_runtime_input_counters(&rt)->nonfinite, 0);
}

/* ---- no subscription without an input that needs it ------------------------------------ */

static void test_ros2_operator_topics_only_when_needed(void **st)
{
    (void)st;
    /* the twist inputs only, no e-stop chord: /cmd_vel read, /joy not */
    const roz_manifest_t *m = with_inputs(YAW + 1);
    m_op.remote_estop = 0;
    open_robot(m, NULL);
    start_runtime(m);
    wait_operator_matched(0);
    twist(1, "0.2 0 0 0 0 0");
    /* the port's participant is discovered (its cmd_vel reader matched):
     * a joy reader would have been by now too */
    roz_ros2fx_ask("operator_matched");
    assert_string_equal(roz_ros2fx_fake()->proc.line, "ok 1 0");
    roz_ros2fx_ask("joy");
    twist(2, "0.2 0 0 0 0 0");
    roz_ros2_counters_t c;
    roz_ros2_counters(roz_ros2fx_bridge(), &c);
    assert_int_equal(c.operator_samples[1], 0);
    teardown(NULL);

    /* no input with a source, no chord: neither */
    m = with_inputs(0);
    m_op.remote_estop = 0;
    open_robot(m, NULL);
    roz_ros2fx_ask("operator_matched");
    assert_string_equal(roz_ros2fx_fake()->proc.line, "ok 0 0");
}

/* ---- the remote's e-stop from /joy ------------------------------------------------------ */

/* The robot's own remote_estop, L2 + B (the left trigger past half way and
 * button 1 in the default joy_map): with no input naming the remote, the
 * chord alone has /joy read; one of its buttons alone latches nothing; the
 * chord latches ESTOP at the next tick; a clear is refused while the last Joy
 * held it; a release and then a /joy silent for 2 s (stale: ROS 2 joy
 * repeats at 20 Hz) leave it latched; only the operator's clear releases it. */
static void test_ros2_joy_remote_estop(void **st)
{
    const uint16_t l2 = ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_L2);
    const uint16_t b = ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_B);
    unsigned tw = 0, jo = 0;
    (void)st;
    assert_int_equal(BASE_MANIFEST.remote_estop, l2 | b);
    const roz_manifest_t *m = with_inputs(0);
    open_robot(m, NULL);
    start_runtime(m);
    for (unsigned ms = 0; jo == 0; ms++) {
        roz_ros2fx_ask("operator_matched");
        assert_int_equal(sscanf(roz_ros2fx_fake()->proc.line, "ok %u %u", &tw, &jo), 2);
        if (ms >= WAIT_MS)
            fail_msg("/joy is not read for the chord alone");
        roz_fake_sleep_ms(1);
    }
    assert_int_equal(tw, 0); /* no twist input: /cmd_vel not read */
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);

    roz_ros2fx_ask("joy_axis 4 -1.0"); /* L2 alone */
    roz_ros2fx_ask("joy");
    wait_samples(1, 1);
    ticks(1);
    roz_ros2fx_ask("joy_axis 4 0.0"); /* B alone */
    roz_ros2fx_ask("joy_button 1 1");
    roz_ros2fx_ask("joy");
    wait_samples(1, 2);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);

    roz_ros2fx_ask("joy_axis 4 -0.75"); /* L2 and B */
    roz_ros2fx_ask("joy");
    roz_ros2_counters_t c = wait_samples(1, 3);
    assert_int_equal(c.operator_handed[1], 3);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_ESTATE);

    roz_ros2fx_ask("joy_axis 4 0.0"); /* released, then silence */
    roz_ros2fx_ask("joy_button 1 0");
    roz_ros2fx_ask("joy");
    wait_samples(1, 4);
    ticks(1000);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* ---- the parameters ---------------------------------------------------------------------- */

static void expect_open_error(const char *key, const char *value, const char *says)
{
    char err[400] = "";
    roz_param_t items[] = { { key, value } };
    roz_params_t p = { items, 1 };
    roz_port_t unused;
    assert_int_not_equal(
        FIXTURE.open(with_inputs(N_IN), &p, &unused, err, sizeof err), ROZ_OK);
    if (strstr(err, says) == NULL)
        fail_msg("%s = \"%s\": \"%s\" does not say \"%s\"", key, value, err, says);
    FIXTURE.close();
}

static void test_ros2_operator_params_refused(void **st)
{
    (void)st;
    expect_open_error("cmd_vel_topic", "cmd_vel",
                      "parameter cmd_vel_topic = \"cmd_vel\": expected a ROS topic name");
    expect_open_error("joy_topic", "/joy/", "parameter joy_topic = \"/joy/\"");
    expect_open_error("joy_topic", "/1joy", "parameter joy_topic = \"/1joy\"");
    expect_open_error("joy_map", "lx=a0 zz=b1",
                      "parameter joy_map = \"lx=a0 zz=b1\": \"zz=b1\": not a field of the remote");
}

/* joy_map's rule (roz_ros2_joy_map_parse()) and its application */
static void test_ros2_joy_map(void **st)
{
    roz_ros2_joy_map_t map;
    roz_operator_remote_t r;
    char err[300];
    float axes[6] = { 0.5f, 0.25f, -1.0f, 1.0f, -1.0f, 0.0f };
    int32_t buttons[21] = { 0 };
    (void)st;

    assert_int_equal(roz_ros2_joy_map_parse(ROZ_ROS2_JOY_MAP_DEFAULT, &map, err, sizeof err),
                     ROZ_OK);
    buttons[6] = 1;  /* start */
    buttons[14] = 1; /* D-pad right */
    assert_int_equal(roz_ros2_joy_remote(&map, axes, 6, buttons, 21, &r), ROZ_OK);
    assert_true(r.lx == -0.5f && r.ly == 0.25f && r.rx == 1.0f && r.ry == 1.0f);
    assert_true(r.l2 == 1.0f && r.r2 == 0.0f);
    assert_int_equal(r.buttons, ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_START) |
                                    ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_RIGHT) |
                                    ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_L2));
    assert_int_equal(roz_ros2_joy_remote(&map, axes, 5, buttons, 21, &r), ROZ_ERANGE);
    assert_int_equal(roz_ros2_joy_remote(&map, axes, 6, buttons, 14, &r), ROZ_ERANGE);
    axes[3] = NAN;
    assert_int_equal(roz_ros2_joy_remote(&map, axes, 6, buttons, 21, &r), ROZ_EINVAL);

    /* a map of its own: what it does not name is 0 */
    assert_int_equal(roz_ros2_joy_map_parse("  ly=-a3 btn.f1=b31 ", &map, err, sizeof err),
                     ROZ_OK);
    axes[3] = 0.5f;
    memset(buttons, 0, sizeof buttons);
    int32_t many[32] = { 0 };
    many[31] = 7;
    assert_int_equal(roz_ros2_joy_remote(&map, axes, 4, many, 32, &r), ROZ_OK);
    assert_true(r.ly == -0.5f && r.lx == 0.0f);
    assert_int_equal(r.buttons, ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_F1));

    static const char *const bad[][2] = {
        { "lx", "\"lx\": expected FIELD=SOURCE" },
        { "=a0", "\"=a0\": expected FIELD=SOURCE" },
        { "lx=a32", "\"lx=a32\": expected aN" },
        { "lx=a01", "\"lx=a01\": expected aN" },
        { "lx=c1", "\"lx=c1\": expected aN" },
        { "btn.a=-b0", "\"btn.a=-b0\": expected aN" },
        { "lx=a0 lx=a1", "\"lx=a1\": the field is mapped twice" },
        { "twist.linear.x=a0", "not a field of the remote" },
        { "remote.lx=a0", "not a field of the remote" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        err[0] = '\0';
        assert_int_equal(roz_ros2_joy_map_parse(bad[i][0], &map, err, sizeof err), ROZ_EINVAL);
        if (strstr(err, bad[i][1]) == NULL || strstr(err, "parameter joy_map = \"") != err)
            fail_msg("%s: \"%s\" does not say \"%s\"", bad[i][0], err, bad[i][1]);
    }
}

ROZ_TEST_MAIN(cmocka_unit_test(test_ros2_joy_map),
              cmocka_unit_test_teardown(test_ros2_twist_reaches_a_controller, teardown),
              cmocka_unit_test_teardown(test_ros2_cmd_vel_topic_renamed, teardown),
              cmocka_unit_test_teardown(test_ros2_joy_reaches_the_inputs, teardown),
              cmocka_unit_test_teardown(test_ros2_operator_topics_only_when_needed, teardown),
              cmocka_unit_test_teardown(test_ros2_joy_remote_estop, teardown),
              cmocka_unit_test(test_ros2_operator_params_refused))
