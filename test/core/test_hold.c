/* SPDX-License-Identifier: Apache-2.0 */
/* The hold every stop sends (roz/hold.h): its cases, and the property that
 * a stop never leaves a joint more torque than the controller's last
 * command gave it, nor a setpoint further from the joint than that
 * command's or the band: over random gains, setpoints and stop kinds, on
 * every built-in manifest with a hold, through the filter (controlled stop,
 * ramped; e-stop) and through the DDS ports' own functions (roz/hal/
 * joints.h): the watchdog's hold, roz_joints_hold_setpoint() joint by joint
 * as g1_watchdog() and the ROS 2 bridges compute it, and the hold after a
 * trip and at exit, roz_joints_hold_keep() (the hold gain at once). The
 * socketcan port's: test/ports/socketcan/test_socketcan.c,
 * test_socketcan_stops_keep_the_torque. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/builtin.h"
#include "roz/filter.h"
#include "roz/hal/joints.h"
#include "roz/hold.h"
#include "support.h"
#include "support_thin.h"

/* ---- random ---------------------------------------------------------------- */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rng(void)
{
    return roz_test_rng(&rng_state);
}

static double uniform(double lo, double hi)
{
    return roz_test_uniform(&rng_state, lo, hi);
}

static double clampd(double v, double lo, double hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/* ---- the property ------------------------------------------------------------ */

/* Tolerance of the comparisons: rounding only. */
static int above(double a, double b)
{
    return a > b + 1e-9 * (1.0 + fabs(b));
}

/* What a stop may send a joint held at @p p whose controller last sent
 * setpoint @p sp at stiffness @p kp_c: @p q at @p kp, with no more torque
 * about p, and q on sp's side of p within max(|sp - p|, band). */
static void check_hold(const char *robot, const char *path, const char *joint, long tick,
                       double sp, double kp_c, double p, double band, double q, double kp)
{
    double torque_c = fabs(kp_c * (sp - p)), torque = fabs(kp * (q - p));
    if (above(torque, torque_c))
        fail_msg("%s, %s, %s, tick %ld: the stop's torque %.6g N*m (kp %.6g, q %.6g) exceeds the "
                 "controller's %.6g N*m (kp %.6g, q %.6g), position %.6g",
                 robot, path, joint, tick, torque, kp, q, torque_c, kp_c, sp, p);
    if (above(fabs(q - p), fmax(fabs(sp - p), band)) || (q - p) * (sp - p) < -1e-12)
        fail_msg("%s, %s, %s, tick %ld: setpoint %.6g is past the controller's %.6g by more "
                 "than the band %.6g around the position %.6g",
                 robot, path, joint, tick, q, sp, band, p);
}

/* The joint's stiffness command (same name up to the '/'), -1: none. */
static int gain_of(const roz_manifest_t *m, uint16_t i)
{
    const char *name = m->commands[i].name, *slash = strrchr(name, '/');
    size_t len = slash != NULL ? (size_t)(slash - name) : strlen(name);
    for (uint16_t k = 0; k < m->n_commands; k++) {
        if (m->commands[k].type == ROZ_IF_STIFFNESS && strncmp(m->commands[k].name, name, len) == 0 &&
            m->commands[k].name[len] == '/')
            return k;
    }
    return -1;
}

/* The manifest's joints bound as a port binds them (roz_joints_bind()): the
 * names before the '/' of its channels, the IMU's aside; their number. */
static uint16_t bind_joints(const roz_manifest_t *m, roz_joint_channels_t *ch)
{
    static char names[ROZ_CFG_MAX_COMMANDS][64];
    const char *list[ROZ_CFG_MAX_COMMANDS];
    int16_t imu[ROZ_IMU_VALUES];
    char err[256];
    uint16_t n = 0;
    for (int pass = 0; pass < 2; pass++) {
        const roz_channel_t *chs = pass == 0 ? m->commands : m->states;
        uint16_t count = pass == 0 ? m->n_commands : m->n_states;
        for (uint16_t i = 0; i < count; i++) {
            const char *slash = strrchr(chs[i].name, '/');
            size_t len = slash != NULL ? (size_t)(slash - chs[i].name) : strlen(chs[i].name);
            if (len == 8 && strncmp(chs[i].name, "base_imu", 8) == 0)
                continue;
            uint16_t k = 0;
            while (k < n && !(strlen(names[k]) == len && strncmp(names[k], chs[i].name, len) == 0))
                k++;
            if (k == n) {
                snprintf(names[n], sizeof names[n], "%.*s", (int)len, chs[i].name);
                list[n] = names[n];
                n++;
            }
        }
    }
    if (roz_joints_bind(m, "test", "this robot", list, n, ch, imu, err, sizeof err) != ROZ_OK)
        fail_msg("%s: %s", m->robot_id, err);
    return n;
}

static roz_filter_t f;
static double target[ROZ_CFG_MAX_COMMANDS], state[ROZ_CFG_MAX_STATES];
static double out[ROZ_CFG_MAX_COMMANDS], sent[ROZ_CFG_MAX_COMMANDS];

/* One random case on manifest @p m: the controller drives each held joint
 * to a random setpoint and stiffness (within its limits, some far from the
 * joint, some stiffer and some softer than the hold gain), the joints stay
 * where they are, then a random stop: a controlled stop (ramped), an
 * e-stop, the DDS ports' watchdog hold, or their hold after a trip and at
 * exit. */
static void one_case(const roz_manifest_t *m, int kind)
{
    const char *paths[4] = { "filter, controlled stop", "filter, e-stop",
                             "the DDS ports' watchdog hold (roz_joints_hold_setpoint)",
                             "the DDS ports' hold after a trip and exit (roz_joints_hold_keep)" };
    static roz_joint_channels_t ch[ROZ_CFG_MAX_COMMANDS];
    uint16_t n_joints = bind_joints(m, ch);
    assert_int_equal(roz_filter_init(&f, m), ROZ_OK);
    for (uint16_t s = 0; s < m->n_states; s++) {
        const roz_channel_t *c = &m->states[s];
        state[s] = c->type == ROZ_IF_POSITION ? uniform(c->min, c->max) : 0.0;
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        target[i] = c->default_value;
        if (c->type == ROZ_IF_STIFFNESS)
            target[i] = rng() % 4u == 0 ? c->max : uniform(c->min, c->max);
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        if (c->type == ROZ_IF_POSITION && c->position_state != ROZ_CHANNEL_UNPAIRED) {
            double p = clampd(state[c->position_state], c->min, c->max);
            double reach = rng() % 2u ? 0.05 : 0.6;
            target[i] = clampd(p + uniform(-reach, reach), c->min, c->max);
            state[c->position_state] = p;
        }
    }
    /* long enough for every channel to reach its target under its cap */
    for (int t = 0; t < 800; t++)
        roz_filter_apply(&f, target, state, ROZ_STOP_NONE, sent);

    long ticks = kind == 0 ? 800 : 3;
    for (long t = 0; t < ticks; t++) {
        if (kind < 2) {
            roz_filter_apply(&f, target, state, kind == 0 ? ROZ_STOP_CONTROLLED : ROZ_STOP_IMMEDIATE,
                             out);
        } else {
            double q[ROZ_CFG_MAX_COMMANDS];
            for (uint16_t k = 0; k < n_joints; k++)
                q[k] = ch[k].q_state >= 0 ? state[ch[k].q_state] : NAN;
            if (kind == 3) {
                roz_joints_hold_keep(m, ch, n_joints, sent, q, 1.0, out);
            } else {
                /* g1_watchdog(), bridge_watchdog(): the setpoint each, the
                 * hold gain */
                memcpy(out, sent, sizeof out[0] * m->n_commands);
                for (uint16_t k = 0; k < n_joints; k++) {
                    if (ch[k].q_cmd < 0)
                        continue;
                    out[ch[k].q_cmd] = roz_joints_hold_setpoint(
                        m, &ch[k], sent[ch[k].q_cmd], ch[k].kp_cmd >= 0 ? sent[ch[k].kp_cmd] : NAN,
                        q[k]);
                    if (ch[k].kp_cmd >= 0)
                        out[ch[k].kp_cmd] = m->commands[ch[k].kp_cmd].default_value;
                }
            }
        }
        for (uint16_t i = 0; i < m->n_commands; i++) {
            const roz_channel_t *c = &m->commands[i];
            if (c->safe_default != ROZ_SAFE_HOLD)
                continue;
            int k = gain_of(m, i);
            double p = state[c->position_state], band = roz_hold_band(c);
            double kp_c = k >= 0 ? sent[k] : 1.0; /* the robot's own gain: the same */
            double q = out[i], kp = k >= 0 ? out[k] : 1.0;
            if (kind >= 2 && k >= 0 && !(fabs(kp - m->commands[k].default_value) <= 1e-12))
                fail_msg("%s, %s, %s: stiffness %.9g, not the hold gain %.9g", m->robot_id,
                         paths[kind], c->name, kp, m->commands[k].default_value);
            if (!(q >= c->min && q <= c->max))
                fail_msg("%s, %s, %s: setpoint %.9g outside [%g, %g]", m->robot_id, paths[kind],
                         c->name, q, c->min, c->max);
            check_hold(m->robot_id, paths[kind], c->name, t, sent[i], kp_c, p, band, q, kp);
        }
    }
    /* a controlled stop reaches the hold gain whenever the band allows it */
    if (kind == 0) {
        for (uint16_t i = 0; i < m->n_commands; i++) {
            const roz_channel_t *c = &m->commands[i];
            int k = gain_of(m, i);
            if (c->safe_default != ROZ_SAFE_HOLD || k < 0)
                continue;
            double p = state[c->position_state], kp_hold = m->commands[k].default_value;
            if (fabs(sent[k] * (sent[i] - p)) <= kp_hold * roz_hold_band(c) * 0.999 &&
                fabs(out[k] - kp_hold) > 1e-6 * kp_hold)
                fail_msg("%s, %s: the stiffness stopped at %.9g short of its hold gain %.9g",
                         m->robot_id, c->name, out[k], kp_hold);
        }
    }
}

static void test_hold_property(void **unused)
{
    (void)unused;
    int with_hold = 0;
    for (size_t b = 0; b < roz_builtin_count(); b++) {
        const roz_manifest_t *m = roz_builtin_at(b);
        int any = 0;
        for (uint16_t i = 0; i < m->n_commands; i++)
            any |= m->commands[i].safe_default == ROZ_SAFE_HOLD;
        if (!any)
            continue;
        with_hold++;
        for (int n = 0; n < 80 / ROZ_TEST_THIN(4); n++) /* fewer under an emulator */
            one_case(m, n % 4);
    }
    assert_true(with_hold >= 3); /* the G1, the PM01, the X2 */
}

/* A ramped stop recomputes the setpoint for the stiffness it sends: on a
 * joint whose controller held it softly (or stiffly) away from its
 * position, the torque about that position stays the controller's on every
 * tick of the ramp, and ends at the hold gain. */
static void test_hold_filter_ramped_stop(void **unused)
{
    (void)unused;
    static const struct {
        const char *joint;
        double      kp;
    } rows[] = {
        { "left_ankle_pitch_joint", 40.0 },      /* a soft ankle stand: hold gain 200 */
        { "left_ankle_pitch_joint", 198.0 },
        { "left_shoulder_pitch_joint", 200.0 },  /* stiff arms: hold gain 40 */
    };
    const roz_manifest_t *m = roz_builtin_find("unitree_g1");
    assert_non_null(m);
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        char qn[64], kpn[64];
        int q = -1, kp = -1;
        snprintf(qn, sizeof qn, "%s/position", rows[r].joint);
        snprintf(kpn, sizeof kpn, "%s/stiffness", rows[r].joint);
        for (uint16_t i = 0; i < m->n_commands; i++) {
            q = strcmp(m->commands[i].name, qn) == 0 ? i : q;
            kp = strcmp(m->commands[i].name, kpn) == 0 ? i : kp;
        }
        assert_true(q >= 0 && kp >= 0);
        assert_int_equal(roz_filter_init(&f, m), ROZ_OK);
        memset(state, 0, sizeof state);
        for (uint16_t i = 0; i < m->n_commands; i++)
            target[i] = m->commands[i].default_value;
        double p = 0.1;
        state[m->commands[q].position_state] = p;
        target[q] = p + 0.02;
        target[kp] = rows[r].kp;
        for (int t = 0; t < 600; t++)
            roz_filter_apply(&f, target, state, ROZ_STOP_NONE, sent);
        double torque = sent[kp] * (sent[q] - p);
        assert_true(torque > 0.0);
        for (int t = 0; t < 400; t++) {
            roz_filter_apply(&f, target, state, ROZ_STOP_CONTROLLED, out);
            double now = out[kp] * (out[q] - p);
            if (fabs(now - torque) > 1e-9 * torque)
                fail_msg("%s, kp %.1f, tick %d of the stop: %.9g N*m (kp %.6g at %.6g), the "
                         "controller's %.9g N*m",
                         rows[r].joint, rows[r].kp, t, now, out[kp], out[q], torque);
        }
        assert_true(fabs(out[kp] - m->commands[kp].default_value) < 1e-9);
    }
}

