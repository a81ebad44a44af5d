/* SPDX-License-Identifier: Apache-2.0 */
/* The safety filter, as tables: one row per rule, on the UR5 (velocity
 * commands paired with positions) and the G1 (position, gains, effort); and
 * per-channel limit margins on a gripper whose range is 8 cm. */
/* white-box: this test reads the private fields of the module it tests */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/filter.h"
#include "support.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

static roz_filter_t f;
static double target[ROZ_CFG_MAX_COMMANDS], state[ROZ_CFG_MAX_STATES], out[ROZ_CFG_MAX_COMMANDS];

typedef struct {
    const char *rule;
    int         ch;        /* command channel */
    double      last;      /* last applied value (primed) */
    double      pos;       /* paired position state value */
    double      target;
    roz_stop_t  stop;
    double      expect;
    int         clamps, rate_caps, limit_stops, nonfinite;
} row_t;

#define UR5_J3 ROZ_UR5_CMD_WRIST_1_JOINT_VELOCITY /* +-3.14, rate 0.5, pos +-2pi */
#define TWO_PI 6.283185307179586

static const row_t ur5_rows[] = {
    /* rule                          ch      last  pos   target  stop                 expect clamp cap lim nf */
    { "in range passes",              UR5_J3, 0.0,  0.0,  0.3,    ROZ_STOP_NONE,       0.3,   0, 0, 0, 0 },
    { "clamp above max",              UR5_J3, 3.0,  0.0,  9.0,    ROZ_STOP_NONE,       3.14,  1, 0, 0, 0 },
    { "clamp below min",              UR5_J3, -3.0, 0.0,  -9.0,   ROZ_STOP_NONE,       -3.14, 1, 0, 0, 0 },
    { "rate cap up",                  UR5_J3, 0.0,  0.0,  2.0,    ROZ_STOP_NONE,       0.5,   0, 1, 0, 0 },
    { "rate cap down",                UR5_J3, 1.0,  0.0,  -1.0,   ROZ_STOP_NONE,       0.5,   0, 1, 0, 0 },
    { "clamp then rate cap",          UR5_J3, 0.0,  0.0,  100.0,  ROZ_STOP_NONE,       0.5,   1, 1, 0, 0 },
    { "NaN target -> default, capped",UR5_J3, 0.4,  0.0,  NAN,    ROZ_STOP_NONE,       0.0,   0, 0, 0, 1 },
    { "inf target -> default",        UR5_J3, 0.0,  0.0,  INFINITY, ROZ_STOP_NONE,     0.0,   0, 0, 0, 1 },
    { "limit: at upper margin stops", UR5_J3, 0.0,  TWO_PI - 0.05, 0.3, ROZ_STOP_NONE, 0.0,   0, 0, 1, 0 },
    { "limit: outside, moving out",   UR5_J3, 0.0,  7.0,  0.2,    ROZ_STOP_NONE,       0.0,   0, 0, 1, 0 },
    { "limit: outside, moving back",  UR5_J3, 0.0,  7.0,  -0.2,   ROZ_STOP_NONE,       -0.2,  0, 0, 0, 0 },
    { "limit: below, moving out",     UR5_J3, 0.0,  -7.0, -0.2,   ROZ_STOP_NONE,       0.0,   0, 0, 1, 0 },
    { "limit: near, slowed",          UR5_J3, 0.0,  TWO_PI - 0.051, 0.5, ROZ_STOP_NONE, 0.0,  0, 0, 1, 0 },
    { "limit: far, untouched",        UR5_J3, 0.0,  0.0,  -0.5,   ROZ_STOP_NONE,       -0.5,  0, 0, 0, 0 },
    { "controlled stop ramps",        UR5_J3, 2.0,  0.0,  3.0,    ROZ_STOP_CONTROLLED, 1.5,   0, 1, 0, 0 },
    { "e-stop is immediate",          UR5_J3, 2.0,  0.0,  3.0,    ROZ_STOP_IMMEDIATE,  0.0,   0, 0, 0, 0 },
};

