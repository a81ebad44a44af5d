/* SPDX-License-Identifier: Apache-2.0 */
/* The runtime on the loopback simulator: controllers drive the robot, each
 * fault latches and drives the safe defaults (ramped or at once), verify and
 * swap, and nothing outside the manifest reaches the port. Time is a test
 * clock that advances a fixed step per reading. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_stats.h"
#include "support_runtime.h"
#include "support_wat.h"
#include "unitree_g1_12dof_manifest.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

static roz_runtime_t rt;
static roz_loopback_t lb;
static roz_test_clock_t clk;

/* Every command the port got is inside the manifest. */
static void assert_port_safe(void)
{
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
}

static void start(const roz_manifest_t *m, const roz_params_t *params)
{
    roz_runtime_config_t cfg;

    clk = (roz_test_clock_t){ 1000000, 1000 }; /* every reading advances 1 us */
    roz_test_loopback_config(&cfg, &lb, m, params, &clk);
    roz_test_runtime_start(&rt, &cfg, NULL);
}

static void load(const char *name, int expect)
{
    size_t len;
    const uint8_t *w = roz_test_controller(name, &len);
    int rc = roz_runtime_load(&rt, w, len, NULL);
    if (rc != expect)
        fail_msg("load %s: %d (%s), expected %d", name, rc, roz_runtime_error(&rt), expect);
}

static void ticks(int n)
{
    for (int i = 0; i < n; i++) {
        roz_test_tick(&rt);
        assert_port_safe();
    }
}

static int teardown(void **st)
{
    (void)st;
    roz_runtime_deinit(&rt);
    return 0;
}

static void test_runtime_sine_drives_ur5(void **st)
{
    roz_verify_report_t rep;
    size_t len;
    const uint8_t *w = roz_test_controller("sine", &len);
    (void)st;
    start(&roz_manifest_ur5, NULL);
    assert_int_equal(roz_runtime_load(&rt, w, len, &rep), ROZ_OK);
    assert_int_equal(rep.ticks_run, ROZ_RUNTIME_VERIFY_TICKS);
    assert_int_equal(rep.nonfinite, 0);
    ticks(300);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(RT_COUNT(&rt, controller_ticks), 300);
    assert_int_equal(RT_COUNT(&rt, writes), 300);
    /* the filter ramped the sine's first steps (rate cap 0.5 per tick) */
    assert_true(FILTER_COUNT(&rt, rate_caps) > 0);
    /* the arm moved: joint 0 integrates the commanded velocity */
    double q[12];
    roz_loopback_true_state(&lb, q);
    assert_true(fabs(q[0]) > 0.01);
    /* commands equal the controller's sine once past the ramp */
    const double *out = roz_runtime_last_commands(&rt);
    const double *tgt = roz_runtime_last_targets(&rt);
    for (int i = 0; i < 6; i++)
        assert_near(out[i], tgt[i], 1e-9);
}

