/* SPDX-License-Identifier: Apache-2.0 */
/* The loopback simulator: works with every built-in manifest, is
 * deterministic, models velocity, position-lag, MIT-mode and planar-base
 * motion, keeps the IMU at rest, and injects faults as documented. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "diff_drive_manifest.h"
#include "quadcopter_manifest.h"
#include "roz/builtin.h"
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_stats.h"
#include "support_runtime.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

static roz_loopback_t lb;
static roz_runtime_t rt;
static double st_a[ROZ_CFG_MAX_STATES], st_b[ROZ_CFG_MAX_STATES];

static void run_builtin(const roz_manifest_t *m, const char *ctl, int ticks, double *final)
{
    roz_runtime_config_t cfg;
    roz_test_clock_t clk = { 1, 10 };

    roz_test_loopback_config(&cfg, &lb, m, NULL, &clk);
    roz_test_runtime_start(&rt, &cfg, ctl);
    for (int t = 0; t < ticks; t++)
        roz_test_tick(&rt);
    if (roz_runtime_faults(&rt) != 0)
        fail_msg("%s: fault %s", m->robot_id, roz_runtime_fault_message(&rt));
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
    assert_int_equal(roz_loopback_counters(&lb).writes, (uint64_t)ticks);
    roz_loopback_true_state(&lb, final);
    roz_runtime_deinit(&rt);
}

/* Every built-in runs, twice, to the same bits. */
static void test_loopback_every_builtin_deterministic(void **st)
{
    (void)st;
    for (size_t i = 0; i < roz_builtin_count(); i++) {
        const roz_manifest_t *m = roz_builtin_at(i);
        print_message("%s\n", m->robot_id);
        run_builtin(m, "sine", 300, st_a);
        run_builtin(m, "sine", 300, st_b);
        assert_memory_equal(st_a, st_b, m->n_states * sizeof st_a[0]);
        int moved = 0;
        for (uint16_t s = 0; s < m->n_states; s++) {
            assert_true(isfinite(st_a[s]));
            moved += st_a[s] != m->states[s].default_value;
        }
        assert_true(moved > 0);
    }
}

static void test_loopback_models(void **st)
{
    (void)st;
    /* UR5: velocity integrates into position; the velocity state reads it */
    run_builtin(&roz_manifest_ur5, "constant_velocity", 100, st_a);
    /* the port steps on each read after the first write: 99 steps, the first
     * at 0.5 rad/s (ramped from 0 by the rate cap), then 0.628 rad/s */
    assert_near(st_a[ROZ_UR5_STATE_ELBOW_JOINT_POSITION], 0.005 + 0.628 * 0.98, 1e-9);
    assert_near(st_a[ROZ_UR5_STATE_ELBOW_JOINT_VELOCITY], 0.628, 1e-12);

    /* quadcopter: body velocities into world position, yaw from the yaw rate */
    run_builtin(&roz_manifest_quadcopter, "constant_velocity", 100, st_a);
    assert_true(st_a[ROZ_QUADCOPTER_STATE_BODY_POSITION_Z] > 0.5);
    assert_near(st_a[ROZ_QUADCOPTER_STATE_BODY_YAW], 0.314 * 0.99, 1e-9);

    /* diff drive: a unicycle */
    run_builtin(&roz_manifest_diff_drive, "constant_velocity", 100, st_a);
    assert_true(st_a[ROZ_DIFF_DRIVE_STATE_BASE_ODOM_X] > 0.15);
    assert_true(st_a[ROZ_DIFF_DRIVE_STATE_BASE_ODOM_Y] > 0.0);
    assert_near(st_a[ROZ_DIFF_DRIVE_STATE_BASE_ODOM_YAW], 0.4 * 0.99, 1e-9);

    /* G1: the IMU stays at rest (its manifest defaults) */
    run_builtin(&roz_manifest_unitree_g1, "g1_stand", 100, st_a);
    assert_true(st_a[ROZ_UNITREE_G1_STATE_BASE_IMU_ORIENTATION_W] == 1.0);
    assert_true(st_a[ROZ_UNITREE_G1_STATE_BASE_IMU_ORIENTATION_X] == 0.0);
    assert_true(st_a[ROZ_UNITREE_G1_STATE_BASE_IMU_LINEAR_ACCELERATION_Z] == 9.81);
    assert_true(st_a[ROZ_UNITREE_G1_STATE_LEFT_KNEE_JOINT_EFFORT] != 0.0); /* PD torque */
}

