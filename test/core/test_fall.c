/* SPDX-License-Identifier: Apache-2.0 */
/* Falls (roz/fall.h, SAFETY.md "Falls"): the tilt of the base from its
 * quaternion; the rule's time counted in ticks in a row; the rule's checks
 * in roz_manifest_validate(); the filter's fallen stop (every stiffness 0
 * at once, the damping default, positions following the measured ones,
 * never a hold); and in the runtime, on a one-joint humanoid whose IMU the
 * test tilts: FALL latches after the rule's time and not a tick before,
 * the controller stops, every command after the latch is damping, the
 * fallen stop wins over an e-stop, a clear while the robot is still down
 * is followed by the next tick's latch, and one after it is up again
 * clears. */
/* white-box in part: the runtime's faults word (the latch number above
 * the bits) */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/fall.h"
#include "roz/filter.h"
#include "roz/runtime.h"
#include "roz_math.h"
#include "support.h"
#include "support_runtime.h"
#include "support_wat.h"

/* ---- a one-joint humanoid with an IMU ------------------------------------------- */

enum { C_Q, C_DQ, C_KP, C_KD, C_TAU, N_CMD };
enum { S_Q, S_DQ, S_QX, S_QY, S_QZ, S_QW, N_ST };

#define KD_DAMP 8.0 /* the damping command's default: the damping mode's kd */

