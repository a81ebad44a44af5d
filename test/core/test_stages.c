/* SPDX-License-Identifier: Apache-2.0 */
/* The deploy sequence (roz/stages.h) on the loopback 12-joint G1: the
 * check names what does not fit, the buttons (inputs of 0 or 1) and the API
 * switch the stages as Unitree's deploy does, each stage's commands reach the
 * port through the filter, and a hand-over keeps the gains on the wire until
 * the incoming controller commands its own. The physics of it:
 * test/ports/mujoco/test_mujoco_stages.c. */
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"
#include "support_stats.h"
#include "support_wat.h"
#include "unitree_g1_12dof_manifest.h"

#define N 12             /* joints */
#define KP(j) (24 + (j)) /* the 12-joint G1's stiffness commands */
#define KD(j) (36 + (j))
#define EFF(j) (48 + (j))
#define VEL(j) (12 + (j))

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;
static roz_manifest_t m;  /* the 12-joint G1 with four buttons */
static roz_channel_t inputs[7];
static roz_input_rule_t input_rules[7];
static roz_channel_t commands[ROZ_CFG_MAX_COMMANDS];
static double stand[ROZ_CFG_MAX_COMMANDS];
/* The velocity commands' default for the next start() (the manifest's is
 * 0): a stage that sends a channel's default instead of its zero shows. */
static double velocity_default;

enum { BTN_START = 3, BTN_A, BTN_B, BTN_SELECT }; /* input indices */

/* The built-in 12-joint G1 with four buttons after its three velocity
 * inputs: a button is an input of 0 or 1. */
static void setup_manifest(void)
{
    static const char *const names[4] = { "remote/start", "remote/a", "remote/b",
                                          "remote/select" };
    m = roz_manifest_unitree_g1_12dof;
    memcpy(inputs, m.inputs, sizeof inputs[0] * m.n_inputs);
    memcpy(input_rules, m.input_rules, sizeof input_rules[0] * m.n_inputs);
    for (int k = 0; k < 4; k++) {
        inputs[3 + k] = (roz_channel_t){ .name = names[k], .type = ROZ_IF_POSITION, .unit = "",
                                         .min = 0.0, .max = 1.0, .max_rate = 1.0,
                                         .position_state = ROZ_CHANNEL_UNPAIRED };
        input_rules[3 + k] = (roz_input_rule_t){ .stale_after_ms = 100000 };
    }
    m.inputs = inputs;
    m.input_rules = input_rules;
    m.n_inputs = 7;
    memcpy(commands, m.commands, sizeof commands[0] * m.n_commands);
    for (int j = 0; j < N; j++)
        commands[VEL(j)].default_value = velocity_default;
    m.commands = commands;
    static const double pose[N] = { -0.1, 0, 0, 0.3, -0.2, 0, -0.1, 0, 0, 0.3, -0.2, 0 };
    static const double kp[N] = { 100, 100, 100, 150, 40, 40, 100, 100, 100, 150, 40, 40 };
    for (int i = 0; i < m.n_commands; i++)
        stand[i] = 0.0;
    for (int j = 0; j < N; j++) {
        stand[j] = pose[j];
        stand[KP(j)] = kp[j];
        stand[KD(j)] = 2.0;
    }
}

static roz_stages_config_t config(void)
{
    return (roz_stages_config_t){ stand, 2.0, 8.0, BTN_START, BTN_A, BTN_B, BTN_SELECT };
}

/* init, the sequence, a controller (NULL: none), start */
static void start(const roz_stages_config_t *sc, const char *wat)
{
    static uint8_t wasm[1024];
    roz_runtime_config_t cfg;
    char err[256];

    setup_manifest();
    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &lb, &m, NULL, &clk);
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    if (sc != NULL && roz_runtime_stages_set(&rt, sc, err, sizeof err) != ROZ_OK)
        fail_msg("%s", err);
    if (wat != NULL) {
        size_t len = roz_test_wat(wat, wasm, sizeof wasm);
        if (roz_runtime_load(&rt, wasm, len, NULL) != ROZ_OK)
            fail_msg("%s", roz_runtime_error(&rt));
    }
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
}