/* A feed-forward effort cannot hold a joint past its position limit: on
 * every humanoid, constant_velocity asks each joint for +velocity and a
 * +effort (0.2 of its limit, 24 N*m on the X2's hip roll) on top of a PD that
 * pulls toward 0.047 rad. Without the filter's effort rule the X2's
 * right_hip_roll_joint settled at 0.647 rad, past its 0.2356 limit; with
 * it, a joint arriving at up to 9 rad/s coasts up to 0.09 rad past (the
 * loopback's joints are light), then comes back. */
static void test_loopback_effort_stops_at_limit(void **st)
{
    (void)st;
    for (size_t i = 0; i < roz_builtin_count(); i++) {
        const roz_manifest_t *m = roz_builtin_at(i);
        roz_runtime_config_t cfg;
        roz_test_clock_t clk = { 1, 10 };
        uint64_t cut = 0;
        double worst = 0.0;

        roz_test_loopback_config(&cfg, &lb, m, NULL, &clk);
        roz_test_runtime_start(&rt, &cfg, "constant_velocity");
        for (int t = 0; t < 2000; t++) {
            roz_test_tick(&rt);
            roz_loopback_true_state(&lb, st_a);
            for (uint16_t c = 0; c < m->n_commands; c++) {
                const roz_channel_t *cc = &m->commands[c];
                if (cc->type != ROZ_IF_EFFORT || cc->position_state == ROZ_CHANNEL_UNPAIRED)
                    continue;
                const roz_channel_t *ps = &m->states[cc->position_state];
                double p = st_a[cc->position_state];
                double out = p > ps->max ? p - ps->max : (p < ps->min ? ps->min - p : 0.0);
                if (out > worst)
                    worst = out;
                /* the cut is reactive: a joint arriving fast coasts on (the
                 * margin must cover that, as SAFETY.md says); once settled,
                 * nothing holds it outside */
                if (t >= 500 && out > 0.0)
                    fail_msg("%s tick %d: %s at %.6g, outside [%g, %g]", m->robot_id, t,
                             ps->name, p, ps->min, ps->max);
            }
        }
        for (uint16_t c = 0; c < m->n_commands; c++) {
            roz_filter_channel_counters_t fc;
            if (m->commands[c].type == ROZ_IF_EFFORT &&
                roz_runtime_channel_counters(&rt, c, &fc) == ROZ_OK)
                cut += fc.limit_stops;
        }
        print_message("%s: %llu effort limit stops, worst coast past a limit %.3g\n",
                      m->robot_id, (unsigned long long)cut, worst);
        if (m->n_commands > 100) /* the humanoids: some joint reached a limit */
            assert_true(cut > 0);
        assert_int_equal(roz_runtime_faults(&rt), 0);
        roz_runtime_deinit(&rt);
    }
}

/* Fault injection, read straight from the port. */
static void test_loopback_faults(void **st)
{
    roz_port_t p = roz_loopback_port(&lb, NULL, NULL);
    roz_param_t items[] = { { "drop", "2:4" }, { "nan", "shoulder_pan_joint/position@5:6" },
                            { "range", "1@6:7" }, { "delay", "2@8:10" }, { "freeze", "12" } };
    roz_params_t params = { items, 5 };
    double s[12], cmd[6] = { 1, 1, 1, 1, 1, 1 };
    char err[160];
    (void)st;
    assert_int_equal(roz_port_open(&p, &roz_manifest_ur5, &params, err, sizeof err), ROZ_OK);
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* tick 0: the initial frame */
    assert_int_equal(roz_port_write(&p, cmd, 6), ROZ_OK);
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* tick 1: moved 0.01 */
    assert_near(s[0], 0.01, 1e-12);
    assert_int_equal(roz_port_read(&p, s, 12), 0); /* 2, 3 dropped: the old frame */
    assert_near(s[0], 0.01, 1e-12);
    assert_int_equal(roz_port_read(&p, s, 12), 0);
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* 4 */
    assert_near(s[0], 0.04, 1e-12);
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* 5: NaN on state 0 */
    assert_true(isnan(s[0]));
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* 6: state 1 beyond its limit */
    assert_near(s[1], 6.283185307179586 + 0.5, 1e-12);
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* 7 */
    assert_near(s[0], 0.07, 1e-12);
    /* frames sent at 8 and 9 arrive two ticks late: a gap, then the frame
     * sent at 8 arrives at 10 with the one sent at 10 (newest wins), and the
     * one sent at 9 arrives at 11 behind frame 10: dropped as a replay */
    assert_int_equal(roz_port_read(&p, s, 12), 0); /* 8 */
    assert_near(s[0], 0.07, 1e-12);
    assert_int_equal(roz_port_read(&p, s, 12), 0); /* 9 */
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* 10 */
    assert_near(s[0], 0.10, 1e-12);
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* 11 */
    assert_near(s[0], 0.11, 1e-12);
    assert_int_equal(roz_loopback_link(&lb).replays, 1);
    for (int t = 12; t < 20; t++) /* frozen from 12: nothing new, ever */
        assert_int_equal(roz_port_read(&p, s, 12), 0);
    assert_int_equal(roz_loopback_counters(&lb).frames_dropped, 2);
    assert_int_equal(roz_loopback_counters(&lb).frames_sent, 12);
    /* the two dropped, and 9, overtaken by 10 */
    assert_int_equal(roz_loopback_link(&lb).missing, 3);
    assert_int_equal(roz_loopback_link(&lb).crc_errors, 0);
}