static void run_rows(const roz_manifest_t *m, const row_t *rows, size_t n)
{
    for (size_t r = 0; r < n; r++) {
        const row_t *row = &rows[r];
        const roz_channel_t *c = &m->commands[row->ch];
        print_message("row: %s\n", row->rule);
        assert_int_equal(roz_filter_init(&f, m), ROZ_OK);
        for (uint16_t s = 0; s < m->n_states; s++)
            state[s] = m->states[s].default_value;
        if (c->position_state >= 0)
            state[c->position_state] = row->pos;
        roz_filter_prime(&f, state);
        for (uint16_t i = 0; i < m->n_commands; i++) /* every channel at its safe default */
            target[i] = f.last[i] = roz_filter_safe_default(&f, i, state);
        f.last[row->ch] = row->last;
        target[row->ch] = row->target;
        roz_filter_apply(&f, target, state, row->stop, out);
        assert_near(out[row->ch], row->expect, 1e-12);
        assert_int_equal(f.counters.clamps, row->clamps);
        assert_int_equal(f.counters.rate_caps, row->rate_caps);
        assert_int_equal(f.counters.limit_stops, row->limit_stops);
        assert_int_equal(f.counters.nonfinite, row->nonfinite);
        assert_int_equal(f.channel_clamps[row->ch], row->clamps);
        for (uint16_t i = 0; i < m->n_commands; i++)
            assert_true(out[i] >= m->commands[i].min && out[i] <= m->commands[i].max);
    }
}

static void test_filter_ur5(void **st)
{
    (void)st;
    run_rows(&roz_manifest_ur5, ur5_rows, sizeof ur5_rows / sizeof ur5_rows[0]);
}

#define G1_KNEE_POS ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_POSITION   /* [-0.087267, 2.8798] */
#define G1_KNEE_KP ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_STIFFNESS   /* [0, 200], rate 0.8 */
#define G1_KNEE_KD ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_DAMPING     /* [0, 10], default 8 */
#define G1_KNEE_TAU ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_EFFORT     /* +-139, rate 1.39 */
#define G1_KNEE_VEL ROZ_UNITREE_G1_CMD_LEFT_KNEE_JOINT_VELOCITY

static const row_t g1_rows[] = {
    /* rule                             ch           last  pos   target stop                 expect clamp cap lim nf */
    { "position clamp to URDF upper",    G1_KNEE_POS, 2.87, 2.87, 3.5,  ROZ_STOP_NONE,       2.8798, 1, 0, 0, 0 },
    { "position target rate cap",        G1_KNEE_POS, 0.0,  0.0,  1.0,  ROZ_STOP_NONE,       0.04,  0, 1, 0, 0 },
    { "NaN position holds the state",    G1_KNEE_POS, 0.5,  0.5,  NAN,  ROZ_STOP_NONE,       0.5,   0, 0, 0, 1 },
    /* safe_default "hold": the setpoint, within 5 rate caps (0.2 rad) of the joint */
    { "stop: position holds its setpoint", G1_KNEE_POS, 0.51, 0.5, 2.0, ROZ_STOP_CONTROLLED, 0.51,  0, 0, 0, 0 },
    { "e-stop: setpoint near the joint", G1_KNEE_POS, 2.0,  0.7,  2.0,  ROZ_STOP_IMMEDIATE,  0.9,   0, 0, 0, 0 },
    { "stop, NaN position: keeps target", G1_KNEE_POS, 1.2, NAN,  2.0,  ROZ_STOP_CONTROLLED, 1.2,   0, 0, 0, 0 },
    { "e-stop, NaN position: keeps target", G1_KNEE_POS, 1.2, NAN, 2.0, ROZ_STOP_IMMEDIATE,  1.2,   0, 0, 0, 0 },
    { "stiffness never negative",        G1_KNEE_KP,  0.0,  0.0,  -5.0, ROZ_STOP_NONE,       0.0,   1, 0, 0, 0 },
    { "stiffness ramps in",              G1_KNEE_KP,  0.0,  0.0,  150.0, ROZ_STOP_NONE,      0.8,   0, 1, 0, 0 },
    { "stop: stiffness ramps to hold",   G1_KNEE_KP,  100.0, 0.0, 100.0, ROZ_STOP_CONTROLLED, 100.8, 0, 1, 0, 0 },
    { "e-stop: stiffness at hold gain",  G1_KNEE_KP,  100.0, 0.0, 100.0, ROZ_STOP_IMMEDIATE,  200.0, 0, 0, 0, 0 },
    { "damping has no cap",              G1_KNEE_KD,  0.0,  0.0,  9.0,  ROZ_STOP_NONE,       9.0,   0, 0, 0, 0 },
    { "stop: hold kd",                   G1_KNEE_KD,  1.0,  0.0,  1.0,  ROZ_STOP_CONTROLLED, 8.0,   0, 0, 0, 0 },
    { "effort clamp",                    G1_KNEE_TAU, 139.0, 0.0, 500.0, ROZ_STOP_NONE,      139.0, 1, 0, 0, 0 },
    { "effort rate cap",                 G1_KNEE_TAU, 0.0,  0.0,  50.0, ROZ_STOP_NONE,       1.39,  0, 1, 0, 0 },
    { "velocity stopped at knee limit",  G1_KNEE_VEL, 0.0,  2.8798 - 0.05, 1.0, ROZ_STOP_NONE, 0.0, 0, 0, 1, 0 },
    { "velocity back from below",        G1_KNEE_VEL, 0.0,  -0.2, 1.0,  ROZ_STOP_NONE,       1.0,   0, 0, 0, 0 },
    /* knee position [-0.087267, 2.8798], margin 0.05: effort pushing out is cut */
    { "effort out at upper limit: 0",    G1_KNEE_TAU, 1.0,  2.8798 - 0.05, 1.5, ROZ_STOP_NONE, 0.0, 0, 0, 1, 0 },
    { "effort out past upper limit: 0",  G1_KNEE_TAU, 0.5,  3.0,  0.5,  ROZ_STOP_NONE,       0.0,   0, 0, 1, 0 },
    { "effort back from upper limit",    G1_KNEE_TAU, -0.5, 3.0,  -0.5, ROZ_STOP_NONE,       -0.5,  0, 0, 0, 0 },
    { "effort out below lower limit: 0", G1_KNEE_TAU, -0.5, -0.087267 + 0.05, -0.5, ROZ_STOP_NONE, 0.0, 0, 0, 1, 0 },
    { "effort back from lower limit",    G1_KNEE_TAU, 0.5,  -0.2, 0.5,  ROZ_STOP_NONE,       0.5,   0, 0, 0, 0 },
    { "effort just inside the margin",   G1_KNEE_TAU, 0.5,  2.8798 - 0.0501, 0.5, ROZ_STOP_NONE, 0.5, 0, 0, 0, 0 },
    { "effort, position unknown: 0",     G1_KNEE_TAU, -0.5, NAN,  -0.5, ROZ_STOP_NONE,       0.0,   0, 0, 1, 0 },
};