static void ticks(int n)
{
    for (int i = 0; i < n; i++) {
        roz_test_tick(&rt);
        assert_int_equal(roz_loopback_counters(&lb).violations, 0);
    }
}

/* Asks for stage @p want (the request taken), ticks @p n times: the stage
 * is then @p now. */
static void request(roz_stage_t want, int n, roz_stage_t now)
{
    assert_int_equal(roz_runtime_stage_request(&rt, want), ROZ_OK);
    ticks(n);
    assert_int_equal(roz_runtime_stage(&rt), now);
}

static void press(int k, double v)
{
    assert_int_equal(roz_runtime_input_set(&rt, (uint32_t)k, v), ROZ_OK);
}

/* A controller that sets every stiffness (channels 24 to 35) to @p kp, a
 * WAT f64 expression of the tick $t, then does @p then. */
#define KP_WAT(kp, then)                                                       \
    "(module"                                                                  \
    " (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))"   \
    " (func (export \"process\") (param $t i64) (local $i i32)"                \
    "  (local.set $i (i32.const 24))"                                          \
    "  (block $done (loop $next"                                               \
    "   (br_if $done (i32.ge_u (local.get $i) (i32.const 36)))"                \
    "   (drop (call $set (local.get $i) " kp "))"                              \
    "   (local.set $i (i32.add (local.get $i) (i32.const 1)))"                 \
    "   (br $next)))" then "))"

/* Every stiffness 120, counting its ticks in effort 0's target (the tick it
 * was given, as f64, clamped by the channel). */
static const char kp120_wat[] =
    KP_WAT("(f64.const 120)",
           "  (drop (call $set (i32.const 48) (f64.convert_i64_s (local.get $t))))");

/* The same shape, its stiffness ramping in from 0 at 0.5 a tick (as the
 * policy runner's ramp does), or staying at 0. */
static const char ramp_wat[] =
    KP_WAT("(f64.mul (f64.convert_i64_s (local.get $t)) (f64.const 0.5))", "");
static const char zero_kp_wat[] = KP_WAT("(f64.const 0)", "");

/* Every stiffness 120, every velocity (channels 12 to 23) 0.5 and every
 * effort (48 to 59) 5: what the zero stage must never pass through. */
static const char moving_wat[] =
    KP_WAT("(f64.const 120)",
           "  (local.set $i (i32.const 12))"
           "  (block $v (loop $nv"
           "   (br_if $v (i32.ge_u (local.get $i) (i32.const 24)))"
           "   (drop (call $set (local.get $i) (f64.const 0.5)))"
           "   (drop (call $set (i32.add (local.get $i) (i32.const 36)) (f64.const 5)))"
           "   (local.set $i (i32.add (local.get $i) (i32.const 1)))"
           "   (br $nv)))");

/* Every value is checked against the manifest, naming the key. */
static void test_stages_check(void **st)
{
    char err[256];
    (void)st;
    setup_manifest();
    roz_stages_config_t c = config();
    assert_int_equal(roz_stages_check(&m, &c, err, sizeof err), ROZ_OK);
    stand[3] = 4.0; /* the left knee, past its upper limit */
    assert_int_equal(roz_stages_check(&m, &c, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "stand[3] \"left_knee_joint/position\": 4: outside its limits"));
    stand[3] = 0.3;
    stand[KP(0)] = NAN;
    assert_int_equal(roz_stages_check(&m, &c, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "\"left_hip_pitch_joint/stiffness\": nan"));
    stand[KP(0)] = 100.0;
    c.move_s = 0.0;
    assert_int_equal(roz_stages_check(&m, &c, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "move_s: 0: must be above 0 s"));
    c = config();
    c.stop_damping = 1e9;
    assert_int_equal(roz_stages_check(&m, &c, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "stop_damping: 1e+09: outside"));
    c = config();
    c.run = 7;
    assert_int_equal(roz_stages_check(&m, &c, err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "run: input 7: the manifest has 7 inputs"));
    c.stand = NULL;
    assert_int_equal(roz_stages_check(&m, &c, err, sizeof err), ROZ_EINVAL);
    assert_string_equal(roz_stage_name(ROZ_STAGE_HOLD), "hold");
    assert_int_equal(roz_stage_from_name("stop"), ROZ_STAGE_STOP);
    assert_int_equal(roz_stage_from_name("walk"), -1);
}