/* The wire faults, read straight from the port: CRC corruption both ways,
 * a replaying transport, a peer that dies and boots again. */
static void test_loopback_wire_faults(void **st)
{
    roz_port_t p = roz_loopback_port(&lb, NULL, NULL);
    roz_param_t items[] = { { "corrupt", "2:4" }, { "corrupt_cmd", "5:7" },
                            { "duplicate", "8:10" }, { "restart", "100:160" } };
    roz_params_t params = { items, 4 };
    double s[12], cmd[6] = { 1, 1, 1, 1, 1, 1 }, zero[6] = { 0 };
    char err[160];
    int t = 0;
    (void)st;
    assert_int_equal(roz_port_open(&p, &roz_manifest_ur5, &params, err, sizeof err), ROZ_OK);
    assert_int_equal(roz_port_write(&p, cmd, 6), ROZ_OK); /* before any state: withheld */
    assert_int_equal(roz_loopback_counters(&lb).writes_withheld, 1);
    assert_null(roz_loopback_last_command(&lb));
    for (; t < 2; t++) {
        assert_int_equal(roz_port_read(&p, s, 12), 1);
        assert_int_equal(roz_port_write(&p, cmd, 6), ROZ_OK);
    }
    /* 2, 3: a bit flips in each state frame: dropped, counted, old state */
    for (; t < 4; t++) {
        assert_int_equal(roz_port_read(&p, s, 12), 0);
        assert_near(s[0], 0.01, 1e-12);
        assert_int_equal(roz_port_write(&p, cmd, 6), ROZ_OK);
    }
    assert_int_equal(roz_loopback_counters(&lb).frames_corrupted, 2);
    assert_int_equal(roz_loopback_link(&lb).crc_errors, 2);
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* 4 */
    assert_near(s[0], 0.04, 1e-12);
    assert_int_equal(roz_port_write(&p, cmd, 6), ROZ_OK);
    /* 5, 6: the robot gets command frames with a bit flipped: it drops them
     * and keeps applying the last good command */
    for (t = 5; t < 7; t++) {
        assert_int_equal(roz_port_read(&p, s, 12), 1);
        assert_int_equal(roz_port_write(&p, zero, 6), ROZ_OK);
        assert_true(roz_loopback_last_command(&lb)[0] == 1.0);
    }
    assert_int_equal(roz_loopback_counters(&lb).cmds_corrupted, 2);
    assert_int_equal(roz_loopback_peer_link(&lb).crc_errors, 2);
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* 7: still moving at 1 rad/s */
    assert_near(s[0], 0.07, 1e-12);
    assert_int_equal(roz_port_write(&p, zero, 6), ROZ_OK);
    assert_true(roz_loopback_last_command(&lb)[0] == 0.0);
    /* 8, 9: the frame of tick 7 again, in place of new ones: replays */
    for (t = 8; t < 10; t++) {
        assert_int_equal(roz_port_read(&p, s, 12), 0);
        assert_near(s[0], 0.07, 1e-12);
        assert_int_equal(roz_port_write(&p, zero, 6), ROZ_OK);
    }
    assert_int_equal(roz_loopback_counters(&lb).frames_duplicated, 2);
    assert_int_equal(roz_loopback_link(&lb).replays, 2);
    for (t = 10; t < 100; t++) {
        assert_int_equal(roz_port_read(&p, s, 12), 1);
        assert_int_equal(roz_port_write(&p, cmd, 6), ROZ_OK);
    }
    double before = s[0];
    /* 100..159: the robot is dead: no frames, commands lost, joints stopped */
    for (t = 100; t < 160; t++) {
        assert_int_equal(roz_port_read(&p, s, 12), 0);
        assert_int_equal(roz_port_write(&p, cmd, 6), ROZ_OK);
    }
    assert_int_equal(roz_loopback_counters(&lb).cmds_lost, 60);
    /* 160: it boots, its sequence back at 0 (from 99): the port reports the
     * link fault once and takes the frame */
    assert_int_equal(roz_port_read(&p, s, 12), ROZ_ELINK);
    assert_int_equal(roz_loopback_counters(&lb).link_events, 1);
    assert_int_equal(roz_loopback_link(&lb).restarts, 1);
    assert_null(roz_loopback_last_command(&lb)); /* it forgot its command */
    assert_int_equal(roz_port_write(&p, zero, 6), ROZ_OK);
    assert_int_equal(roz_port_read(&p, s, 12), 1); /* 161 */
    roz_loopback_true_state(&lb, s);
    assert_near(s[0], before, 1e-12); /* it stopped where it died; the new command is 0 */
    assert_int_equal(roz_loopback_counters(&lb).violations, 0);
}

