/* SPDX-License-Identifier: Apache-2.0 */
/* Falls judged in physics (SAFETY.md, "Falls"): the 29-DoF G1 on the
 * example balancing stand (examples/controllers/g1_stand.c) behind the
 * runtime, in MuJoCo's simulated time, pushed at the pelvis 3 s in.
 *
 * - Pushed over: the built-in manifest's fall rule latches FALL before
 *   anything but the feet touches the ground, and every command from the
 *   latch on is the fallen stop's damping (kp 0, the manifest's kd, no
 *   velocity or effort, the position where the joint is), on every joint,
 *   to the end. The peak joint speed on the impact is recorded, and the
 *   same push under the same manifest without its fall rule (the stand
 *   pushing stiffly into the ground) beside it.
 * - A stumble it recovers from (0.9 times the largest push the stand
 *   survives, test_mujoco_stand.c) latches nothing.
 *
 * Bounds come from the figures measured here (printed by each run), with
 * the margins named where they are asserted; nothing is timed by a clock. */
/* white-box in part: reads the port's truth history (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/builtin.h"
#include "roz/port/mujoco.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"

#define RATE       500
#define PUSH_AT    1500 /* tick: 3 s in, 2 s after g1_stand's gains are in */
#define PUSH_TICKS 50   /* 0.1 s */
#define AFTER      1500 /* ticks judged after the push: 3 s */
#define N_JOINTS   29

/* The pushes, N for 0.1 s at the pelvis, forward (+x). OVER fells the
 * stand; STUMBLE is 0.9 times the largest it survives (G1_PUSH_X of
 * test_mujoco_stand.c, 125 N). */
#define PUSH_OVER    400.0
#define PUSH_STUMBLE 112.0

static roz_mujoco_t mj;
static roz_runtime_t rt;

typedef struct {
    long     latch;        /* tick FALL latched, -1 none */
    long     impact;       /* first tick after the push with a body but the feet on the ground */
    char     first_body[ROZ_MUJOCO_NAME_MAX]; /* that body */
    double   tilt_at_latch; /* rad, the base's (truth) */
    double   height_at_latch; /* m, the pelvis's */
    double   max_tilt;     /* rad, the base's largest tilt after the push */
    double   peak_impact;  /* rad/s, the fastest joint within 0.5 s of the impact */
    int      peak_joint;
    double   peak_tau;     /* N*m, the largest motor torque within 0.5 s of the impact */
    int      tau_joint;
    double   lying_tau;    /* N*m, the motors' torques summed over the joints, on average
                              from 0.5 s after the impact to the end: what pushes into the
                              ground once the robot lies there */
    double   lying_speed;  /* rad/s, the fastest joint over that time */
    double   lowest;       /* m, the pelvis */
    long     not_damping;  /* commands after the latch that were not the fallen stop's */
    char     first_bad[160];
    unsigned faults;
} fall_run_t;

static int is_foot(const char *body)
{
    return !strcmp(body, "left_ankle_roll_link") || !strcmp(body, "right_ankle_roll_link");
}

/* The truth sample of the last read (before any fault or latency). */
static const double *truth(void)
{
    return mj.hist[(mj.tick - 1) % (ROZ_MUJOCO_MAX_DELAY + 1)];
}

/* The base's tilt from the vertical (its z axis), from MuJoCo's quaternion. */
static double base_tilt(const roz_mujoco_base_t *b)
{
    double w = b->quat[0], x = b->quat[1], y = b->quat[2], z = b->quat[3];
    double c = (w * w + z * z - x * x - y * y) / (w * w + x * x + y * y + z * z);
    return acos(c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c);
}

/* Whether @p cmd is the fallen stop for @p state on every joint; the
 * first difference into r->first_bad. Channel blocks: position, velocity,
 * stiffness, damping, effort (manifests/unitree_g1.toml). */
static int is_damping(const roz_manifest_t *m, const double *cmd, const double *state, long t,
                      fall_run_t *r)
{
    for (int k = 0; k < N_JOINTS; k++) {
        const roz_channel_t *qc = &m->commands[k];
        double q = state[k] < qc->min ? qc->min : state[k] > qc->max ? qc->max : state[k];
        double kd = m->commands[3 * N_JOINTS + k].default_value;
        if (cmd[2 * N_JOINTS + k] != 0.0 || cmd[3 * N_JOINTS + k] != kd ||
            cmd[N_JOINTS + k] != 0.0 || cmd[4 * N_JOINTS + k] != 0.0 || cmd[k] != q) {
            if (r->first_bad[0] == '\0')
                snprintf(r->first_bad, sizeof r->first_bad,
                         "tick %ld, %s: q %.4f (measured %.4f), dq %.3f, kp %.3f, kd %.3f, "
                         "tau %.3f", t, qc->name, cmd[k], state[k], cmd[N_JOINTS + k],
                         cmd[2 * N_JOINTS + k], cmd[3 * N_JOINTS + k], cmd[4 * N_JOINTS + k]);
            return 0;
        }
    }
    return 1;
}