static void test_runtime_nothing_before_first_state(void **st)
{
    roz_param_t p[] = { { "drop", "0:5" } };
    roz_params_t params = { p, 1 };
    (void)st;
    start(&roz_manifest_ur5, &params);
    load("constant_velocity", ROZ_OK);
    ticks(5);
    assert_int_equal(roz_loopback_counters(&lb).writes, 0);
    assert_int_equal(RT_COUNT(&rt, waiting_ticks), 5);
    ticks(1);
    assert_int_equal(roz_loopback_counters(&lb).writes, 1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

static int warnings;
static char last_warning[160];

static void capture(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    if (level == ROZ_LOG_WARN && strstr(msg, "no state") != NULL) {
        warnings++;
        snprintf(last_warning, sizeof last_warning, "%s", msg);
    }
}

/* Waiting for the robot's first frame is not a fault (a DDS peer may take
 * a while to be discovered): nothing is sent, one warning after stale_ticks,
 * and staleness counts from the first frame. */
static void test_runtime_waiting_is_not_a_fault(void **st)
{
    roz_param_t p[] = { { "freeze", "0:300" }, { "freeze", "310:330" } };
    roz_params_t params = { p, 2 };
    roz_runtime_config_t cfg;
    (void)st;
    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, &params, &clk);
    cfg.log = capture;
    warnings = 0;
    roz_test_runtime_start(&rt, &cfg, NULL);
    load("constant_velocity", ROZ_OK);
    ticks(300);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(roz_loopback_counters(&lb).writes, 0);
    assert_int_equal(RT_COUNT(&rt, waiting_ticks), 300);
    assert_int_equal(RT_COUNT(&rt, stale_reads), 0);
    assert_int_equal(warnings, 0); /* the tick never calls the log callback */
    roz_runtime_log_drain(&rt);    /* the application's non-RT thread does */
    assert_int_equal(warnings, 1);
    assert_non_null(strstr(last_warning, "no state from the port yet after 10 ticks"));
    ticks(10); /* frames from 300 */
    assert_int_equal(roz_loopback_counters(&lb).writes, 10);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    ticks(10); /* frozen again from 310: STALE on the tenth */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
}

static void test_runtime_trap_latches_controlled_stop(void **st)
{
    (void)st;
    start(&roz_manifest_ur5, NULL);
    load("bad_trap_run", ROZ_OK);
    ticks(150);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.1, 1e-12);
    ticks(1); /* tick 150 traps: defaults this very tick, ramped */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_TRAP);
    assert_non_null(strstr(roz_runtime_fault_message(&rt), "unreachable"));
    assert_int_equal(RT_COUNT(&rt, faults[0]), 1);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.0, 1e-12); /* 0.1 within one cap */
    uint64_t calls = RT_COUNT(&rt, controller_ticks);
    ticks(50);
    assert_int_equal(RT_COUNT(&rt, controller_ticks), calls); /* it never runs again */
    assert_int_equal(roz_runtime_tick(&rt), ROZ_EFAULT);
    /* clearing rebuilds it (a trapped instance is not reused), from tick 0 */
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(RT_COUNT(&rt, swaps), 2);
    ticks(149);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_TRAP);
}

static void test_runtime_controlled_stop_ramps(void **st)
{
    (void)st;
    start(&roz_manifest_ur5, NULL);
    load("constant_velocity", ROZ_OK); /* 0.2 * 3.14 = 0.628 on every joint */
    ticks(20);
    assert_near(roz_runtime_last_commands(&rt)[2], 0.628, 1e-12);
    /* freeze the state stream: stale after 10 ticks, then a ramp down */
    roz_loopback_fault_t f = { ROZ_INJECT_FREEZE, roz_loopback_counters(&lb).tick, 0, -1, 0 };
    assert_int_equal(roz_loopback_inject(&lb, &f), ROZ_OK);
    ticks(9);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_near(roz_runtime_last_commands(&rt)[2], 0.128, 1e-12); /* 0.628 - 0.5 */
    ticks(1);
    assert_near(roz_runtime_last_commands(&rt)[2], 0.0, 1e-12);
    /* still latched after the stream comes back, until cleared */
    roz_loopback_clear_faults(&lb);
    ticks(20);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_STALE);
    assert_near(roz_runtime_last_commands(&rt)[2], 0.0, 1e-12);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(3);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_near(roz_runtime_last_commands(&rt)[2], 0.628, 1e-12);
}

static void test_runtime_estop_is_immediate(void **st)
{
    (void)st;
    start(&roz_manifest_ur5, NULL);
    load("constant_velocity", ROZ_OK);
    ticks(10);
    roz_runtime_estop(&rt);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    for (int i = 0; i < 6; i++)
        assert_true(roz_runtime_last_commands(&rt)[i] == 0.0);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(5);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

static void test_runtime_controller_estop(void **st)
{
    (void)st;
    start(&roz_manifest_ur5, NULL);
    load("bad_estop_run", ROZ_OK);
    ticks(150);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.2, 1e-12);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP_REQUEST);
    assert_true(roz_runtime_last_commands(&rt)[0] == 0.0); /* at once, not ramped */
}

static void test_runtime_overrun(void **st)
{
    (void)st;
    start(&roz_manifest_ur5, NULL);
    /* budget 5 ms; from tick 150 it reads the clock 20000 times, each
     * reading 4 us later: the deadline passes after about 1,250 readings,
     * long before the fuel (20 units a reading, 100,000 a tick) runs out */
    clk.step = 4000;
    load("bad_slow", ROZ_OK);
    ticks(150);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_OVERRUN);
    if (strstr(roz_runtime_fault_message(&rt), "deadline passed at tick 150: 5000 us budget") == NULL)
        fail_msg("%s", roz_runtime_fault_message(&rt));
}