/* Unitree's deploy, by the buttons: zero torque until Start, the stand pose
 * over 2 s, held until A, the controller, B back to the stand, Select to
 * damping. */
static void test_stages_buttons(void **st)
{
    (void)st;
    roz_stages_config_t c = config();
    start(&c, kp120_wat);
    const double *out = roz_runtime_last_commands(&rt);
    const double *s = roz_runtime_last_state(&rt);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_ZERO);
    ticks(50);
    for (int j = 0; j < N; j++) { /* zero torque: limp, positions where they are */
        assert_true(out[KP(j)] == 0.0 && out[KD(j)] == 0.0 && out[EFF(j)] == 0.0 &&
                    out[VEL(j)] == 0.0);
        assert_near(out[j], s[j], 1e-9);
    }
    assert_int_equal(RT_COUNT(&rt, controller_ticks), 0);
    press(BTN_A, 1.0); /* A before Start: nothing */
    ticks(5);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_ZERO);
    press(BTN_A, 0.0);
    press(BTN_START, 1.0);
    ticks(2);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_MOVE);
    press(BTN_START, 0.0);
    /* the move: every channel between where it started and the stand */
    double knee0 = s[3];
    for (int t = 0; t < 990; t++) {
        ticks(1);
        double lo = fmin(knee0, stand[3]) - 1e-9, hi = fmax(knee0, stand[3]) + 1e-9;
        assert_true(out[3] >= lo && out[3] <= hi);
        assert_true(out[KP(3)] >= 0.0 && out[KP(3)] <= stand[KP(3)]);
    }
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_MOVE);
    ticks(20);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_HOLD);
    ticks(200);
    for (int j = 0; j < N; j++) {
        assert_near(out[j], stand[j], 1e-9);
        assert_true(out[KP(j)] == stand[KP(j)]);
    }
    assert_int_equal(RT_COUNT(&rt, controller_ticks), 0);
    press(BTN_A, 1.0);
    ticks(2);
    press(BTN_A, 0.0);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_RUN);
    /* the controller from tick 0, the stand's knee gain kept (150 > 120)
     * for the hand-over, then down to the controller's at the rate cap */
    assert_true(roz_runtime_last_targets(&rt)[EFF(0)] <= 1.0);
    assert_true(out[KP(3)] == 150.0);
    ticks(998);
    assert_true(out[KP(3)] == 150.0);
    ticks(50);
    assert_true(out[KP(3)] == 120.0 && out[KP(0)] == 120.0); /* its own, at the rate cap */
    /* B: back to the stand from where the robot is */
    press(BTN_B, 1.0);
    ticks(2);
    press(BTN_B, 0.0);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_MOVE);
    assert_true(out[KP(3)] >= 120.0 - 1e-9);
    ticks(1100);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_HOLD);
    assert_true(out[KP(3)] == 150.0);
    /* Select: damping (kp 0, kd 8), reached at the rate caps */
    press(BTN_SELECT, 1.0);
    ticks(400);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_STOP);
    for (int j = 0; j < N; j++)
        assert_true(out[KP(j)] == 0.0 && out[KD(j)] == 8.0 && out[EFF(j)] == 0.0);
    const roz_stages_counters_t *sc = roz_runtime_stages_counters(&rt);
    assert_int_equal(sc->transitions, 6); /* move hold run move hold stop */
    assert_int_equal(sc->handovers, 1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* Whether the tick's targets and the commands on the wire are ZERO's: no
 * stiffness, damping, velocity nor effort, on every joint. */
static void assert_zero_torque(const char *when)
{
    const double *tg = roz_runtime_last_targets(&rt), *out = roz_runtime_last_commands(&rt);
    for (int j = 0; j < N; j++) {
        const int ch[4] = { KP(j), KD(j), VEL(j), EFF(j) };
        for (int k = 0; k < 4; k++) {
            if (tg[ch[k]] != 0.0 || out[ch[k]] != 0.0)
                fail_msg("%s: %s: target %g, sent %g: not zero torque", when,
                         m.commands[ch[k]].name, tg[ch[k]], out[ch[k]]);
        }
    }
}

/* ZERO sends no velocity and no gains whatever drove before it or is
 * loaded: with a controller commanding stiffness 120, velocity 0.5 and
 * effort 5 on every joint, and velocity channels that default to 0.25 (a
 * stage sending a channel's default is not sending zero), ZERO at the
 * start and ZERO after the controller drove and Select stopped it send 0
 * on each of them from their first tick. */
static void test_stages_zero_sends_no_velocity(void **st)
{
    (void)st;
    roz_stages_config_t c = config();
    velocity_default = 0.25;
    start(&c, moving_wat);
    velocity_default = 0.0;
    const double *out = roz_runtime_last_commands(&rt);
    assert_true(m.commands[VEL(0)].default_value == 0.25);
    for (int t = 0; t < 50; t++) {
        ticks(1);
        assert_zero_torque("ZERO at the start, a controller loaded");
    }
    assert_int_equal(RT_COUNT(&rt, controller_ticks), 0);
    request(ROZ_STAGE_MOVE, 1001, ROZ_STAGE_HOLD);
    for (int j = 0; j < N; j++)
        assert_true(out[VEL(j)] == stand[VEL(j)]); /* the stand's, not the default */
    request(ROZ_STAGE_RUN, 1, ROZ_STAGE_RUN);
    ticks(2 * ROZ_CFG_HANDOVER_MS); /* past the hand-over and the rate caps */
    for (int j = 0; j < N; j++) /* the controller drives: its velocity on the wire */
        assert_true(out[VEL(j)] == 0.5 && out[KP(j)] == 120.0 && out[EFF(j)] == 5.0);
    request(ROZ_STAGE_STOP, 1, ROZ_STAGE_STOP);
    assert_int_equal(roz_runtime_stage_request(&rt, ROZ_STAGE_ZERO), ROZ_OK);
    uint64_t ran = RT_COUNT(&rt, controller_ticks);
    ticks(1);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_ZERO);
    const double *tg = roz_runtime_last_targets(&rt);
    for (int j = 0; j < N; j++) /* the targets from the first tick; the wire by the rate caps */
        assert_true(tg[VEL(j)] == 0.0 && tg[KP(j)] == 0.0 && tg[KD(j)] == 0.0 &&
                    tg[EFF(j)] == 0.0 && out[VEL(j)] == 0.0);
    ticks(2000);
    assert_zero_torque("ZERO after the controller and STOP");
    assert_int_equal(RT_COUNT(&rt, controller_ticks), ran);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* The API: only the transitions a deploy has; the rest dropped and counted;
 * RUN needs a controller; STOP is left only for ZERO. */
static void test_stages_requests(void **st)
{
    char err[64];
    (void)st;
    start(NULL, NULL);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_NONE);
    assert_int_equal(roz_runtime_stage_request(&rt, ROZ_STAGE_MOVE), ROZ_ESTATE);
    roz_stages_config_t c = config();
    assert_int_equal(roz_runtime_stages_set(&rt, &c, err, sizeof err), ROZ_ESTATE);
    roz_runtime_deinit(&rt);

    start(&c, NULL);
    assert_int_equal(roz_runtime_stage_request(&rt, ROZ_STAGE_HOLD), ROZ_EINVAL);
    request(ROZ_STAGE_RUN, 1, ROZ_STAGE_ZERO);
    request(ROZ_STAGE_MOVE, 1001, ROZ_STAGE_HOLD);
    request(ROZ_STAGE_RUN, 1, ROZ_STAGE_HOLD); /* no controller */
    request(ROZ_STAGE_STOP, 1, ROZ_STAGE_STOP);
    request(ROZ_STAGE_MOVE, 1, ROZ_STAGE_STOP);
    request(ROZ_STAGE_ZERO, 1, ROZ_STAGE_ZERO);
    assert_int_equal(roz_runtime_stages_counters(&rt)->refused, 3);
    /* a latched fault: only STOP is taken */
    roz_runtime_estop_set(&rt, 1);
    request(ROZ_STAGE_MOVE, 1, ROZ_STAGE_ZERO);
    assert_int_equal(roz_runtime_stage_request(&rt, ROZ_STAGE_STOP), ROZ_OK);
    roz_test_tick(&rt);
    assert_int_equal(roz_runtime_stage(&rt), ROZ_STAGE_STOP);
    roz_runtime_estop_set(&rt, 0);
}