/* The fault table holds ROZ_LOOPBACK_MAX_FAULTS active injections; spent
 * ones make room for new ones. */
static void test_loopback_fault_table(void **st)
{
    roz_port_t p = roz_loopback_port(&lb, NULL, NULL);
    double s[12];
    char err[160];
    (void)st;
    assert_int_equal(roz_port_open(&p, &roz_manifest_ur5, NULL, err, sizeof err), ROZ_OK);
    for (uint64_t k = 0; k < ROZ_LOOPBACK_MAX_FAULTS; k++) {
        roz_loopback_fault_t f = { ROZ_INJECT_DROP, k, k + 1, -1, 0 };
        assert_int_equal(roz_loopback_inject(&lb, &f), ROZ_OK);
    }
    roz_loopback_fault_t forever = { ROZ_INJECT_NAN, 100, 0, 0, 0 };
    assert_int_equal(roz_loopback_inject(&lb, &forever), ROZ_ENOSPC); /* all pending */
    for (int t = 0; t < 3; t++)
        assert_int_equal(roz_port_read(&p, s, 12), ROZ_ENOENT); /* ticks 0..2 dropped */
    for (uint32_t k = 0; k < 3; k++) /* three spent: room for three */
        assert_int_equal(roz_loopback_inject(&lb, &forever), ROZ_OK);
    assert_int_equal(roz_loopback_inject(&lb, &forever), ROZ_ENOSPC);
    assert_int_equal(roz_loopback_counters(&lb).faults, ROZ_LOOPBACK_MAX_FAULTS);
}