static void test_runtime_verify_refuses(void **st)
{
    (void)st;
    start(&roz_manifest_ur5, NULL);
    load("bad_trap_verify", ROZ_EVERIFY);
    assert_non_null(strstr(roz_runtime_error(&rt), "unreachable"));
    load("bad_nonfinite", ROZ_EVERIFY);
    assert_non_null(strstr(roz_runtime_error(&rt), "non-finite"));
    load("bad_unknown_import", ROZ_EINVAL);
    assert_non_null(strstr(roz_runtime_error(&rt), "env.open_valve"));
    assert_int_equal(RT_COUNT(&rt, swaps_refused), 3);
    ticks(5); /* no controller: defaults go out, no fault */
    assert_int_equal(roz_loopback_counters(&lb).writes, 5);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

static void test_runtime_swap_keeps_old_on_failure(void **st)
{
    (void)st;
    start(&roz_manifest_ur5, NULL);
    load("constant_velocity", ROZ_OK);
    ticks(10);
    load("bad_trap_verify", ROZ_EVERIFY);
    ticks(10);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.628, 1e-12);
    assert_int_equal(RT_COUNT(&rt, swaps), 1);
    /* a good one swaps in at the next tick boundary, from tick 0 */
    load("hold", ROZ_OK);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.628, 1e-12);
    ticks(1);
    assert_int_equal(RT_COUNT(&rt, swaps), 2);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.128, 1e-12); /* ramped down */
    ticks(2);
    assert_true(roz_runtime_last_commands(&rt)[0] == 0.0);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* A controller that sets nothing: every target is where the runtime
 * started it. */
static const char idle_wat[] = "(module (func (export \"process\") (param i64)))";

/* Operator inputs are states after the port's: state.count covers them,
 * state.get(n_states + k) reads them, and what a source sets reaches the
 * controller at the input's rate cap, goes back to the default at it when
 * the source falls silent, and never reaches the port. The controller
 * traps unless state.count is 49 (46 states, 3 inputs), and targets the
 * left hip at the operator's velocity.x (in rad: within the hip's limits). */
static const char input_wat[] =
    "(module"
    " (import \"state\" \"count\" (func $count (result i32)))"
    " (import \"state\" \"get\" (func $get (param i32) (result f64)))"
    " (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))"
    " (func (export \"process\") (param i64)"
    "  (if (i32.ne (call $count) (i32.const 49)) (then unreachable))"
    "  (drop (call $set (i32.const 0) (call $get (i32.const 46))))))";