static void test_filter_g1(void **st)
{
    (void)st;
    run_rows(&roz_manifest_unitree_g1, g1_rows, sizeof g1_rows / sizeof g1_rows[0]);
}

/* A velocity toward a limit, rate-capped, brakes in time: simulate the joint
 * under the filter at full speed and check it never crosses the limit less
 * margin, and every change stays within max_rate. */
static void test_filter_brakes_before_limit(void **st)
{
    const roz_manifest_t *m = &roz_manifest_ur5;
    const double dt = 1.0 / m->control_rate_hz;
    (void)st;
    assert_int_equal(roz_filter_init(&f, m), ROZ_OK);
    memset(state, 0, sizeof state);
    state[3] = 5.0;
    roz_filter_prime(&f, state);
    for (int i = 0; i < 6; i++)
        target[i] = 0.0;
    double prev = 0.0;
    for (int t = 0; t < 2000; t++) {
        target[3] = 3.14;
        roz_filter_apply(&f, target, state, ROZ_STOP_NONE, out);
        assert_true(fabs(out[3] - prev) <= 0.5 + 1e-12);
        prev = out[3];
        state[3] += out[3] * dt;
        assert_true(state[3] <= TWO_PI - 0.05 + 1e-9);
    }
    assert_true(state[3] > TWO_PI - 0.05 - 0.02); /* and it got close */
}

/* A gripper, limits [0, 0.08] m. roz's old margin, 0.05 whatever the unit,
 * stopped it at 0.03 m for good; now each position state has its own. */