static const roz_channel_t commands[N_CMD] = {
    { .name = "knee/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -2.0, .max = 2.0,
      .default_value = 0.0, .max_rate = 0.04, .position_state = S_Q,
      .safe_default = ROZ_SAFE_HOLD },
    { .name = "knee/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -20.0,
      .max = 20.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "knee/stiffness", .type = ROZ_IF_STIFFNESS, .unit = "N*m/rad", .min = 0.0,
      .max = 200.0, .default_value = 150.0, .max_rate = 0.8,
      .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "knee/damping", .type = ROZ_IF_DAMPING, .unit = "N*m*s/rad", .min = 0.0,
      .max = 10.0, .default_value = KD_DAMP, .max_rate = 0.0,
      .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "knee/effort", .type = ROZ_IF_EFFORT, .unit = "N*m", .min = -50.0, .max = 50.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
/* The IMU's orientation quaternion component @p axis, upright by default. */
#define ORIENTATION(axis, upright)                                                       \
    { .name = "imu/orientation." axis, .type = ROZ_IF_ORIENTATION, .unit = "", .min = -1.0, \
      .max = 1.0, .default_value = (upright), .max_rate = 0.0, \
      .position_state = ROZ_CHANNEL_UNPAIRED }
static const roz_channel_t states[N_ST] = {
    { .name = "knee/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -2.0, .max = 2.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "knee/velocity", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -20.0,
      .max = 20.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    ORIENTATION("x", 0.0),
    ORIENTATION("y", 0.0),
    ORIENTATION("z", 0.0),
    ORIENTATION("w", 1.0),
};

/* down beyond 1 rad for 20 ms: 10 ticks at 500 Hz */
#define PI 3.14159265358979323846
#define RATE 500
#define NEED 10
static roz_fall_rule_t rule = { "imu/orientation", { S_QX, S_QY, S_QZ, S_QW }, 1.0, 20 };
static roz_manifest_t manifest = {
    .robot_id = "fall_leg", .robot_class = "humanoid", .control_rate_hz = RATE,
    .commands = commands, .n_commands = N_CMD, .states = states, .n_states = N_ST,
    .fall = &rule,
};

/* The quaternion of a rotation by @p angle about the unit axis (ax, ay, az). */
static void tilt_to(double *s, double angle, double ax, double ay, double az)
{
    s[S_QX] = ax * sin(angle / 2.0);
    s[S_QY] = ay * sin(angle / 2.0);
    s[S_QZ] = az * sin(angle / 2.0);
    s[S_QW] = cos(angle / 2.0);
}

/* ---- the tilt and the time -------------------------------------------------------- */

static void test_fall_tilt(void **unused)
{
    (void)unused;
    double s[N_ST] = { 0 };
    tilt_to(s, 0.0, 1.0, 0.0, 0.0);
    assert_true(roz_fall_tilt(&rule, s) == 0.0);
    /* about x, about y, about a tilted axis: the angle; about z: none */
    tilt_to(s, 0.7, 1.0, 0.0, 0.0);
    assert_true(fabs(roz_fall_tilt(&rule, s) - 0.7) < 1e-12);
    tilt_to(s, -1.2, 0.0, 1.0, 0.0);
    assert_true(fabs(roz_fall_tilt(&rule, s) - 1.2) < 1e-12);
    tilt_to(s, 0.9, sqrt(0.5), sqrt(0.5), 0.0);
    assert_true(fabs(roz_fall_tilt(&rule, s) - 0.9) < 1e-12);
    tilt_to(s, 2.5, 0.0, 0.0, 1.0);
    assert_true(fabs(roz_fall_tilt(&rule, s)) < 1e-12);
    /* upside down; a quaternion not of unit length: its direction */
    tilt_to(s, PI, 1.0, 0.0, 0.0);
    assert_true(fabs(roz_fall_tilt(&rule, s) - PI) < 1e-7);
    tilt_to(s, 0.7, 0.0, 1.0, 0.0);
    for (int k = S_QX; k <= S_QW; k++)
        s[k] *= 3.0;
    assert_true(fabs(roz_fall_tilt(&rule, s) - 0.7) < 1e-12);
    /* unknown: not finite, or no direction */
    s[S_QY] = NAN;
    assert_true(isnan(roz_fall_tilt(&rule, s)));
    s[S_QX] = s[S_QY] = s[S_QZ] = s[S_QW] = 0.0;
    assert_true(isnan(roz_fall_tilt(&rule, s)));
    s[S_QW] = INFINITY;
    assert_true(isnan(roz_fall_tilt(&rule, s)));
}

/* Down after NEED tilted ticks in a row, not one before; an upright tick
 * starts the count again; an unknown one leaves it; a level while down. */
static void test_fall_ticks_in_a_row(void **unused)
{
    (void)unused;
    roz_fall_t f;
    double s[N_ST] = { 0 };
    roz_fall_init(&f, &manifest);

    tilt_to(s, 1.01, 1.0, 0.0, 0.0);
    for (int i = 0; i < NEED - 1; i++)
        assert_int_equal(roz_fall_tick(&f, s), 0);
    tilt_to(s, 0.99, 1.0, 0.0, 0.0); /* within the angle: the count restarts */
    assert_int_equal(roz_fall_tick(&f, s), 0);
    tilt_to(s, 1.01, 0.0, 1.0, 0.0);
    for (int i = 0; i < NEED - 1; i++)
        assert_int_equal(roz_fall_tick(&f, s), 0);
    s[S_QX] = NAN; /* unknown: neither counts nor restarts */
    assert_int_equal(roz_fall_tick(&f, s), 0);
    tilt_to(s, 1.01, 0.0, 1.0, 0.0);
    assert_int_equal(roz_fall_tick(&f, s), 1);
    assert_int_equal(roz_fall_tick(&f, s), 1); /* a level */
    tilt_to(s, 0.2, 0.0, 1.0, 0.0);
    assert_int_equal(roz_fall_tick(&f, s), 0);

    /* for_ms 0 and 1 at 500 Hz: one tick; no rule: never */
    roz_fall_rule_t quick = rule;
    roz_manifest_t m = manifest;
    m.fall = &quick;
    quick.for_ms = 0;
    roz_fall_init(&f, &m);
    tilt_to(s, 3.0, 1.0, 0.0, 0.0);
    assert_int_equal(roz_fall_tick(&f, s), 1);
    quick.for_ms = 1;
    roz_fall_init(&f, &m);
    assert_int_equal(roz_fall_tick(&f, s), 1);
    m.fall = NULL;
    roz_fall_init(&f, &m);
    assert_int_equal(roz_fall_tick(&f, s), 0);
}

/* At the angle is not beyond it, to the last bit of the rule's angle: a
 * quarter turn about x, q = (1, 0, 0, 1), has cos(tilt) exactly 0 and a
 * tilt of pi/2 exactly. The double nearest pi/2 is below it (its cosine
 * 6.1e-17): the quarter turn is beyond it; the next double up is above pi/2
 * (cosine -1.6e-16): not beyond. The threshold is cos(max_tilt) on every
 * target (roz_math.h, no libm), so the same bit decides everywhere. */
static void test_fall_at_the_angle(void **unused)
{
    (void)unused;
    roz_fall_rule_t r = rule;
    roz_manifest_t m = manifest;
    roz_fall_t f;
    double s[N_ST] = { 0 };
    m.fall = &r;
    r.for_ms = 0;
    s[S_QX] = 1.0;
    s[S_QW] = 1.0;
    r.max_tilt = PI / 2.0;
    roz_fall_init(&f, &m);
    assert_int_equal(roz_fall_tick(&f, s), 1);
    assert_true(roz_fall_tilt(&r, s) == PI / 2.0);
    r.max_tilt = nextafter(PI / 2.0, 4.0);
    roz_fall_init(&f, &m);
    assert_int_equal(roz_fall_tick(&f, s), 0);
    /* cos(tilt) equal to the threshold, bit for bit: q = (1, 0, 0, 2) has
     * cos(tilt) 3.0 / 5.0; a limit whose roz_math_cos is that double is
     * not exceeded, the next one down (a larger cosine) is */
    s[S_QW] = 2.0;
    double at = acos(0.6);
    for (int k = 0; k < 16 && roz_math_cos(at) != 3.0 / 5.0; k++)
        at = nextafter(at, roz_math_cos(at) > 0.6 ? 4.0 : 0.0);
    assert_true(roz_math_cos(at) == 3.0 / 5.0);
    r.max_tilt = at;
    roz_fall_init(&f, &m);
    assert_true(f.cos_max == 3.0 / 5.0); /* the threshold is roz_math.h's */
    assert_int_equal(roz_fall_tick(&f, s), 0);
    r.max_tilt = nextafter(at, 0.0);
    roz_fall_init(&f, &m);
    assert_int_equal(roz_fall_tick(&f, s), 1);
    /* and either side of the test rule's 1 rad, by 1e-9 rad */
    tilt_to(s, 1.0 + 1e-9, 1.0, 0.0, 0.0);
    r.max_tilt = 1.0;
    roz_fall_init(&f, &m);
    assert_int_equal(roz_fall_tick(&f, s), 1);
    tilt_to(s, 1.0 - 1e-9, 1.0, 0.0, 0.0);
    assert_int_equal(roz_fall_tick(&f, s), 0);
}

/* ---- the rule's checks in roz_manifest_validate() ------------------------------- */

static void expect_fall_problem(const roz_manifest_t *m, int32_t index)
{
    roz_manifest_problem_t p;
    assert_int_equal(roz_manifest_validate(m, &p), ROZ_EINVAL);
    assert_int_equal(p.rule, ROZ_MANIFEST_RULE_FALL);
    assert_int_equal(p.index, index);
}

static void test_fall_validate(void **unused)
{
    (void)unused;
    roz_manifest_problem_t p;
    roz_fall_rule_t r = rule;
    roz_manifest_t m = manifest;
    roz_channel_t c[N_CMD];
    m.fall = &r;
    assert_int_equal(roz_manifest_validate(&m, &p), ROZ_OK);

    r.quaternion[1] = N_ST; /* out of range */
    expect_fall_problem(&m, -1);
    r.quaternion[1] = S_Q; /* a position state */
    expect_fall_problem(&m, -1);
    r.quaternion[1] = S_QX; /* twice */
    expect_fall_problem(&m, -1);
    r = rule;
    r.max_tilt = 0.0;
    expect_fall_problem(&m, -1);
    r.max_tilt = PI;
    expect_fall_problem(&m, -1);
    r.max_tilt = NAN;
    expect_fall_problem(&m, -1);
    r = rule;
    r.for_ms = ROZ_FALL_MAX_MS + 1u;
    expect_fall_problem(&m, -1);
    r.for_ms = ROZ_FALL_MAX_MS;
    assert_int_equal(roz_manifest_validate(&m, &p), ROZ_OK);
    /* a stiffness that cannot be 0: the fallen stop could not send it */
    memcpy(c, commands, sizeof c);
    c[C_KP].min = 10.0;
    m.commands = c;
    expect_fall_problem(&m, C_KP);
    m.fall = NULL; /* without a rule, the same channel is fine */
    assert_int_equal(roz_manifest_validate(&m, &p), ROZ_OK);
}

/* ---- the filter's fallen stop ---------------------------------------------------- */

static void expect_damping(const double *out, double q)
{
    assert_true(out[C_Q] == q);
    assert_true(out[C_DQ] == 0.0);
    assert_true(out[C_KP] == 0.0);
    assert_true(out[C_KD] == KD_DAMP);
    assert_true(out[C_TAU] == 0.0);
}

/* From a stiff run, at once (no rate cap): stiffness 0, the damping
 * default, velocity and effort 0, the position command following the
 * measured position (not the hold its safe_default latches in other
 * stops). Then another stop: its hold latched anew, the stiffness from 0
 * up by its rate cap. */
static void test_fall_filter_stop(void **unused)
{
    (void)unused;
    static roz_filter_t f;
    double s[N_ST] = { 0.3, 0.0, 0.0, 0.0, 0.0, 1.0 };
    double target[N_CMD] = { 0.3, 0.0, 0.0, 2.0, 0.0 }, out[N_CMD];
    assert_int_equal(roz_filter_init(&f, &manifest), ROZ_OK);
    for (int i = 0; i < 400; i++) { /* the stiffness ramps up to 150 */
        target[C_KP] = 150.0;
        roz_filter_apply(&f, target, s, ROZ_STOP_NONE, out);
    }
    assert_true(out[C_KP] == 150.0);
    target[C_Q] = 0.5;
    target[C_TAU] = 12.0;
    roz_filter_apply(&f, target, s, ROZ_STOP_NONE, out);
    assert_true(fabs(out[C_Q] - 0.34) < 1e-12 && out[C_TAU] == 12.0); /* rate-capped */

    s[S_Q] = 0.1; /* the joint gave way */
    roz_filter_apply(&f, target, s, ROZ_STOP_FALLEN, out);
    expect_damping(out, 0.1);
    s[S_Q] = -0.4; /* it keeps following, beyond the position's rate cap */
    roz_filter_apply(&f, target, s, ROZ_STOP_FALLEN, out);
    expect_damping(out, -0.4);
    s[S_Q] = NAN; /* position unknown: the last one */
    roz_filter_apply(&f, target, s, ROZ_STOP_FALLEN, out);
    expect_damping(out, -0.4);

    /* a controlled stop after it (the fall cleared, another fault on):
     * the hold latched where the joint is, the stiffness ramping from 0 */
    s[S_Q] = -0.4;
    roz_filter_apply(&f, target, s, ROZ_STOP_CONTROLLED, out);
    assert_true(out[C_KP] == 0.8);
    assert_true(fabs(out[C_Q] - -0.4) < 1e-12);
}

/* ---- in the runtime ---------------------------------------------------------------- */

static roz_runtime_t rt;
static double st[N_ST];
static double written[N_CMD];
static uint64_t writes;

static int fp_read(void *self, double *state, size_t n)
{
    (void)self;
    memcpy(state, st, n * sizeof st[0]);
    return 1;
}

static int fp_write(void *self, const double *cmd, size_t n)
{
    (void)self;
    memcpy(written, cmd, n * sizeof cmd[0]);
    writes++;
    return ROZ_OK;
}

static const roz_port_ops_t fall_ops = { .name = "fall-test", .read = fp_read, .write = fp_write };

/* Stiff into whatever the robot does: kp 150, kd 2, the knee at 0.3. */
static const char *const stiff_wat =
    "(module\n"
    "  (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))\n"
    "  (func (export \"process\") (param $tick i64)\n"
    "    (drop (call $set (i32.const 0) (f64.const 0.3)))\n"
    "    (drop (call $set (i32.const 2) (f64.const 150)))\n"
    "    (drop (call $set (i32.const 3) (f64.const 2)))\n"
    "    (drop (call $set (i32.const 4) (f64.const 5)))))\n";

static void start(void)
{
    static uint8_t wasm[1024];
    static size_t len;
    static roz_test_clock_t clk;
    roz_runtime_config_t cfg;
    memset(st, 0, sizeof st);
    st[S_Q] = 0.3;
    st[S_QW] = 1.0;
    writes = 0;
    clk = (roz_test_clock_t){ 1000000, 1000 };
    roz_test_runtime_config(&cfg, &manifest, (roz_port_t){ &fall_ops, NULL, 0 }, &clk);
    cfg.monitor_jitter = 0;
    roz_test_runtime_start(&rt, &cfg, NULL);
    if (len == 0)
        len = roz_test_wat(stiff_wat, wasm, sizeof wasm);
    assert_int_equal(roz_runtime_load(&rt, wasm, len, NULL), ROZ_OK);
}

static int teardown(void **unused)
{
    (void)unused;
    roz_runtime_deinit(&rt);
    return 0;
}

static int tick(void)
{
    return roz_runtime_tick(&rt);
}

static void ticks(int n)
{
    for (int i = 0; i < n; i++)
        tick();
}

/* Started, standing 300 ticks, then tilted by @p angle about x for the
 * NEED ticks a fall takes. */
static void stand_then_tilt(double angle)
{
    start();
    ticks(300);
    tilt_to(st, angle, 1.0, 0.0, 0.0);
    ticks(NEED);
}

/* Standing: the controller's gains are in. Tilted NEED - 1 ticks: nothing.
 * The NEED-th: FALL, named with the tilt, and from that tick on every
 * command is damping and the controller never runs. */
static void test_fall_runtime_latches_and_damps(void **unused)
{
    (void)unused;
    start();
    for (int i = 0; i < 300; i++)
        assert_int_equal(tick(), ROZ_OK);
    assert_true(written[C_KP] == 150.0 && written[C_KD] == 2.0 && written[C_TAU] == 5.0);

    tilt_to(st, 1.2, 0.0, 1.0, 0.0);
    for (int i = 0; i < NEED - 1; i++) {
        assert_int_equal(tick(), ROZ_OK);
        assert_true(written[C_KP] == 150.0);
    }
    uint64_t calls = rt.counters.controller_ticks;
    st[S_Q] = 0.9;
    assert_int_equal(tick(), ROZ_EFAULT);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_FALL);
    assert_int_equal(rt.counters.controller_ticks, calls); /* it did not run */
    expect_damping(written, 0.9);
    assert_string_equal(roz_fault_name(ROZ_FAULT_FALL), "fall");
    assert_string_equal(roz_runtime_fault_message(&rt),
                        "fall: the base tilted 1200 mrad from upright, beyond the fall rule's "
                        "1000 mrad (manifest.fall): the fallen stop, zero stiffness and the "
                        "manifest's damping");
    for (int i = 0; i < 200; i++) {
        st[S_Q] = 0.9 - 0.005 * i;
        assert_int_equal(tick(), ROZ_EFAULT);
        expect_damping(written, st[S_Q]);
    }
    assert_int_equal(rt.counters.controller_ticks, calls);
    assert_int_equal(rt.counters.faults[8], 1);
}

/* The fallen stop wins over the e-stop's (whose hold is stiff), both
 * ways round. */
static void test_fall_runtime_beats_estop(void **unused)
{
    (void)unused;
    start();
    ticks(300);
    roz_runtime_estop_set(&rt, 1);
    tick();
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    assert_true(written[C_KP] > 0.0); /* the e-stop's hold gain */
    tilt_to(st, 1.6, 1.0, 0.0, 0.0);
    ticks(NEED);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP | ROZ_FAULT_FALL);
    expect_damping(written, st[S_Q]);
    roz_runtime_estop_set(&rt, 0);
    teardown(NULL);

    stand_then_tilt(1.6);
    roz_runtime_estop(&rt);
    tick();
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP | ROZ_FAULT_FALL);
    expect_damping(written, st[S_Q]);
}