/* g1_stand on @p m, pushed at the pelvis by (fx, fy) N at PUSH_AT. */
static fall_run_t run(const roz_manifest_t *m, double fx, double fy, const char *name)
{
    char kv[128], err[512] = "";
    double push = sqrt(fx * fx + fy * fy);
    snprintf(kv, sizeof kv, "%.3f,%.3f,0@pelvis@%d:%d", fx, fy, PUSH_AT, PUSH_AT + PUSH_TICKS);
    roz_param_t item = { "push", kv };
    roz_params_t params = { &item, 1 };
    roz_port_t p = roz_mujoco_port(&mj, NULL, NULL);
    if (roz_port_open(&p, m, &params, err, sizeof err) != ROZ_OK)
        fail_msg("%s", err);
    roz_runtime_config_t cfg;
    roz_test_clock_t clk = { 0, 1000 };
    roz_test_runtime_config(&cfg, m, p, &clk);
    cfg.budget_ns = UINT64_MAX; /* fuel alone: the same on every machine */
    cfg.monitor_jitter = 0;
    roz_test_runtime_start(&rt, &cfg, "g1_stand");

    fall_run_t r;
    memset(&r, 0, sizeof r);
    r.latch = -1;
    r.impact = -1;
    r.lowest = INFINITY;
    roz_mujoco_base_t b;
    long lying_ticks = 0;
    for (long t = 0; t < PUSH_AT + AFTER; t++) {
        int rc = roz_runtime_tick(&rt);
        if (rc != ROZ_OK && rc != ROZ_EFAULT)
            fail_msg("%s: tick %ld: %s", name, t, roz_strerror(rc));
        roz_mujoco_base(&mj, &b);
        unsigned faults = roz_runtime_faults(&rt);
        if (t < PUSH_AT) {
            if (faults != 0 || b.pos[2] < 0.7)
                fail_msg("%s: the stand is not up before the push (tick %ld: pelvis %.3f m, "
                         "faults 0x%x)", name, t, b.pos[2], faults);
            continue;
        }
        double tilt = base_tilt(&b);
        if (tilt > r.max_tilt)
            r.max_tilt = tilt;
        if (b.pos[2] < r.lowest)
            r.lowest = b.pos[2];
        if (r.latch < 0 && (faults & ROZ_FAULT_FALL)) {
            r.latch = t;
            r.tilt_at_latch = tilt;
            r.height_at_latch = b.pos[2];
        }
        if (r.latch >= 0 && !is_damping(m, roz_runtime_last_commands(&rt),
                                        roz_runtime_last_state(&rt), t, &r))
            r.not_damping++;
        for (uint32_t i = 0; i < b.n_bodies && r.impact < 0; i++) {
            if (!is_foot(b.bodies[i])) {
                r.impact = t;
                snprintf(r.first_body, sizeof r.first_body, "%s", b.bodies[i]);
            }
        }
        if (r.impact >= 0 && t < r.impact + RATE / 2) {
            const double *s = truth();
            for (int k = 0; k < N_JOINTS; k++) {
                if (fabs(s[N_JOINTS + k]) > r.peak_impact) {
                    r.peak_impact = fabs(s[N_JOINTS + k]);
                    r.peak_joint = k;
                }
                if (fabs(mj.tau[k]) > r.peak_tau) {
                    r.peak_tau = fabs(mj.tau[k]);
                    r.tau_joint = k;
                }
            }
        }
        if (r.impact >= 0 && t >= r.impact + RATE / 2) {
            const double *s = truth();
            double sum = 0.0;
            for (int k = 0; k < N_JOINTS; k++) {
                sum += fabs(mj.tau[k]);
                if (fabs(s[N_JOINTS + k]) > r.lying_speed)
                    r.lying_speed = fabs(s[N_JOINTS + k]);
            }
            r.lying_tau += sum;
            lying_ticks++;
        }
        if (getenv("ROZ_TEST_MUJOCO_TRACE") != NULL && t % 10 == 0)
            print_message("  %s, tick %ld: pelvis %.3f m, tilt %.3f rad, faults 0x%x, %u "
                          "bodies down\n", name, t, b.pos[2], tilt, faults, b.n_bodies);
    }
    r.faults = roz_runtime_faults(&rt);
    if (lying_ticks > 0)
        r.lying_tau /= (double)lying_ticks;
    roz_mujoco_counters_t c;
    roz_mujoco_counters(&mj, &c);
    assert_int_equal(c.violations, 0);
    print_message("%s: %.0f N: FALL at tick %ld (%+ld ms after the push; tilt %.3f rad, pelvis "
                  "%.3f m), impact at tick %ld (%s), largest tilt %.3f rad, lowest pelvis %.3f "
                  "m; within 0.5 s of the impact: peak joint speed %.2f rad/s (%s), peak "
                  "motor torque %.1f N*m (%s); lying: torque %.1f N*m over the joints, "
                  "fastest joint %.2f rad/s; commands after the latch that were not "
                  "damping: %ld\n",
                  name, push, r.latch, r.latch >= 0 ? (r.latch - PUSH_AT) * 1000 / RATE : 0,
                  r.tilt_at_latch, r.height_at_latch, r.impact,
                  r.impact >= 0 ? r.first_body : "-", r.max_tilt, r.lowest, r.peak_impact,
                  m->states[N_JOINTS + r.peak_joint].name, r.peak_tau,
                  m->commands[r.tau_joint].name, r.lying_tau, r.lying_speed, r.not_damping);
    roz_runtime_deinit(&rt);
    roz_port_close(&p);
    return r;
}