static void test_runtime_operator_inputs(void **st)
{
    static uint8_t wasm[512];
    const roz_manifest_t *m = &roz_manifest_unitree_g1_12dof;
    const double *state;
    (void)st;
    assert_int_equal(m->n_states + m->n_inputs, 49);
    assert_int_equal(ROZ_UNITREE_G1_12DOF_INPUT_OPERATOR_VELOCITY_X, 46);
    start(m, NULL);
    size_t len = roz_test_wat(input_wat, wasm, sizeof wasm);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_input_set(&rt, 3, 0.1), ROZ_EINVAL);
    assert_int_equal(roz_runtime_input_set(&rt, 0, 0.3), ROZ_OK);
    ticks(1);
    state = roz_runtime_last_state(&rt);
    assert_true(fabs(state[46] - 0.002) < 1e-12); /* the rate cap: 0.002 a tick */
    ticks(149);
    assert_true(state[46] == 0.3);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.3, 1e-9);
    /* out of range and non-finite: clamped, refused, counted */
    for (int i = 0; i < 300; i++) { /* the source repeats itself every 100 ticks */
        if (i % 100 == 0)
            assert_int_equal(roz_runtime_input_set(&rt, 0, 5.0), ROZ_OK);
        ticks(1);
    }
    assert_true(state[46] == 0.8);
    assert_int_equal(roz_runtime_input_set(&rt, 0, NAN), ROZ_OK);
    ticks(1);
    assert_true(state[46] == 0.8);
    assert_int_equal(roz_runtime_input_counters(&rt)->clamped, 3);
    assert_int_equal(roz_runtime_input_counters(&rt)->nonfinite, 1);
    /* no good value since tick 351: stale 500 ms (250 ticks) later, then
     * 0.8 back to 0 at 0.002 a tick (400 ticks), never a jump */
    for (int i = 0; i < 600; i++) {
        double before = state[46];
        ticks(1);
        assert_true(fabs(state[46] - before) <= 0.002 + 1e-12);
    }
    assert_true(state[46] == 0.0);
    assert_int_equal(roz_runtime_input_counters(&rt)->stale, 1);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.0, 1e-9);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* The G1's remote reaches its walking command as unitree_rl_gym's deploy
 * reads it: vx = 0.8 ly, vy = -0.5 lx, yaw rate = -1.57 rx (the 12-joint
 * manifest's sources); a twist, which no input names, changes nothing. */
static void test_runtime_operator_remote(void **st)
{
    static uint8_t wasm[512];
    const roz_manifest_t *m = &roz_manifest_unitree_g1_12dof;
    roz_operator_remote_t r = { .lx = 0.5f, .ly = 0.25f, .rx = -1.0f };
    roz_operator_twist_t t = { .linear = { 1.0, 1.0, 1.0 }, .angular = { 1.0, 1.0, 1.0 } };
    const double *state;
    (void)st;
    start(m, NULL);
    size_t len = roz_test_wat(input_wat, wasm, sizeof wasm);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_operator_remote(NULL, &r), ROZ_EINVAL);
    assert_int_equal(roz_runtime_operator_remote(&rt, NULL), ROZ_EINVAL);
    assert_int_equal(roz_runtime_operator_twist(&rt, &t), ROZ_OK);
    for (int i = 0; i < 500; i++) { /* the remote's rate is the port's: here every 10 ticks */
        if (i % 10 == 0)
            assert_int_equal(roz_runtime_operator_remote(&rt, &r), ROZ_OK);
        ticks(1);
    }
    state = roz_runtime_last_state(&rt);
    assert_near(state[ROZ_UNITREE_G1_12DOF_INPUT_OPERATOR_VELOCITY_X], 0.8 * 0.25, 1e-12);
    assert_near(state[ROZ_UNITREE_G1_12DOF_INPUT_OPERATOR_VELOCITY_Y], -0.5 * 0.5, 1e-12);
    assert_near(state[ROZ_UNITREE_G1_12DOF_INPUT_OPERATOR_YAW_RATE], 1.57, 1e-12);
    assert_near(roz_runtime_last_commands(&rt)[0], 0.2, 1e-9);
    assert_int_equal(roz_runtime_input_counters(&rt)->clamped, 0);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* The remote's e-stop (the G1's remote_estop, L2 + B): the chord latches
 * ESTOP at the next tick, one button alone does not; releasing the chord,
 * the remote going silent or a twist never clear it; a clear while the
 * last frame held the chord is refused; after a release the clear takes.
 * A chord pressed and released between two ticks still latches. */