static roz_channel_t grip_cmd[] = {
    { .name = "gripper/velocity", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -0.05,
      .max = 0.05, .default_value = 0.0, .max_rate = 0.0, .position_state = 0 },
};
static roz_channel_t grip_state[] = {
    { .name = "gripper/position", .type = ROZ_IF_POSITION, .unit = "m", .min = 0.0, .max = 0.08,
      .default_value = 0.04, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_manifest_t gripper = { "gripper", "gripper", 100, grip_cmd, 1, grip_state, 1,
                                        NULL, NULL, 0, 0, NULL, NULL };

typedef struct {
    const char *what;
    double      margin;   /* the state's limit_margin; 0 = the default */
    double      max_rate; /* of the command */
    double      lo, hi;   /* where the gripper comes to rest: [min + margin, max - margin] */
} margin_row_t;

static const margin_row_t margin_rows[] = {
    /* what                          margin   max_rate  lo       hi */
    { "default: 5 % of 8 cm",        0.0,     0.0,      0.004,   0.076 },
    { "default, rate-capped",        0.0,     0.002,    0.004,   0.076 },
    { "its own 1 cm",                0.01,    0.0,      0.01,    0.07 },
    { "its own, 0.2 mm of room",     0.0399,  0.0,      0.0399,  0.0401 },
};

/* Drives the gripper at full speed toward one end for n ticks; returns
 * where it ends, checking it never passes the end less the margin. */
static double drive(double speed, double lo, double hi, int n)
{
    const double dt = 1.0 / gripper.control_rate_hz;
    for (int t = 0; t < n; t++) {
        target[0] = speed;
        roz_filter_apply(&f, target, state, ROZ_STOP_NONE, out);
        state[0] += out[0] * dt;
        assert_true(state[0] <= hi + 1e-12 && state[0] >= lo - 1e-12);
    }
    return state[0];
}

static void test_filter_margin_per_channel(void **st)
{
    (void)st;
    for (size_t r = 0; r < sizeof margin_rows / sizeof margin_rows[0]; r++) {
        const margin_row_t *row = &margin_rows[r];
        print_message("row: %s\n", row->what);
        grip_state[0].limit_margin = row->margin;
        grip_cmd[0].max_rate = row->max_rate;
        assert_int_equal(roz_filter_init(&f, &gripper), ROZ_OK);
        state[0] = 0.04;
        roz_filter_prime(&f, state);

        /* open: it gets to the end less the margin (within 0.1 mm), and
         * stays; every tick it pushes there is a limit stop in a row */
        roz_filter_channel_counters_t cc;
        double open = drive(0.05, row->lo, row->hi, 400);
        print_message("  opens to %.6f m, closes to ", open);
        assert_true(open > row->hi - 1e-4);
        assert_int_equal(roz_filter_channel_counters_get(&f, 0, &cc), ROZ_OK);
        assert_true(cc.stop_run > 300 && cc.stop_run <= 400); /* 3.6 cm: ~72 ticks */
        assert_int_equal(cc.stop_longest, cc.stop_run);
        uint32_t longest = cc.stop_longest;

        /* and it moves again: closing is not held back until the other end
         * (unless the room is less than a tick of travel, 0.5 mm) */
        drive(-0.05, row->lo, row->hi, 1);
        assert_int_equal(roz_filter_channel_counters_get(&f, 0, &cc), ROZ_OK);
        if (row->hi - row->lo > 0.0005)
            assert_int_equal(cc.stop_run, 0);
        double closed = drive(-0.05, row->lo, row->hi, 399);
        print_message("%.6f m\n", closed);
        assert_true(closed < row->lo + 1e-4);
        assert_int_equal(roz_filter_channel_counters_get(&f, 0, &cc), ROZ_OK);
        assert_true(cc.stop_run > 200); /* 7.2 cm take ~144 of the 400 ticks */
        if (row->hi - row->lo > 0.0005) {
            assert_int_equal(cc.stop_longest, longest);
            assert_int_equal(cc.limit_stops, cc.stop_run + longest);
        } else {
            assert_int_equal(cc.stop_run, 800); /* held back every tick */
        }
    }
    grip_state[0].limit_margin = 0.0;
    grip_cmd[0].max_rate = 0.0;
}

/* A hold (the G1's position commands: safe_default "hold") latches at a
 * stop's first tick and keeps that value while the joint moves under it,
 * whatever the stop; the first tick without a stop releases it, and the
 * next stop latches again. Before, the stop's position followed the joint
 * down (the damping mode). */
static void test_filter_hold_latches(void **st)
{
    const roz_manifest_t *m = &roz_manifest_unitree_g1;
    const uint16_t knee = G1_KNEE_POS;
    const int s = m->commands[knee].position_state;
    (void)st;
    assert_int_equal(m->commands[knee].safe_default, ROZ_SAFE_HOLD);
    assert_int_equal(roz_filter_init(&f, m), ROZ_OK);
    for (uint16_t i = 0; i < m->n_states; i++)
        state[i] = 0.0;
    state[s] = 0.3;
    roz_filter_prime(&f, state);
    /* the knee held at the hold gain (its stiffness's safe default): the
     * torque kept is the setpoint's own */
    const uint16_t kpi = f.hold_kp[knee];
    assert_int_equal(m->commands[kpi].type, ROZ_IF_STIFFNESS);
    const double kp_hold = m->commands[kpi].default_value;
    assert_true(kp_hold > 0.0);
    f.last[kpi] = kp_hold;
    memcpy(target, f.last, sizeof target);
    target[knee] = 0.34; /* the setpoint; the joint sags below it */
    roz_filter_apply(&f, target, state, ROZ_STOP_NONE, out);
    const double sp = out[knee];
    assert_near(sp, 0.34, 1e-12);
    for (int t = 0; t < 50; t++) { /* the joint sinks; the hold stays */
        state[s] = 0.3 - 0.01 * t;
        roz_filter_apply(&f, target, state, t < 25 ? ROZ_STOP_IMMEDIATE : ROZ_STOP_CONTROLLED,
                         out);
        assert_near(out[knee], sp, 0.0);
        assert_near(roz_filter_safe_default(&f, knee, state), sp, 0.0);
        target[knee] = NAN; /* a non-finite target during the stop is the hold too */
    }
    /* released: the running rule again, the safe default follows the joint */
    target[knee] = 0.1;
    state[s] = -0.05;
    roz_filter_apply(&f, target, state, ROZ_STOP_NONE, out);
    assert_near(out[knee], 0.30, 1e-12); /* 0.34 less one rate cap toward 0.1 */
    assert_near(roz_filter_safe_default(&f, knee, state), -0.05, 0.0);
    /* the next stop latches the new setpoint, within 5 rate caps of the joint */
    roz_filter_apply(&f, target, state, ROZ_STOP_IMMEDIATE, out);
    assert_near(out[knee], -0.05 + 5 * 0.04, 1e-12);
    /* the position unknown at the latch: the last setpoint, as the follow rule */
    roz_filter_apply(&f, target, state, ROZ_STOP_NONE, out);
    state[s] = NAN;
    roz_filter_apply(&f, target, state, ROZ_STOP_CONTROLLED, out);
    assert_near(out[knee], f.hold[knee], 0.0);
    assert_true(isfinite(out[knee]));
    /* a soft gain (a quarter of the hold gain): the hold keeps its torque,
     * kp_hold * (hold - q) = kp_was * (setpoint - q), so a balancing stand's
     * offset setpoints do not push it over (test_mujoco_stops_g1) */
    state[s] = 0.3;
    target[knee] = 0.34;
    target[kpi] = kp_hold / 4.0;
    roz_filter_apply(&f, target, state, ROZ_STOP_NONE, out);
    f.last[kpi] = kp_hold / 4.0; /* past its rate cap, as a controller that ramped it */
    f.last[knee] = 0.34;
    roz_filter_apply(&f, target, state, ROZ_STOP_IMMEDIATE, out);
    assert_near(out[knee], 0.3 + 0.04 / 4.0, 1e-12);
    assert_near(out[kpi], kp_hold, 0.0);
}

static void test_filter_init_errors(void **st)
{
    roz_manifest_t bad = roz_manifest_ur5;
    (void)st;
    bad.control_rate_hz = 0;
    assert_int_equal(roz_filter_init(&f, &bad), ROZ_EINVAL);
    assert_int_equal(roz_filter_init(NULL, &roz_manifest_ur5), ROZ_EINVAL);
    assert_int_equal(roz_filter_init(&f, &roz_manifest_ur5), ROZ_OK);
    /* a margin that leaves the gripper no room to move is refused */
    grip_state[0].limit_margin = 0.04;
    assert_int_equal(roz_filter_init(&f, &gripper), ROZ_EINVAL);
    grip_state[0].limit_margin = -0.001;
    assert_int_equal(roz_filter_init(&f, &gripper), ROZ_EINVAL);
    grip_state[0].limit_margin = 0.0;
    assert_int_equal(roz_filter_init(&f, &gripper), ROZ_OK);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_filter_ur5),
              cmocka_unit_test(test_filter_g1),
              cmocka_unit_test(test_filter_brakes_before_limit),
              cmocka_unit_test(test_filter_margin_per_channel),
              cmocka_unit_test(test_filter_hold_latches),
              cmocka_unit_test(test_filter_init_errors))