/* The hold's cases, one row each. */
static void test_hold_setpoint_cases(void **unused)
{
    (void)unused;
    static const struct {
        double sp, kp, p, kp_sent, band, want;
    } rows[] = {
        { 0.5, 80.0, 0.9, 200.0, 1.0, 0.74 },      /* the torque kept */
        { 0.5, 80.0, 0.9, 200.0, 0.1, 0.8 },       /* within the band of the joint */
        { 0.5, 200.0, 0.6, 40.0, 0.2, 0.4 },       /* softer: past the setpoint, to the band */
        { 0.5, 200.0, 0.6, 40.0, 1.0, 0.1 },       /* softer, inside the band */
        { NAN, 80.0, 0.75, 200.0, 0.2, 0.75 },     /* no position command: the joint */
        { NAN, NAN, 0.75, 200.0, 0.2, 0.75 },
        { 0.5, 80.0, NAN, 200.0, 0.2, 0.5 },       /* position unknown: the command */
        { 0.5, NAN, 0.9, 200.0, 0.2, 0.7 },        /* no stiffness command: the band */
        { 0.5, 80.0, 0.9, 0.0, 0.2, 0.7 },         /* no stiffness sent: the band */
        { 0.5, 80.0, 0.9, 200.0, 0.0, 0.9 },       /* no rate cap: the joint */
        { 0.5, INFINITY, 0.9, 200.0, 0.2, 0.7 },
    };
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        roz_hold_from_t h = { rows[r].sp, rows[r].kp, rows[r].p };
        double got = roz_hold_setpoint(&h, rows[r].kp_sent, rows[r].band);
        if (!(fabs(got - rows[r].want) < 1e-12))
            fail_msg("row %zu: %.17g, want %.17g", r, got, rows[r].want);
    }
    roz_hold_from_t none = { NAN, 80.0, NAN };
    assert_true(isnan(roz_hold_setpoint(&none, 200.0, 0.2))); /* no hold: the caller's to say */
    /* the gain a lagging setpoint allows */
    roz_hold_from_t h = { 1.0, 10.0, 0.0 };
    assert_true(fabs(roz_hold_gain_cap(&h, 0.5, 30.0, 0.0) - 20.0) < 1e-12);
    assert_true(fabs(roz_hold_gain_cap(&h, 0.5, 30.0, 25.0) - 25.0) < 1e-12);
    assert_true(fabs(roz_hold_gain_cap(&h, 0.2, 30.0, 0.0) - 30.0) < 1e-12);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_hold_setpoint_cases),
              cmocka_unit_test(test_hold_filter_ramped_stop),
              cmocka_unit_test(test_hold_property))