static void test_runtime_remote_estop(void **st)
{
    static uint8_t wasm[512];
    const roz_manifest_t *m = &roz_manifest_unitree_g1_12dof;
    const uint16_t l2 = ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_L2);
    const uint16_t b = ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_B);
    roz_operator_remote_t r = { .buttons = l2 };
    roz_operator_twist_t t = { { 0.0, 0.0, 0.0 }, { 0.0, 0.0, 0.0 } };
    (void)st;
    assert_int_equal(m->remote_estop, l2 | b);
    start(m, NULL);
    size_t len = roz_test_wat(input_wat, wasm, sizeof wasm);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, NULL), ROZ_OK);
    ticks(5);
    assert_int_equal(roz_runtime_operator_remote(&rt, &r), ROZ_OK); /* L2 alone */
    r.buttons = b | ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_A); /* B and A */
    assert_int_equal(roz_runtime_operator_remote(&rt, &r), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    r.buttons = l2 | b | ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_UP); /* the chord, and more */
    assert_int_equal(roz_runtime_operator_remote(&rt, &r), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    /* held: a clear is refused */
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_ESTATE);
    ticks(2);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    /* released, then a silent remote and a twist: latched all along */
    r.buttons = 0;
    assert_int_equal(roz_runtime_operator_remote(&rt, &r), ROZ_OK);
    assert_int_equal(roz_runtime_operator_twist(&rt, &t), ROZ_OK);
    ticks(1000); /* 2 s: the inputs went stale meanwhile */
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    /* the operator's clear releases it */
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    /* pressed and released between two ticks: latched still */
    r.buttons = l2 | b;
    assert_int_equal(roz_runtime_operator_remote(&rt, &r), ROZ_OK);
    r.buttons = 0;
    assert_int_equal(roz_runtime_operator_remote(&rt, &r), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    ticks(1);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* A swapped-in controller starts with its paired position targets at the
 * hold (the measured positions), not at the manifest's defaults: after the
 * stand, the knees stay at 0.3 rad under the idle controller. */
static void test_runtime_swap_starts_at_the_hold(void **st)
{
    static uint8_t idle[256];
    (void)st;
    start(&roz_manifest_unitree_g1, NULL);
    load("g1_stand", ROZ_OK);
    ticks(1500);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    const double *state = roz_runtime_last_state(&rt);
    double knee = state[ROZ_UNITREE_G1_STATE_LEFT_KNEE_JOINT_POSITION];
    assert_near(knee, 0.3, 0.02);
    size_t len = roz_test_wat(idle_wat, idle, sizeof idle);
    assert_int_equal(roz_runtime_load(&rt, idle, len, NULL), ROZ_OK);
    ticks(1);
    assert_int_equal(RT_COUNT(&rt, swaps), 2);
    const double *tgt = roz_runtime_last_targets(&rt);
    const roz_channel_t *c =
        &roz_manifest_unitree_g1.commands[ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_POSITION];
    assert_true(c->default_value != knee);
    assert_near(tgt[ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_POSITION], knee, 0.01);
    ticks(500);
    assert_near(roz_runtime_last_commands(&rt)[ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_POSITION], knee,
                0.01);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* A controller loaded before the first tick starts its paired position
 * targets at the hold too: at the positions of its first tick's snapshot,
 * not the manifest's defaults (a Go2's thigh at 0.9 rad was targeted at 0
 * and the robot tipped). The loopback's left elbow reads 0.5 rad past its
 * upper limit from the first frame: the idle controller's elbow target on
 * tick 0 is the command's upper limit, where the joint is, not 0. */
static void test_runtime_first_tick_holds(void **st)
{
    static uint8_t idle[256];
    char range[64];
    (void)st;
    snprintf(range, sizeof range, "%d@0:5", ROZ_UNITREE_G1_STATE_LEFT_ELBOW_JOINT_POSITION);
    roz_param_t p[] = { { "range", range } };
    roz_params_t params = { p, 1 };
    start(&roz_manifest_unitree_g1, &params);
    size_t len = roz_test_wat(idle_wat, idle, sizeof idle);
    assert_int_equal(roz_runtime_load(&rt, idle, len, NULL), ROZ_OK);
    ticks(1);
    const roz_channel_t *c =
        &roz_manifest_unitree_g1.commands[ROZ_UNITREE_G1_CMD_LEFT_ELBOW_JOINT_POSITION];
    assert_true(c->default_value != c->max);
    assert_true(roz_runtime_last_targets(&rt)[ROZ_UNITREE_G1_CMD_LEFT_ELBOW_JOINT_POSITION] ==
                c->max);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

static void test_runtime_g1_stand(void **st)
{
    (void)st;
    start(&roz_manifest_unitree_g1, NULL);
    load("g1_stand", ROZ_OK);
    ticks(1500); /* 3 s at 500 Hz */
    assert_int_equal(roz_runtime_faults(&rt), 0);
    double q[ROZ_UNITREE_G1_N_STATES];
    roz_loopback_true_state(&lb, q);
    /* the knees reached the standing pose (0.3 rad) under the robot-side PD */
    assert_near(q[ROZ_UNITREE_G1_STATE_LEFT_KNEE_JOINT_POSITION], 0.3, 0.02);
    assert_near(q[ROZ_UNITREE_G1_STATE_RIGHT_ELBOW_JOINT_POSITION], 0.9, 0.05);
    assert_true(roz_runtime_last_commands(&rt)[ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_STIFFNESS] == 150.0);
}

static void test_runtime_nan_and_range_states(void **st)
{
    roz_param_t p[] = { { "nan", "3@50:60" }, { "range", "wrist_2_joint/position@70:" } };
    roz_params_t params = { p, 2 };
    (void)st;
    start(&roz_manifest_ur5, &params);
    load("constant_velocity", ROZ_OK);
    ticks(55);
    /* NaN position of joint 3: its velocity command stops (unknown position) */
    assert_true(roz_runtime_last_commands(&rt)[3] == 0.0);
    assert_true(roz_runtime_last_commands(&rt)[2] > 0.0);
    ticks(20);
    /* joint 4 reads beyond its upper limit: positive velocity refused */
    assert_true(roz_runtime_last_commands(&rt)[4] == 0.0);
    assert_true(FILTER_COUNT(&rt, limit_stops) > 0);
    assert_int_equal(roz_runtime_faults(&rt), 0);
}

/* A read() that takes 200 us (of the test clock): a simulator's physics
 * (ROZ_PORT_CAP_SIMULATOR) is measured but not warned about; the same read
 * on a port with a wire exceeds the 100 us read threshold. */
static roz_port_ops_t slow_ops;

static int slow_read(void *self, double *state, size_t n)
{
    clk.now += 200000;
    return roz_loopback_ops.read(self, state, n);
}

static void run_slow(uint32_t caps, roz_monitor_stat_t *out)
{
    roz_runtime_config_t cfg;
    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_loopback_config(&cfg, &lb, &roz_manifest_ur5, NULL, &clk);
    slow_ops = roz_loopback_ops;
    slow_ops.read = slow_read;
    slow_ops.caps = caps;
    cfg.port.ops = &slow_ops;
    roz_test_runtime_start(&rt, &cfg, NULL);
    ticks(20);
    assert_int_equal(roz_monitor_snapshot(roz_runtime_monitor(&rt), ROZ_MON_READ, out), ROZ_OK);
    roz_runtime_deinit(&rt);
}

static void test_runtime_simulator_read_not_warned(void **st)
{
    roz_monitor_stat_t sim, wire;
    (void)st;
    run_slow(ROZ_PORT_CAP_SIMULATOR, &sim);
    assert_int_equal(sim.count, 20);
    assert_true(sim.max_ns >= 200000);
    assert_int_equal(sim.exceeded, 0);
    assert_int_equal(sim.warned, 0);
    run_slow(0, &wire);
    assert_int_equal(wire.count, 20);
    assert_int_equal(wire.exceeded, 20);
    assert_true(wire.warned >= 1);
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_runtime_sine_drives_ur5, teardown),
              cmocka_unit_test_teardown(test_runtime_nothing_before_first_state, teardown),
              cmocka_unit_test_teardown(test_runtime_waiting_is_not_a_fault, teardown),
              cmocka_unit_test_teardown(test_runtime_trap_latches_controlled_stop, teardown),
              cmocka_unit_test_teardown(test_runtime_controlled_stop_ramps, teardown),
              cmocka_unit_test_teardown(test_runtime_estop_is_immediate, teardown),
              cmocka_unit_test_teardown(test_runtime_controller_estop, teardown),
              cmocka_unit_test_teardown(test_runtime_overrun, teardown),
              cmocka_unit_test_teardown(test_runtime_verify_refuses, teardown),
              cmocka_unit_test_teardown(test_runtime_swap_keeps_old_on_failure, teardown),
              cmocka_unit_test_teardown(test_runtime_g1_stand, teardown),
              cmocka_unit_test_teardown(test_runtime_swap_starts_at_the_hold, teardown),
              cmocka_unit_test_teardown(test_runtime_operator_inputs, teardown),
              cmocka_unit_test_teardown(test_runtime_operator_remote, teardown),
              cmocka_unit_test_teardown(test_runtime_remote_estop, teardown),
              cmocka_unit_test_teardown(test_runtime_first_tick_holds, teardown),
              cmocka_unit_test_teardown(test_runtime_nan_and_range_states, teardown),
              cmocka_unit_test(test_runtime_simulator_read_not_warned))