/* A swap keeps the gains on the wire: an incoming controller that ramps
 * its stiffness in gets the outgoing 120 until its ramp reaches 120; one
 * that sends 0 gets 120 for ROZ_CFG_HANDOVER_MS, then the rate cap down. */
static void test_stages_swap_keeps_gains(void **st)
{
    static uint8_t w1[1024], w2[1024];
    (void)st;
    start(NULL, kp120_wat);
    const double *out = roz_runtime_last_commands(&rt);
    ticks(400);
    assert_true(out[KP(3)] == 120.0);
    size_t len = roz_test_wat(ramp_wat, w1, sizeof w1);
    assert_int_equal(roz_runtime_load(&rt, w1, len, NULL), ROZ_OK);
    for (int t = 0; t < 300; t++) {
        ticks(1);
        assert_true(out[KP(3)] >= 120.0);
    }
    assert_true(out[KP(3)] == 149.5); /* its own, above 120: released at tick 240 */
    assert_int_equal(roz_runtime_stages_counters(&rt)->handovers, 1);
    len = roz_test_wat(zero_kp_wat, w2, sizeof w2);
    assert_int_equal(roz_runtime_load(&rt, w2, len, NULL), ROZ_OK);
    int ticks_held = 0;
    for (int t = 0; t < 1000 * 500 / 1000 * ROZ_CFG_HANDOVER_MS / 1000; t++) {
        ticks(1);
        ticks_held += out[KP(3)] >= 149.5;
    }
    assert_int_equal(ticks_held, ROZ_CFG_HANDOVER_MS / 2); /* 500 Hz */
    ticks(1);
    assert_near(out[KP(3)], 149.5 - 0.8, 1e-9); /* the rate cap, down */
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* Requests from another thread while the tick runs (TSan in its build):
 * each is taken whole or dropped and counted, and the stage the tick
 * publishes is always one of the sequence's. */
static atomic_int asking;
static void *ask(void *arg)
{
    static const roz_stage_t asks[] = { ROZ_STAGE_MOVE, ROZ_STAGE_STOP, ROZ_STAGE_ZERO };
    unsigned n = 0;
    (void)arg;
    while (atomic_load(&asking))
        (void)roz_runtime_stage_request(&rt, asks[n++ % 3u]);
    return NULL;
}

static void test_stages_request_from_thread(void **st)
{
    pthread_t th;
    (void)st;
    roz_stages_config_t c = config();
    start(&c, NULL);
    atomic_store(&asking, 1);
    assert_int_equal(pthread_create(&th, NULL, ask, NULL), 0);
    for (int t = 0; t < 20000; t++) {
        roz_test_tick(&rt);
        int s = (int)roz_runtime_stage(&rt);
        assert_true(s >= ROZ_STAGE_ZERO && s <= ROZ_STAGE_STOP);
    }
    atomic_store(&asking, 0);
    assert_int_equal(pthread_join(th, NULL), 0);
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
    assert_true(roz_runtime_stages_counters(&rt)->transitions > 0);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

static int teardown(void **st)
{
    (void)st;
    roz_runtime_deinit(&rt);
    return 0;
}

ROZ_TEST_MAIN(cmocka_unit_test(test_stages_check),
              cmocka_unit_test_teardown(test_stages_buttons, teardown),
              cmocka_unit_test_teardown(test_stages_zero_sends_no_velocity, teardown),
              cmocka_unit_test_teardown(test_stages_requests, teardown),
              cmocka_unit_test_teardown(test_stages_swap_keeps_gains, teardown),
              cmocka_unit_test_teardown(test_stages_request_from_thread, teardown))