/* A level: cleared while still down, FALL latches again at the next tick
 * (no stiff tick between); cleared once the robot is up, it clears, and
 * the controller's gains come back by the stiffness's rate cap from 0. */
static void test_fall_runtime_clear(void **unused)
{
    (void)unused;
    stand_then_tilt(1.4);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_FALL);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    assert_int_equal(tick(), ROZ_EFAULT);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_FALL);
    expect_damping(written, st[S_Q]);
    assert_int_equal(rt.counters.faults[8], 2);

    tilt_to(st, 0.1, 1.0, 0.0, 0.0); /* picked up */
    tick();
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_FALL);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    assert_int_equal(tick(), ROZ_OK);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_true(written[C_KP] == 0.8); /* from 0, by the rate cap */
}

/* A manifest without a rule: tilted as far as it goes, nothing latches. */
static void test_fall_runtime_without_rule(void **unused)
{
    (void)unused;
    manifest.fall = NULL;
    start();
    tilt_to(st, 3.0, 1.0, 0.0, 0.0);
    for (int i = 0; i < 300; i++)
        assert_int_equal(tick(), ROZ_OK);
    assert_true(written[C_KP] == 150.0);
    manifest.fall = &rule;
}

ROZ_TEST_MAIN(cmocka_unit_test(test_fall_tilt),
              cmocka_unit_test(test_fall_ticks_in_a_row),
              cmocka_unit_test(test_fall_at_the_angle),
              cmocka_unit_test(test_fall_validate),
              cmocka_unit_test(test_fall_filter_stop),
              cmocka_unit_test_teardown(test_fall_runtime_latches_and_damps, teardown),
              cmocka_unit_test_teardown(test_fall_runtime_beats_estop, teardown),
              cmocka_unit_test_teardown(test_fall_runtime_clear, teardown),
              cmocka_unit_test_teardown(test_fall_runtime_without_rule, teardown))