/* ---- tests ------------------------------------------------------------------------ */

/* What a fall under the built-in manifest must show: FALL latched, and at
 * least MIN_LEAD ticks before the impact; damping from the latch to the
 * end on every joint; the impact's peak joint speed under MAX_IMPACT_SPEED;
 * lying on the ground, the motors' torques at most LYING_SHARE of what the
 * stand without the rule pushes into the ground, and no joint faster than
 * MAX_LYING_SPEED. Measured (printed by each run): forward, FALL 26 ticks
 * before the impact, 9.1 rad/s on the impact, lying 4.9 N*m (the stand
 * without the rule: 26.1) and 0.70 rad/s; sideways, 48 ticks, 9.7 rad/s,
 * 4.8 N*m (104.1, its joints thrashing at 11.8 rad/s) and 0.40 rad/s. */
#define MIN_LEAD          10   /* ticks, 20 ms */
#define MAX_IMPACT_SPEED  12.0 /* rad/s */
#define LYING_SHARE       0.5
#define MAX_LYING_SPEED   1.0  /* rad/s */

static void judge_fall(const fall_run_t *d, const fall_run_t *s)
{
    assert_true(s->impact >= 0); /* the push fells the stand */
    assert_int_equal(s->faults, 0u);
    assert_int_equal(d->faults, ROZ_FAULT_FALL);
    assert_true(d->latch >= 0 && d->impact >= 0);
    if (d->not_damping != 0)
        fail_msg("%ld commands after the latch were not damping; the first: %s",
                 d->not_damping, d->first_bad);
    if (!(d->latch + MIN_LEAD <= d->impact))
        fail_msg("FALL at tick %ld, the impact at %ld: less than %d ticks before it", d->latch,
                 d->impact, MIN_LEAD);
    assert_true(d->peak_impact < MAX_IMPACT_SPEED);
    assert_true(d->lying_tau < LYING_SHARE * s->lying_tau);
    assert_true(d->lying_speed < MAX_LYING_SPEED);
    print_message("on the impact: peak joint speed %.2f rad/s damped, %.2f rad/s stiff; peak "
                  "motor torque %.1f N*m damped, %.1f N*m stiff; lying: %.1f N*m damped, %.1f "
                  "N*m stiff, fastest joint %.2f rad/s damped, %.2f rad/s stiff\n",
                  d->peak_impact, s->peak_impact, d->peak_tau, s->peak_tau, d->lying_tau,
                  s->lying_tau, d->lying_speed, s->lying_speed);
}

/* The built-in G1 and the same manifest without its fall rule (the stand
 * pushing stiffly on), both pushed by (fx, fy). */
static void pushed_over(double fx, double fy)
{
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    assert_non_null(m);
    assert_non_null(m->fall);
    fall_run_t d = run(m, fx, fy, "damped");
    static roz_manifest_t stiff;
    stiff = *m;
    stiff.fall = NULL;
    fall_run_t s = run(&stiff, fx, fy, "no fall rule");
    judge_fall(&d, &s);
}

/* Pushed over forward. */
static void test_mujoco_fall_forward(void **state)
{
    (void)state;
    pushed_over(PUSH_OVER, 0.0);
}

/* Pushed over sideways (+y). */
static void test_mujoco_fall_sideways(void **state)
{
    (void)state;
    pushed_over(0.0, PUSH_OVER);
}

/* A stumble: pushed, it recovers; nothing latches, and the base never
 * comes near the rule's angle (measured: 0.071 rad of 0.8). */
static void test_mujoco_fall_stumble(void **state)
{
    (void)state;
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    assert_non_null(m);
    fall_run_t r = run(m, PUSH_STUMBLE, 0.0, "stumble");
    assert_int_equal(r.faults, 0u);
    assert_true(r.impact < 0);
    assert_true(r.lowest > 0.7);
    assert_true(r.max_tilt < 0.5 * m->fall->max_tilt);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_mujoco_fall_forward),
              cmocka_unit_test(test_mujoco_fall_sideways),
              cmocka_unit_test(test_mujoco_fall_stumble))