static void test_loopback_bad_params(void **st)
{
    /* each message quotes the value and says what is wrong with it */
    static const struct {
        const roz_manifest_t *m;
        const char *key, *value, *want;
    } cases[] = {
        { &roz_manifest_ur5, "dropp", "1:2", "unknown parameter \"dropp\" for port loopback" },
        { &roz_manifest_ur5, "drop", "300:100", "parameter drop = \"300:100\": FROM 300 after TO 100" },
        { &roz_manifest_ur5, "drop", "5:5", "FROM 5 equals TO" },
        /* a TO of 0 is written, so it is not "forever" (that is "5:") */
        { &roz_manifest_ur5, "restart", "5:0", "parameter restart = \"5:0\": FROM 5 after TO 0" },
        { &roz_manifest_ur5, "drop", "0:0", "FROM 0 equals TO" },
        { &roz_manifest_ur5, "drop", "0:00", "FROM 0 equals TO" },
        /* the simulators' one grammar (roz/hal/inject.h): a restart boots
         * again at TO, so it needs one (the loopback used to take "5:" as
         * dead for good; the mujoco port refused it) */
        { &roz_manifest_ur5, "restart", "5:", "parameter restart = \"5:\": no TO: the robot boots again at TO" },
        { &roz_manifest_ur5, "restart", "5:6", NULL },
        /* entries separated by ';' (spaces around it ignored), each held
         * to the same rules */
        { &roz_manifest_ur5, "drop", "1:2;5:6", NULL },
        { &roz_manifest_ur5, "drop", "1:2 ; 5:", NULL },
        { &roz_manifest_ur5, "drop", "1:2;3:3", "parameter drop = \"1:2;3:3\": FROM 3 equals TO" },
        { &roz_manifest_ur5, "drop", "1:2;", "FROM is missing or not a tick number" },
        { &roz_manifest_ur5, "drop", "99999999999999999999999:",
          "FROM 99999999999999999999999 is too large (at most 18446744073709551615)" },
        { &roz_manifest_ur5, "freeze", "1:18446744073709551616", "TO 18446744073709551616 is too large" },
        { &roz_manifest_ur5, "freeze", "18446744073709551615", NULL }, /* the largest: taken */
        { &roz_manifest_ur5, "drop", "x", "parameter drop = \"x\": FROM is missing or not a tick number" },
        { &roz_manifest_ur5, "drop", "-1:2", "FROM is missing or not a tick number" },
        { &roz_manifest_ur5, "drop", "1:-2", "TO is missing or not a tick number" },
        { &roz_manifest_ur5, "drop", "1:2x", "unexpected \"x\" after the ticks" },
        { &roz_manifest_ur5, "delay", "99@1:2", "parameter delay = \"99@1:2\": K 99 is not a delay in 1..15 ticks" },
        { &roz_manifest_ur5, "delay", "0@1:2", "K 0 is not a delay in 1..15" },
        { &roz_manifest_ur5, "delay", "1:2", "no K before '@'; expected K@FROM:TO" },
        { &roz_manifest_diff_drive, "nan", "7@1:2", "parameter nan = \"7@1:2\": state 7 does not exist (3 states)" },
        { &roz_manifest_diff_drive, "nan", "3@1:2", "state 3 does not exist (3 states)" },
        { &roz_manifest_diff_drive, "nan", "2@1:2", NULL },
        { &roz_manifest_diff_drive, "nan", "99999999999999999999@1:", "state 99999999999999999999 does not exist (3 states)" },
        { &roz_manifest_ur5, "nan", "nosuch/state@1:2", "parameter nan = \"nosuch/state@1:2\": no state named \"nosuch/state\"" },
        { &roz_manifest_ur5, "nan", "@1:2", "no CHANNEL before '@'" },
        { &roz_manifest_ur5, "range", "12@1:", "parameter range = \"12@1:\": state 12 does not exist (12 states)" },
        { &roz_manifest_ur5, "range", "6@1:", "state 6 (shoulder_pan_joint/velocity) is not a position state" },
    };
    roz_port_t p = roz_loopback_port(&lb, NULL, NULL);
    char err[320];
    (void)st;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        roz_param_t item = { cases[i].key, cases[i].value };
        roz_params_t params = { &item, 1 };
        int rc = roz_port_open(&p, cases[i].m, &params, err, sizeof err);
        if (cases[i].want == NULL) {
            if (rc != ROZ_OK)
                fail_msg("%s=%s refused: %s", cases[i].key, cases[i].value, err);
            continue;
        }
        if (rc >= 0)
            fail_msg("%s=%s accepted", cases[i].key, cases[i].value);
        if (strstr(err, cases[i].want) == NULL)
            fail_msg("\"%s\" lacks \"%s\"", err, cases[i].want);
    }
    /* one more than the table holds */
    roz_param_t many[ROZ_LOOPBACK_MAX_FAULTS + 1];
    for (size_t i = 0; i < ROZ_LOOPBACK_MAX_FAULTS + 1; i++)
        many[i] = (roz_param_t){ "drop", "1:2" };
    roz_params_t all = { many, ROZ_LOOPBACK_MAX_FAULTS + 1 };
    assert_true(roz_port_open(&p, &roz_manifest_ur5, &all, err, sizeof err) < 0);
    assert_non_null(strstr(err, "more than 8 fault injections"));
    /* wrong sizes are refused, not overrun */
    double s[12];
    assert_int_equal(roz_port_open(&p, &roz_manifest_ur5, NULL, err, sizeof err), ROZ_OK);
    assert_int_equal(roz_port_read(&p, s, 11), ROZ_EINVAL);
    assert_int_equal(roz_port_write(&p, s, 7), ROZ_EINVAL);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_loopback_every_builtin_deterministic),
              cmocka_unit_test(test_loopback_models),
              cmocka_unit_test(test_loopback_effort_stops_at_limit),
              cmocka_unit_test(test_loopback_faults),
              cmocka_unit_test(test_loopback_wire_faults),
              cmocka_unit_test(test_loopback_fault_table),
              cmocka_unit_test(test_loopback_bad_params))
