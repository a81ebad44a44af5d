/* SPDX-License-Identifier: Apache-2.0 */
/* The PM01 port (roz/port/engineai_pm01.h) against the fake robot (fake_ros2
 * --robot pm01: its own IDL and robot description, a separate process) over
 * loopback DDS, beyond the conformance suite:
 *  - all 24 joints map both ways, a distinct value per joint and field: the
 *    states the port reads from joint_state, the JointCommand the robot
 *    gets (position, velocity, feed_forward_torque from effort, stiffness,
 *    damping; torque 0); every array of every command is 24 long;
 *  - parallel_parser_type: RL_PARSER (1) by default, each documented
 *    spelling as its number in every command (hold, commands, damping),
 *    from robot.toml or the caller; anything else refused by key and value;
 *  - the IMU: imu_info's quaternion x, y, z, w, angular velocity and linear
 *    acceleration reach the manifest's channels in order;
 *  - header stamps: every command is stamped with the system clock, stamps
 *    never go back; the state's stamps are its link checks: a stamp not
 *    newer than the last is a replay (dropped), one more than a second back
 *    a restart (ROZ_ELINK), one that is not a time malformed (dropped);
 *  - a joint_state whose arrays are not 24 long is dropped and counted;
 *  - the domain: 69 from the manifest's parameters (traffic flows on it),
 *    overridden by dds_domain, a bad one refused;
 *  - a peer that speaks as rmw_cyclonedds (no type information: matched by
 *    topic and type name alone) exchanges samples with the port both ways;
 *    an endpoint whose type name lacks ROS 2's "dds_" never matches;
 *  - decimation 4, the periodic writer and a restarted robot, the start-up
 *    hold with startup_damping, the damping command on shutdown;
 *  - a manifest's joints are found by name, in any order and any subset
 *    (the other indices passive); a joint not on the PM01 is refused;
 *  - the command watchdog (roz::ros2, shared with the X2), on a clock the
 *    test moves: 100 ms of silence is not a trip, 1 ns more is, and the
 *    robot gets the watchdog's hold, repeatedly: the hold gains, each setpoint moved to
 *    keep the torque it last went out with (a joint held with kp 80 at s,
 *    measured at q, gets q + 80 (s - q) / kh), clamped inside the limits,
 *    about the last finite position when the robot last said NaN; read()
 *    reports the trip once naming the silence and the timeout; the next
 *    write is the hold, then the commands as written;
 *  - bad parameters and manifests are refused naming the key and value. */
#define _POSIX_C_SOURCE 200809L
#define ROZ_PRIVATE_ACCESS /* the command path, whose watchdog counts on the test's clock */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>
#include <dds/dds.h>

#include "engineai_pm01_manifest.h"
#include "interface_protocol.h"
#include "port_fixture.h"
#include "port_test.h"
#include "support.h"
#include "support_blocking_log.h"
#include "ros2_fixture.h"
#include "roz/filter.h"
#include "roz/hold.h"
#include "roz/port/engineai_pm01.h"
#include "ur5_manifest.h"

#define N ROZ_ENGINEAI_PM01_JOINTS

static const roz_manifest_t *const m = &roz_manifest_engineai_pm01;
static roz_port_t port;
static double state[ROZ_CFG_MAX_STATES], sent[ROZ_CFG_MAX_STATES];
static double cmd[ROZ_CFG_MAX_COMMANDS];

static void open_pm01_on(const roz_manifest_t *man, const roz_param_t *items, size_t n)
{
    roz_port_test_drive(&roz_fixture_engineai_pm01, man, items, n, &port, state, cmd);
}

static void open_pm01(const roz_param_t *items, size_t n)
{
    open_pm01_on(m, items, n);
}

static int teardown(void **st)
{
    (void)st;
    roz_fixture_engineai_pm01.close();
    return 0;
}

static int cmd_index(uint16_t joint, const char *suffix)
{
    return roz_port_test_joint_command(m, joint, suffix);
}

static int state_index(const char *name)
{
    return roz_port_test_state(m, name);
}

static void get_command(roz_fake_ros2_cmd_t *c)
{
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), 0, c), 1);
}

static void assert_state_is_sent(void)
{
    roz_ros2fx_sent(sent);
    roz_port_test_assert_state(m, state, sent);
}


/* The setpoints the watchdog's hold sends after the command in cmd[] went
 * out against the measured positions @p measured (state order): each
 * joint's setpoint moved to keep the torque it went out with at the hold
 * gain, within the band of the measured position (roz/hold.h), inside the
 * position state's and the command's limits. */
static void watchdog_positions(const double *measured, double *q)
{
    for (uint16_t j = 0; j < N; j++) {
        const roz_channel_t *qc = &m->commands[cmd_index(j, "position")];
        const roz_channel_t *kc = &m->commands[cmd_index(j, "stiffness")];
        const roz_channel_t *qs = &m->states[qc->position_state];
        roz_hold_from_t from = { cmd[cmd_index(j, "position")], cmd[cmd_index(j, "stiffness")],
                                 measured[qc->position_state] };
        double v = roz_hold_setpoint(&from, kc->default_value, roz_hold_band(qc));
        q[j] = roz_channel_clamp(qc, roz_channel_clamp(qs, v));
    }
}

/* ---- mapping ---------------------------------------------------------------------- */

static void test_pm01_joints_map_both_ways(void **st)
{
    roz_fake_ros2_cmd_t c;
    (void)st;

    open_pm01(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    for (int k = 1; k <= 3; k++) {
        roz_ros2fx_send();
        assert_int_equal(roz_port_test_read(), 1);
        assert_state_is_sent();
        roz_port_test_distinct_command(m, k, cmd);
        roz_port_test_write();
        get_command(&c);
        assert_int_equal(c.n, N);       /* every array 24 long */
        assert_int_equal(c.min_len, N);
        assert_int_equal(c.ppt, 1);     /* RL_PARSER */
        for (uint16_t j = 0; j < N; j++) {
            assert_true(c.q[j] == cmd[cmd_index(j, "position")]);
            assert_true(c.dq[j] == cmd[cmd_index(j, "velocity")]);
            assert_true(c.tau[j] == cmd[cmd_index(j, "effort")]); /* feed_forward_torque */
            assert_true(c.kp[j] == cmd[cmd_index(j, "stiffness")]);
            assert_true(c.kd[j] == cmd[cmd_index(j, "damping")]);
            assert_true(c.extra[j] == 0.0); /* torque */
        }
    }
}

/* ---- parallel_parser_type ------------------------------------------------------------ */

/* The last command the robot got, once it counted @p n0 + 1 on its topic. */
static void next_command(uint64_t n0, roz_fake_ros2_cmd_t *c)
{
    uint64_t n[FAKE_ROS2_MAX_GROUPS] = { 0 };
    for (int i = 0; i < 5000 && n[0] <= n0; i++) {
        assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), n), 0);
        if (n[0] <= n0)
            roz_fake_sleep_ms(1);
    }
    assert_true(n[0] > n0);
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), 0, c), 1);
}

/* Every JointCommand of a session carries @p want: the start-up hold, the
 * commands after it, the damping command on deactivate. */
static void expect_parser_on_the_wire(const roz_manifest_t *man, const roz_param_t *items,
                                      size_t n, unsigned want)
{
    roz_fake_ros2_cmd_t c;
    uint64_t counts[FAKE_ROS2_MAX_GROUPS];
    open_pm01_on(man, items, n);
    roz_ros2fx_send();
    assert_int_equal(roz_port_read(&port, state, man->n_states), 1);
    roz_port_test_distinct_command(m, 2, cmd);
    for (int k = 0; k < 3; k++) { /* the hold, then two commands */
        assert_int_equal(roz_port_write(&port, cmd, man->n_commands), ROZ_OK);
        get_command(&c);
        assert_int_equal(c.ppt, want);
    }
    assert_int_equal(roz_ros2fx_counters().holds, 1);
    assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), counts), 0);
    assert_int_equal(roz_port_deactivate(&port), ROZ_OK);
    next_command(counts[0], &c);
    assert_true(c.kp[0] > 0.0); /* the exit's hold */
    assert_int_equal(c.ppt, want);
    roz_fixture_engineai_pm01.close();
}

/* The PM01's manifest with parallel_parser_type in its [hardware.params]. */
static roz_param_t hw_params[4];
static roz_hardware_t hw_with_parser;
static roz_manifest_t with_parser;

static const roz_manifest_t *manifest_with_parser(const char *value)
{
    const roz_hardware_t *hw = m->hardware;
    size_t n = hw->n_params;
    assert_true(n < 4);
    memcpy(hw_params, hw->params, n * sizeof hw_params[0]);
    hw_params[n] = (roz_param_t){ "parallel_parser_type", value };
    hw_with_parser = *hw;
    hw_with_parser.params = hw_params;
    hw_with_parser.n_params = (uint16_t)(n + 1);
    with_parser = *m;
    with_parser.hardware = &hw_with_parser;
    return &with_parser;
}

/* ParallelParserType (interface_protocol): CLASSIC_PARSER 0, RL_PARSER 1;
 * the parameter's default is RL_PARSER, as the vendor's RL example sends;
 * each spelling docs/ports/ros2.md gives reaches the wire as its number, in every
 * command; robot.toml's [hardware.params] sets it, the caller's overrides;
 * anything else is refused at open naming the key and the value. */
static void test_pm01_parallel_parser_type(void **st)
{
    (void)st;
    expect_parser_on_the_wire(m, NULL, 0, 1);
    static const struct { const char *value; unsigned wire; } spellings[] = {
        { "rl", 1 },     { "RL_PARSER", 1 },     { "1", 1 },
        { "classic", 0 }, { "CLASSIC_PARSER", 0 }, { "0", 0 },
    };
    for (size_t i = 0; i < sizeof spellings / sizeof spellings[0]; i++) {
        roz_param_t p = { "parallel_parser_type", spellings[i].value };
        expect_parser_on_the_wire(m, &p, 1, spellings[i].wire);
    }
    expect_parser_on_the_wire(manifest_with_parser("classic"), NULL, 0, 0);
    roz_param_t rl = { "parallel_parser_type", "rl" };
    expect_parser_on_the_wire(manifest_with_parser("classic"), &rl, 1, 1);

    static const char *const bad[] = { "2", "RL", "Classic", "rl ", "-1", "01", "0x1",
                                       "parallel", "" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        static roz_engineai_pm01_t pm;
        roz_param_t item = { "parallel_parser_type", bad[i] };
        roz_params_t p = { &item, 1 };
        roz_port_t pt = roz_engineai_pm01_port(&pm, NULL, NULL);
        char err[400] = "", want[64];
        assert_int_equal(roz_port_open(&pt, m, &p, err, sizeof err), ROZ_EINVAL);
        snprintf(want, sizeof want, "parallel_parser_type = \"%s\"", bad[i]);
        if (strstr(err, want) == NULL || strstr(err, "RL_PARSER") == NULL)
            fail_msg("\"%s\": the error \"%s\" names neither the key and value nor the "
                     "choices",
                     bad[i], err);
        roz_port_close(&pt);
    }
    /* and from robot.toml */
    static roz_engineai_pm01_t pm;
    roz_port_t pt = roz_engineai_pm01_port(&pm, NULL, NULL);
    char err[400] = "";
    assert_int_equal(roz_port_open(&pt, manifest_with_parser("2"), NULL, err, sizeof err),
                     ROZ_EINVAL);
    assert_non_null(strstr(err, "parallel_parser_type = \"2\""));
    roz_port_close(&pt);
}

static void test_pm01_imu_order(void **st)
{
    (void)st;
    open_pm01(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_ask("imu 0.25 -0.125 0.0625 0.5 1.5 -2.5 3.5 0.75 -1.25 9.75");
    roz_ros2fx_ask_judged(0, "send");
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_assert_imu(m, state);
}

/* ---- stamps --------------------------------------------------------------------------- */

static void test_pm01_command_stamps(void **st)
{
    roz_fake_ros2_cmd_t c;
    uint64_t last = 0;
    (void)st;

    open_pm01(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    for (int k = 1; k <= 20; k++) {
        roz_ros2fx_send();
        (void)roz_port_test_read();
        roz_port_test_distinct_command(m, k, cmd);
        uint64_t before = roz_port_test_realtime_ns();
        roz_port_test_write();
        get_command(&c);
        uint64_t after = roz_port_test_realtime_ns();
        uint64_t stamp = (uint64_t)c.sec * 1000000000u + c.nanosec;
        /* the system clock (ROS time) when the writer published it */
        assert_true(c.nanosec <= 999999999u);
        assert_true(stamp >= before && stamp <= after);
        assert_true(stamp >= last);
        last = stamp;
        assert_string_equal(c.frame_id, "-"); /* empty */
    }
}

static void send_judged(void)
{
    roz_ros2fx_ask_judged(0, "send");
}

static void test_pm01_state_stamps_are_the_link(void **st)
{
    roz_link_t l;
    (void)st;

    open_pm01(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    for (int k = 0; k < 10; k++)
        roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_ros2_link(roz_ros2fx_bridge(), &l);
    uint64_t replays = l.replays, restarts = l.restarts;

    /* the same stamp again, new values: a replay on both topics, dropped */
    roz_ros2fx_ask("stamp 1800000000 500000000");
    roz_ros2fx_set_state(50);
    send_judged();
    assert_int_equal(roz_port_test_read(), 1);
    assert_state_is_sent();
    roz_ros2fx_ask("stamp 1800000000 500000000");
    roz_ros2fx_set_state(51);
    send_judged();
    assert_int_equal(roz_port_test_read(), 0);
    roz_ros2_link(roz_ros2fx_bridge(), &l);
    assert_int_equal(l.replays, replays + 2);
    /* half a second back: still a replay */
    roz_ros2fx_ask("stamp 1800000000 0");
    send_judged();
    assert_int_equal(roz_port_test_read(), 0);
    roz_ros2_link(roz_ros2fx_bridge(), &l);
    assert_int_equal(l.replays, replays + 4);
    /* newer again: fresh */
    roz_ros2fx_ask("stamp 1800000001 0");
    roz_ros2fx_set_state(52);
    send_judged();
    assert_int_equal(roz_port_test_read(), 1);
    assert_state_is_sent();
    /* five seconds back: the robot's clock restarted */
    roz_ros2fx_ask("stamp 1799999996 0");
    send_judged();
    assert_int_equal(roz_port_test_read(), ROZ_ELINK);
    roz_ros2_link(roz_ros2fx_bridge(), &l);
    assert_int_equal(l.restarts, restarts + 2);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);

    /* a stamp that is not a time: malformed, dropped, counted */
    uint64_t malformed = roz_ros2fx_counters().topic[0].malformed;
    roz_ros2fx_ask("stamp 1799999997 1000000000");
    roz_ros2fx_ask("send");
    roz_ros2fx_wait_malformed(0, malformed);
    assert_int_equal(roz_port_test_read(), 0);
}

/* A documented limit (SAFETY.md, docs/ports/ros2.md): the PM01's header has
 * no sequence, so a step back of the robot's clock (NTP, PTP, `date`) is not
 * told from a replay. 20 ms back: every sample is dropped as a replay until
 * the robot's clock passes the last stamp taken: as long as stale_ticks
 * periods (10 at 500 Hz) of nothing fresh, so the runtime latches STALE. */
static void test_pm01_clock_step_back_is_a_replay(void **st)
{
    roz_link_t l;
    (void)st;

    open_pm01(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_ask("stamp 1800000000 500000000");
    send_judged();
    assert_int_equal(roz_port_test_read(), 1);
    roz_ros2_link(roz_ros2fx_bridge(), &l);
    uint64_t replays = l.replays, restarts = l.restarts;
    /* the clock steps 20 ms back; it advances 1 ms a sample (on either
     * topic) from there */
    roz_ros2fx_ask("stamp 1800000000 480000000");
    int fresh = 0, sends = 0;
    for (; sends < 40 && fresh == 0; sends++) {
        send_judged();
        fresh = roz_port_test_read() == 1;
    }
    roz_ros2_link(roz_ros2fx_bridge(), &l);
    assert_int_equal(l.restarts, restarts); /* no restart: within the window */
    assert_int_equal(fresh, 1);
    /* the samples before it dropped, on both topics (the last one on one of
     * them only): 2 ms of the robot's clock a send, so 20 ms are 10 sends
     * lost, as many ticks of nothing fresh as stale_ticks */
    print_message("clock 20 ms back: %d sends until fresh, %llu replays\n", sends,
                  (unsigned long long)(l.replays - replays));
    assert_true(l.replays >= replays + 2u * (uint64_t)(sends - 2));
    assert_true(sends - 1 >= 9);
}

/* ---- shapes ----------------------------------------------------------------------------- */

static void test_pm01_arrays_must_be_24_long(void **st)
{
    (void)st;
    /* the notice is kept by the receive thread and said by the drain, on
     * this thread: a log that blocks every other thread never stops it */
    roz_test_blocking_log_arm();
    roz_fixture_engineai_pm01.set_log(roz_test_blocking_log);
    open_pm01(NULL, 0);
    roz_fixture_engineai_pm01.set_log(NULL);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    static const unsigned lengths[] = { 23, 25, 0, 12 };
    for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; i++) {
        uint64_t malformed = roz_ros2fx_counters().topic[0].malformed;
        roz_ros2fx_ask("length body %u", lengths[i]);
        roz_ros2fx_set_state(60 + (uint32_t)i);
        roz_ros2fx_ask("send body");
        roz_ros2fx_wait_malformed(0, malformed);
        assert_int_equal(roz_port_test_read(), 0); /* nothing new, the old frame stays */
    }
    roz_ros2fx_ask("length body 24");
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    assert_state_is_sent();
    unsigned blocked = roz_test_blocking_log_blocked();
    int said = roz_port_drain(&port) >= 1 &&
               roz_test_blocking_log_saw("a sample with 23 joint values, expected 24: dropped");
    int once = !roz_test_blocking_log_saw("a sample with 25 joint values");
    roz_test_blocking_log_release();
    assert_int_equal(blocked, 0);
    assert_true(said);
    assert_true(once);
}

/* ---- the domain -------------------------------------------------------------------------- */

static void test_pm01_domain(void **st)
{
    static roz_engineai_pm01_t pm;
    char err[300] = "";
    (void)st;

    /* the manifest's hardware parameters say 69 */
    roz_param_t lo = { "network_interface", "lo" };
    roz_params_t p = { &lo, 1 };
    roz_port_t pt = roz_engineai_pm01_port(&pm, NULL, NULL);
    assert_int_equal(roz_port_open(&pt, m, &p, err, sizeof err), ROZ_OK);
    assert_int_equal(roz_ros2_dds_params(&pm.b)->domain, 69);
    assert_int_equal(roz_ros2_participant(&pm.b)->domain, 69);
    roz_port_close(&pt);
    /* overridden */
    roz_param_t items[2] = { { "network_interface", "lo" }, { "dds_domain", "7" } };
    p = (roz_params_t){ items, 2 };
    assert_int_equal(roz_port_open(&pt, m, &p, err, sizeof err), ROZ_OK);
    assert_int_equal(roz_ros2_participant(&pm.b)->domain, 7);
    roz_port_close(&pt);
    /* refused */
    items[1].value = "233";
    assert_true(roz_port_open(&pt, m, &p, err, sizeof err) < 0);
    assert_non_null(strstr(err, "dds_domain"));
    assert_non_null(strstr(err, "233"));
    roz_port_close(&pt);
}

/* The robot on its own domain, 69: the port finds it there with nothing but
 * the manifest's parameters. Nothing in it depends on the machine's pace:
 * the command watchdog counts on the test's clock, standing still from
 * before the writer starts (on the real one, a writer thread starved past
 * the default 50 ms judges the only write stale, and the robot never gets
 * a command); the first frame and the first command are each retried until
 * discovery has matched the two sides, 60 s the hang guard. */
static void test_pm01_traffic_on_69(void **st)
{
    roz_fake_ros2_t fake;
    static roz_engineai_pm01_t pm;
    char err[300] = "";
    (void)st;

    assert_int_equal(roz_fake_ros2_start(&fake, "pm01", 69, NULL, err, sizeof err), 0);
    roz_param_t items[2] = { { "network_interface", "lo" }, { "command_writer_period_us", "0" } };
    roz_params_t p = { items, 2 };
    roz_port_t pt = roz_engineai_pm01_port(&pm, NULL, NULL);
    assert_int_equal(roz_port_open(&pt, m, &p, err, sizeof err), ROZ_OK);
    roz_port_test_watchdog_clock(&pm.b.cmd); /* the writer's start takes it */
    assert_int_equal(roz_port_activate(&pt), ROZ_OK);
    int rc = ROZ_ENOENT;
    for (unsigned k = 0; k < 6000 && rc != 1; k++) {
        if (k % 20 == 0) /* a sample sent before discovery is lost: again */
            assert_int_equal(roz_fake_ros2_ask(&fake, "send"), 0);
        roz_fake_sleep_ms(10);
        rc = roz_port_read(&pt, state, m->n_states);
    }
    assert_int_equal(rc, 1);
    int got = 0;
    for (uint32_t k = 1; k <= 600 && !got; k++) {
        /* the fake's reader may not have matched the port's writer yet */
        roz_port_test_distinct_command(m, k, cmd);
        assert_int_equal(roz_port_write(&pt, cmd, m->n_commands), ROZ_OK);
        got = roz_fake_ros2_ask(&fake, "wait_commands body 1 100") == 0;
    }
    assert_true(got);
    roz_ros2_counters_t c;
    roz_ros2_counters(&pm.b, &c);
    assert_int_equal(c.command_timeouts, 0);
    (void)roz_port_deactivate(&pt);
    roz_port_close(&pt);
    assert_int_equal(roz_fake_ros2_stop(&fake), 0);
}

/* ---- ROS 2's names ---------------------------------------------------------------------- */

/* A peer as rmw_cyclonedds is: no type information, so the topics match by
 * their names alone (rt/hardware/..., interface_protocol::msg::dds_::...). */
static void test_pm01_ros2_names(void **st)
{
    static const char *const as_ros2[] = { "--typeinfo", "off", NULL };
    roz_fake_ros2_cmd_t c;
    (void)st;

    roz_ros2fx_set_fake_args(as_ros2);
    open_pm01(NULL, 0); /* matched both ways, or it fails */
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    assert_state_is_sent();
    roz_port_test_distinct_command(m, 2, cmd);
    roz_port_test_write();
    get_command(&c);
    assert_true(c.q[7] == cmd[cmd_index(7, "position")]);

    /* the port's bytes under another type name: never matched */
    const dds_topic_descriptor_t *d = &interface_protocol_msg_dds__JointCommand__desc;
    const struct dds_type_meta_ser none = { NULL, 0 };
    const dds_topic_descriptor_t wrong = {
        .m_size = d->m_size, .m_align = d->m_align,
        .m_flagset = d->m_flagset & ~DDS_TOPIC_XTYPES_METADATA, .m_nkeys = d->m_nkeys,
        .m_typename = "interface_protocol::msg::JointCommand", .m_keys = d->m_keys,
        .m_nops = d->m_nops, .m_ops = d->m_ops, .m_meta = d->m_meta,
        .type_information = none, .type_mapping = none,
        .restrict_data_representation = d->restrict_data_representation,
    };
    dds_entity_t part = dds_create_participant(ROZ_TEST_DDS_DOMAIN, NULL, NULL);
    assert_true(part > 0);
    dds_entity_t topic = dds_create_topic(part, &wrong, "rt/hardware/joint_command", NULL, NULL);
    assert_true(topic > 0);
    dds_qos_t *q = dds_create_qos();
    dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_entity_t rd = dds_create_reader(part, topic, q, NULL);
    dds_delete_qos(q);
    assert_true(rd > 0);
    roz_fake_sleep_ms(500); /* discovery on loopback takes milliseconds */
    dds_subscription_matched_status_t sm;
    assert_int_equal(dds_get_subscription_matched_status(rd, &sm), 0);
    assert_int_equal(sm.total_count, 0);
    uint32_t readers, writers;
    roz_ros2_matched(roz_ros2fx_bridge(), &readers, &writers);
    assert_int_equal(readers, 1); /* the fake's alone */
    dds_delete(part);
}

/* ---- decimation ------------------------------------------------------------------------- */

static void test_pm01_decimation(void **st)
{
    (void)st;

    open_pm01((roz_param_t[]){ { "state_decimation", "4" } }, 1);
    roz_port_test_decimation("J00_HIP_PITCH_L", roz_ros2fx_send, roz_ros2fx_sent);
    assert_int_equal(roz_ros2fx_counters().topic[0].full, 3);
    assert_int_equal(roz_ros2fx_counters().topic[1].full, 3);
    assert_int_equal(roz_ros2fx_counters().frames, 12);
    /* every sample is still checked: a replay between two whole conversions */
    roz_ros2fx_ask_judged(0, "replay");
    assert_int_equal(roz_port_test_read(), 0);
}

/* ---- the writer ---------------------------------------------------------------------------- */

static void test_pm01_periodic_writer(void **st)
{
    roz_fake_ros2_cmd_t c;
    uint64_t n0[FAKE_ROS2_MAX_GROUPS], n[FAKE_ROS2_MAX_GROUPS];
    (void)st;

    open_pm01((roz_param_t[]){ { "command_writer_period_us", "2000" } }, 1);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    for (int k = 0; k < 5; k++)
        roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_distinct_command(m, 3, cmd);
    roz_port_test_write();
    get_command(&c);
    assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), n0), 0);
    n[0] = n0[0];
    for (int i = 0; i < 5000 && n[0] < n0[0] + 50; i++) {
        roz_fake_sleep_ms(2);
        assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), n), 0);
    }
    assert_true(n[0] >= n0[0] + 50);
    get_command(&c);
    assert_true(c.q[5] == cmd[cmd_index(5, "position")]);

    /* a restarted robot gets nothing until the tick writes for it */
    roz_link_t before[ROZ_ROS2_MAX_TOPICS];
    roz_ros2fx_ask("restart");
    roz_ros2fx_links(before);
    roz_ros2fx_set_state(100);
    roz_ros2fx_ask("send");
    roz_ros2fx_wait_judged(before, 0, 1); /* the new writers: again until discovered */
    assert_int_equal(roz_port_test_read(), ROZ_ELINK);
    /* a pass of the writer after it: stale, nothing sent; then what it
     * published before has reached the robot (however slowly a loaded
     * machine runs either), and nothing more comes */
    ROZ_PORT_TEST_WAIT_UNTIL(roz_ros2fx_counters().stale_session >= 1);
    roz_ros2fx_settle();
    uint64_t after[FAKE_ROS2_MAX_GROUPS], later[FAKE_ROS2_MAX_GROUPS];
    uint64_t published = roz_ros2fx_counters().published;
    assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), after), 0);
    roz_fake_sleep_ms(50);
    assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), later), 0);
    assert_int_equal(later[0], after[0]);
    assert_int_equal(roz_ros2fx_counters().published, published);
    /* the tick writes: the hold of the restarted robot's positions */
    roz_port_test_distinct_command(m, 4, cmd);
    roz_port_test_write();
    get_command(&c);
    roz_ros2fx_sent(sent);
    assert_true(c.q[3] == sent[state_index("J03_KNEE_PITCH_L/position")]);
    assert_true(c.kp[3] == 0.0 && c.kd[3] == 0.0);

    roz_monitor_stat_t s;
    assert_int_equal(roz_monitor_snapshot(roz_ros2_writer_monitor(roz_ros2fx_bridge()),
                                          ROZ_MON_JITTER, &s),
                     ROZ_OK);
    assert_true(s.count >= 50);
    assert_int_equal(
        roz_monitor_snapshot(roz_ros2_topic_monitor(roz_ros2fx_bridge(), 0),
                             ROZ_MON_STATE_HANDLER, &s),
        ROZ_OK);
    assert_true(s.count >= 1);
}


/* The PM01 on @p man, its command watchdog on the test's clock
 * (roz_port_test_watched). */
static void open_pm01_watched(const roz_manifest_t *man)
{
    open_pm01_on(man, roz_port_test_watched, ROZ_PORT_TEST_WATCHED_N);
    roz_port_test_watchdog_clock(&roz_ros2fx_bridge()->cmd);
}

/* The tick stops after its last write: 100 ms of silence on the watchdog's
 * clock is not yet a trip, 1 ns more is (roz_port_test_watchdog_trip());
 * @p c the robot's command once @p more have come since. */
static void silence_trips(unsigned more, roz_fake_ros2_cmd_t *c)
{
    uint64_t n0[FAKE_ROS2_MAX_GROUPS];
    roz_port_test_watchdog_trip(&roz_ros2fx_bridge()->cmd, 100000u, roz_ros2fx_commands);
    assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), n0), 0);
    assert_int_equal(roz_fake_ros2_ask(roz_ros2fx_fake(), "wait_commands %s %llu 20000",
                                       roz_ros2fx_fake()->group[0],
                                       (unsigned long long)n0[0] + more),
                     0);
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), 0, c), 1);
}

static void test_pm01_watchdog(void **st)
{
    roz_fake_ros2_cmd_t c;
    double q[N];
    (void)st;

    open_pm01_watched(m);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_ros2fx_sent(sent);
    roz_port_test_distinct_command(m, 1, cmd);
    watchdog_positions(sent, q);
    roz_port_test_write();
    get_command(&c);
    assert_true(c.kp[3] == cmd[cmd_index(3, "stiffness")]);
    assert_int_equal(roz_ros2fx_counters().command_timeouts, 0);

    /* the tick stops: 100 ms on the watchdog's clock is not yet a trip, 1 ns
     * more is */
    silence_trips(5u, &c);
    for (uint16_t j = 0; j < N; j++) {
        const roz_channel_t *kd = &m->commands[cmd_index(j, "damping")];
        const roz_channel_t *kp = &m->commands[cmd_index(j, "stiffness")]; /* the hold gain */
        if (c.q[j] != q[j] || c.kp[j] != kp->default_value || c.dq[j] != 0.0 || c.tau[j] != 0.0 ||
            c.extra[j] != 0.0 || c.kd[j] != kd->default_value)
            fail_msg("joint %u after the tick stopped: q %g kp %g kd %g dq %g tau %g: not the "
                     "watchdog's hold",
                     (unsigned)j, c.q[j], c.kp[j], c.kd[j], c.dq[j], c.tau[j]);
    }
    assert_true(roz_ros2fx_counters().safe_published >= 5);
    assert_int_equal(roz_ros2fx_counters().command_timeouts, 1);

    /* the tick is back: reported once with the silence; the hold; then as
     * written */
    roz_port_fault_t f;
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EWATCHDOG);
    assert_int_equal(roz_engineai_pm01_ops.fault(port.self, &f), ROZ_OK);
    assert_string_equal(f.what, "command_timeout_us");
    assert_int_equal(f.limit, 100000);
    assert_int_equal(f.code, 100000); /* the silence by the watchdog's clock, in us */
    assert_int_equal(roz_port_test_read(), 0);
    /* the stop's hold from the last command before the trip, at the hold
     * gains and the damping command's kd: never a frame without stiffness
     * between the watchdog's hold and the tick's */
    double before_trip[ROZ_CFG_MAX_COMMANDS];
    memcpy(before_trip, cmd, sizeof before_trip);
    roz_port_test_distinct_command(m, 2, cmd);
    roz_port_test_write();
    get_command(&c);
    roz_ros2fx_sent(sent);
    {
        const roz_channel_t *qc = &m->commands[cmd_index(3, "position")];
        const roz_channel_t *kc = &m->commands[cmd_index(3, "stiffness")];
        roz_hold_from_t from = { before_trip[cmd_index(3, "position")],
                                 before_trip[cmd_index(3, "stiffness")],
                                 sent[qc->position_state] };
        double want = roz_channel_clamp(qc, roz_hold_setpoint(&from, kc->default_value,
                                                              roz_hold_band(qc)));
        assert_true(fabs(c.q[3] - want) < 1e-12);
        assert_true(c.kp[3] == kc->default_value);
    }
    assert_true(c.kd[3] == m->commands[cmd_index(3, "damping")].default_value);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_distinct_command(m, 3, cmd);
    roz_port_test_write();
    get_command(&c);
    assert_true(c.kp[3] == cmd[cmd_index(3, "stiffness")]);
    assert_true(c.q[3] == cmd[cmd_index(3, "position")]);
}

/* Joint @p j's position in the fake's next frame (its velocity and
 * effort 0). */
static void fake_position(uint16_t j, const char *q)
{
    int g, s;
    assert_int_equal(roz_ros2fx_place(j, &g, &s), 0);
    roz_ros2fx_ask("joint %s %d %s 0 0", roz_ros2fx_fake()->group[g], s, q);
}

/* The watchdog's hold keeps the torque each joint went out with, as the
 * filter's hold and the G1 port's watchdog do (SAFETY.md, section 7): the
 * left knee held with kp 80 at 0.5 rad, measured at 0.9, goes on at its
 * hold gain kh (200) at 0.9 + 80 (0.5 - 0.9) / 200 = 0.74; the left hip
 * pitch held hard (kp 500) near its upper limit, from 0.5 rad below it,
 * gets the band's edge (5 rate caps above where it is: roz_hold_band()),
 * not the limit the torque would push it to; the right knee, NaN in the
 * last frame, keeps its torque about its last finite position (0.6); every
 * joint by the same rule, every value finite. */
static void test_pm01_watchdog_keeps_the_torque(void **st)
{
    roz_fake_ros2_cmd_t c;
    double q[N], measured[ROZ_CFG_MAX_STATES];
    const uint16_t knee_l = 3, hip_l = 0, knee_r = 9;
    const roz_channel_t *hip_q = &m->commands[cmd_index(hip_l, "position")];
    char hip_at[64];
    (void)st;

    open_pm01_watched(m);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    /* the frame the command goes out against: the right knee at 0.6, then
     * NaN (the port keeps 0.6, the last finite one) */
    roz_ros2fx_send();
    snprintf(hip_at, sizeof hip_at, "%.17g", hip_q->max - 0.5);
    fake_position(knee_l, "0.9");
    fake_position(hip_l, hip_at);
    fake_position(knee_r, "0.6");
    roz_ros2fx_ask_judged(0, "send");
    assert_int_equal(roz_port_test_read(), 1);
    fake_position(knee_r, "nan");
    roz_ros2fx_ask_judged(0, "send");
    assert_int_equal(roz_port_test_read(), 1);
    assert_true(isnan(state[m->commands[cmd_index(knee_r, "position")].position_state]));
    memcpy(measured, state, sizeof measured);
    measured[m->commands[cmd_index(knee_r, "position")].position_state] = 0.6;

    roz_port_test_distinct_command(m, 1, cmd);
    cmd[cmd_index(knee_l, "position")] = 0.5;
    cmd[cmd_index(knee_l, "stiffness")] = 80.0;
    cmd[cmd_index(hip_l, "position")] = hip_q->max - 0.01;
    cmd[cmd_index(hip_l, "stiffness")] = 500.0;
    watchdog_positions(measured, q);
    roz_port_test_write();
    get_command(&c);
    assert_true(c.kp[knee_l] == 80.0 && c.q[knee_l] == 0.5);

    /* the tick stops */
    silence_trips(2u, &c);
    double kh = m->commands[cmd_index(knee_l, "stiffness")].default_value;
    print_message("left knee: kp 80 at 0.5, measured 0.9: the watchdog's hold kp %g at %.6f; "
                  "left hip pitch: kp 500 at %.4f, measured %.4f: at %.4f (its limit %.4f)\n",
                  c.kp[knee_l], c.q[knee_l], cmd[cmd_index(hip_l, "position")],
                  hip_q->max - 0.5, c.q[hip_l], hip_q->max);
    assert_true(c.kp[knee_l] == kh && kh == 200.0);
    assert_true(fabs(c.q[knee_l] - (0.9 + 80.0 * (0.5 - 0.9) / kh)) < 1e-12);
    assert_true(fabs(c.q[hip_l] - (hip_q->max - 0.5 + roz_hold_band(hip_q))) < 1e-12);
    assert_true(c.q[hip_l] < hip_q->max - 0.2);
    {
        roz_hold_from_t from = { cmd[cmd_index(knee_r, "position")],
                                 cmd[cmd_index(knee_r, "stiffness")], 0.6 };
        assert_true(fabs(c.q[knee_r] - roz_hold_setpoint(&from, kh, roz_hold_band(&m->commands[
                                                                 cmd_index(knee_r, "position")]))) <
                    1e-12);
    }
    for (uint16_t j = 0; j < N; j++) {
        const roz_channel_t *kd = &m->commands[cmd_index(j, "damping")];
        const roz_channel_t *kp = &m->commands[cmd_index(j, "stiffness")];
        const roz_channel_t *qc = &m->commands[cmd_index(j, "position")];
        if (!isfinite(c.q[j]) || c.q[j] != q[j] || c.q[j] < qc->min || c.q[j] > qc->max ||
            c.kp[j] != kp->default_value || c.dq[j] != 0.0 || c.tau[j] != 0.0 ||
            c.kd[j] != kd->default_value)
            fail_msg("joint %u after the tick stopped: q %g (expected %g) kp %g kd %g dq %g "
                     "tau %g: not the watchdog's hold",
                     (unsigned)j, c.q[j], q[j], c.kp[j], c.kd[j], c.dq[j], c.tau[j]);
    }
}

/* A joint with a stiffness command but no position command, whose position
 * the robot reports NaN when the tick goes silent: the watchdog's hold keeps
 * it at the last position measured finite (the fixture's first frames), at
 * its hold gain, inside its position state's limits; never at 0 rad for
 * want of a command. */
static void test_pm01_watchdog_without_a_position_command(void **st)
{
    static roz_channel_t cmds[ROZ_CFG_MAX_COMMANDS];
    static roz_manifest_t kneeless;
    static double kcmd[ROZ_CFG_MAX_COMMANDS], kstate[ROZ_CFG_MAX_STATES];
    roz_fake_ros2_cmd_t c;
    const uint16_t knee = 3, hip = 0;
    (void)st;
    uint16_t n = 0;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (strcmp(m->commands[i].name, "J03_KNEE_PITCH_L/position") != 0)
            cmds[n++] = m->commands[i];
    }
    kneeless = *m;
    kneeless.commands = cmds;
    kneeless.n_commands = n;
    open_pm01_watched(&kneeless);
    fake_position(knee, "nan");
    roz_ros2fx_send();
    assert_int_equal(roz_port_read(&port, kstate, kneeless.n_states), 1);
    roz_port_test_distinct_command(&kneeless, 1, kcmd);
    for (int k = 0; k < 2; k++) /* the start-up hold, then the command */
        assert_int_equal(roz_port_write(&port, kcmd, kneeless.n_commands), ROZ_OK);
    get_command(&c);
    roz_port_test_watchdog_trip(&roz_ros2fx_bridge()->cmd, 100000u, roz_ros2fx_commands);
    roz_ros2fx_settle();
    ROZ_PORT_TEST_WAIT_UNTIL(roz_fake_ros2_command(roz_ros2fx_fake(), 0, &c) == 1 &&
                             c.kp[hip] == 200.0);
    const roz_channel_t *ks = &kneeless.states[roz_port_test_state(&kneeless,
                                                                    "J03_KNEE_PITCH_L/position")];
    print_message("left knee without a position command, reported NaN: the watchdog's hold q %g "
                  "kp %g (the hip's kp %g)\n", c.q[knee], c.kp[knee], c.kp[hip]);
    assert_true(c.kp[knee] == 200.0);
    assert_true(isfinite(c.q[knee]) && c.q[knee] >= ks->min && c.q[knee] <= ks->max);
    assert_true(c.q[knee] != 0.0);
}

static void test_pm01_startup_and_shutdown_damping(void **st)
{
    roz_fake_ros2_cmd_t c;
    (void)st;

    /* damping on exit, chosen (the default is the hold) */
    open_pm01((roz_param_t[]){ { "startup_damping", "2.5" }, { "exit_stop", "damping" } }, 2);
    /* nothing before the first frame */
    roz_port_test_distinct_command(m, 0, cmd);
    roz_port_test_write();
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), 0, &c), 0);
    assert_int_equal(roz_ros2fx_counters().writes_withheld, 1);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_ros2fx_sent(sent);
    roz_port_test_distinct_command(m, 1, cmd);
    roz_port_test_write(); /* the first write: the hold */
    get_command(&c);
    for (uint16_t j = 0; j < N; j++) {
        char name[160];
        snprintf(name, sizeof name, "%s/position", m->hardware->joints[j]);
        assert_true(c.q[j] == sent[state_index(name)]);
        assert_true(c.kp[j] == 0.0 && c.dq[j] == 0.0 && c.tau[j] == 0.0);
        assert_true(c.kd[j] == 2.5);
    }
    assert_int_equal(roz_ros2fx_counters().holds, 1);
    roz_port_test_write();
    get_command(&c);
    assert_true(c.kp[0] == cmd[cmd_index(0, "stiffness")]);

    /* shutdown: the damping command, kd the manifest's damping default,
     * repeated for ROZ_DDS_SHUTDOWN_REPEAT_MS (the robot's reader may be best
     * effort and lose one): all of them, or on a loaded machine most */
    const uint64_t repeats = ROZ_DDS_SHUTDOWN_REPEAT_MS * 1000u / ROZ_DDS_SHUTDOWN_REPEAT_US;
    uint64_t n0[FAKE_ROS2_MAX_GROUPS], n[FAKE_ROS2_MAX_GROUPS];
    assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), n0), 0);
    assert_int_equal(roz_port_deactivate(&port), ROZ_OK);
    ROZ_PORT_TEST_WAIT_UNTIL(roz_fake_ros2_commands(roz_ros2fx_fake(), n) == 0 && n[0] > n0[0]);
    for (int i = 0; i < 2000 && n[0] < n0[0] + repeats; i++) {
        roz_fake_sleep_ms(1);
        assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), n), 0);
    }
    assert_true(n[0] > n0[0] && n[0] <= n0[0] + repeats);
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), 0, &c), 1);
    assert_int_equal(c.min_len, N);
    for (uint16_t j = 0; j < N; j++) {
        const roz_channel_t *kd = &m->commands[cmd_index(j, "damping")];
        assert_true(c.kp[j] == 0.0 && c.dq[j] == 0.0 && c.tau[j] == 0.0);
        assert_true(c.kd[j] == kd->default_value);
        assert_true(c.q[j] == cmd[cmd_index(j, "position")]);
    }
}

/* ---- a manifest of fewer joints, in another order ------------------------------------------ */

/* Two joints, listed right hip roll first, then left hip roll (indices 7 and
 * 1): each found by its name, not by its place in the list (the names are
 * not on the wire; by place, the left hip roll would get the right's
 * command, outside its own limits). The rest of the robot's 24 get their
 * measured positions and zero gains. */
static const roz_channel_t two_commands[] = {
    { .name = "J07_HIP_ROLL_R/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -2.094,
      .max = 0.436, .default_value = 0.0, .max_rate = 0.0, .position_state = 0 },
    { .name = "J01_HIP_ROLL_L/stiffness", .type = ROZ_IF_STIFFNESS, .unit = "", .min = 0.0,
      .max = 100.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_channel_t two_states[] = {
    { .name = "J07_HIP_ROLL_R/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -2.094,
      .max = 0.436, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "J01_HIP_ROLL_L/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -0.436,
      .max = 2.094, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const char *const two_joints[] = { "J07_HIP_ROLL_R", "J01_HIP_ROLL_L" };
static const roz_hardware_t two_hw = { "engineai/PM01", two_joints, 2, NULL, 0 };
static const roz_manifest_t two = { "two", "humanoid", 500, two_commands, 2, two_states, 2,
                                    &two_hw, NULL, 0, 0, NULL, NULL };

static void test_pm01_joints_by_name(void **st)
{
    roz_fake_ros2_cmd_t c;
    char err[300] = "";
    (void)st;
    if (roz_fixture_engineai_pm01.open(&two, NULL, &port, err, sizeof err) != ROZ_OK)
        fail_msg("open: %s", err);
    roz_ros2fx_ask("joint body 5 0.375 0 0");
    roz_ros2fx_ask("joint body 0 0.125 0 0");
    roz_ros2fx_ask("joint body 1 0.25 0 0");
    roz_ros2fx_ask("joint body 7 -0.5 0 0");
    double st2[2], cmd2[2] = { -1.5, 80.0 };
    int rc = ROZ_ENOENT;
    for (int ms = 0; ms < 10000 && rc != 1; ms += 10) {
        if (ms % 500 == 0) /* until the fake's writer found the port's reader */
            roz_ros2fx_ask("send body");
        roz_fake_sleep_ms(10);
        rc = roz_port_read(&port, st2, 2); /* no IMU channel: joint_state alone */
    }
    assert_int_equal(rc, 1);
    assert_true(st2[0] == -0.5 && st2[1] == 0.25);
    assert_int_equal(roz_port_write(&port, cmd2, 2), ROZ_OK); /* the hold */
    roz_ros2fx_settle(); /* the writes after it are holds until it went out */
    assert_int_equal(roz_port_write(&port, cmd2, 2), ROZ_OK);
    get_command(&c);
    assert_int_equal(c.min_len, N);
    assert_true(c.q[7] == -1.5 && c.kp[7] == 0.0);
    assert_true(c.q[1] == 0.25 && c.kp[1] == 80.0); /* no position command: its own */
    for (unsigned i = 0; i < N; i++) {
        if (i == 1 || i == 7)
            continue;
        assert_true(c.kp[i] == 0.0 && c.kd[i] == 0.0 && c.tau[i] == 0.0);
    }
    assert_true(c.q[0] == 0.125 && c.q[5] == 0.375);

    /* NaN and Inf from the robot never go back out: the joint without a
     * position command keeps its last finite position under its stiffness,
     * a slot of no manifest joint its last finite one */
    roz_ros2fx_ask("joint body 1 nan 0 0");
    roz_ros2fx_ask("joint body 0 inf 0 0");
    rc = 0;
    for (int ms = 0; ms < 10000 && rc != 1; ms += 10) {
        if (ms % 500 == 0)
            roz_ros2fx_ask("send body");
        roz_fake_sleep_ms(10);
        rc = roz_port_read(&port, st2, 2);
    }
    assert_int_equal(rc, 1);
    assert_true(isnan(st2[1])); /* the runtime sees what the robot said */
    assert_int_equal(roz_port_write(&port, cmd2, 2), ROZ_OK);
    get_command(&c);
    for (unsigned i = 0; i < N; i++) {
        if (!isfinite(c.q[i]) || !isfinite(c.kp[i]) || !isfinite(c.kd[i]) ||
            !isfinite(c.dq[i]) || !isfinite(c.tau[i]))
            fail_msg("slot %u: q %g kp %g kd %g: not finite on the wire", i, c.q[i], c.kp[i],
                     c.kd[i]);
    }
    assert_true(c.q[1] == 0.25 && c.kp[1] == 80.0);
    assert_true(c.q[0] == 0.125 && c.kp[0] == 0.0);
}

/* ---- refusals ------------------------------------------------------------------------------- */

static void expect_refused(const roz_manifest_t *man, const char *key, const char *value,
                           const char *want1, const char *want2)
{
    static roz_engineai_pm01_t pm;
    roz_port_t pt = roz_engineai_pm01_port(&pm, NULL, NULL);
    roz_port_test_expect_refused(&pt, man, key, value, want1, want2);
}

static const char *const many_joints[25] = { "j0",  "j1",  "j2",  "j3",  "j4",  "j5",  "j6",
                                             "j7",  "j8",  "j9",  "j10", "j11", "j12", "j13",
                                             "j14", "j15", "j16", "j17", "j18", "j19", "j20",
                                             "j21", "j22", "j23", "j24" };
static const roz_channel_t many_commands[] = {
    { .name = "j24/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_hardware_t many_hw = { "engineai/PM01", many_joints, 25, NULL, 0 };
static const roz_manifest_t many = { "many", "humanoid", 500, many_commands, 1, NULL, 0,
                                     &many_hw, NULL, 0, 0, NULL, NULL };
/* a joint that is not the robot's, where a PM01 joint would be by place */
static const char *const stranger_joints[] = { "J00_HIP_PITCH_L", "left_knee" };
static const roz_channel_t stranger_commands[] = {
    { .name = "J00_HIP_PITCH_L/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "left_knee/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_hardware_t stranger_hw = { "engineai/PM01", stranger_joints, 2, NULL, 0 };
static const roz_manifest_t stranger = { "stranger", "humanoid", 500, stranger_commands, 2,
                                         NULL, 0, &stranger_hw, NULL, 0, 0, NULL, NULL };

static void test_pm01_bad_parameters(void **st)
{
    (void)st;
    static const struct { const char *key, *value; } bad[] = {
        { "network_interface", "eth0;rm" }, { "network_interface", "roznosuch0" },
        { "dds_domain", "999" },            { "command_writer_period_us", "10" },
        { "state_decimation", "0" },        { "enable_monitor", "maybe" },
        { "peer_timeout_ms", "5" },         { "startup_damping", "11" },
        { "shutdown_damping", "-1" },       { "parallel_parser_type", "2" },
        { "link_check", "sequence" },       { "link_check", "crc" },
        { "command_timeout_us", "1000" },   { "command_timeout_us", "60000001" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        expect_refused(m, bad[i].key, bad[i].value, bad[i].key, bad[i].value);
    expect_refused(m, "no_such_key", "1", "no_such_key", "engineai/PM01");
    expect_refused(m, "mode_pr", "PR", "mode_pr", "engineai/PM01"); /* the G1's, not ours */
    expect_refused(&roz_manifest_ur5, NULL, NULL, "[hardware] joints", NULL);
    expect_refused(&many, NULL, NULL, "25 joints", "24");
    expect_refused(&stranger, NULL, NULL, "joints[1] \"left_knee\"", "not one of the robot's");
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_pm01_joints_map_both_ways, teardown),
              cmocka_unit_test_teardown(test_pm01_parallel_parser_type, teardown),
              cmocka_unit_test_teardown(test_pm01_imu_order, teardown),
              cmocka_unit_test_teardown(test_pm01_command_stamps, teardown),
              cmocka_unit_test_teardown(test_pm01_state_stamps_are_the_link, teardown),
              cmocka_unit_test_teardown(test_pm01_clock_step_back_is_a_replay, teardown),
              cmocka_unit_test_teardown(test_pm01_arrays_must_be_24_long, teardown),
              cmocka_unit_test(test_pm01_domain),
              cmocka_unit_test(test_pm01_traffic_on_69),
              cmocka_unit_test_teardown(test_pm01_ros2_names, teardown),
              cmocka_unit_test_teardown(test_pm01_decimation, teardown),
              cmocka_unit_test_teardown(test_pm01_periodic_writer, teardown),
              cmocka_unit_test_teardown(test_pm01_watchdog, teardown),
              cmocka_unit_test_teardown(test_pm01_watchdog_keeps_the_torque, teardown),
              cmocka_unit_test_teardown(test_pm01_startup_and_shutdown_damping, teardown),
              cmocka_unit_test_teardown(test_pm01_watchdog_without_a_position_command, teardown),
              cmocka_unit_test_teardown(test_pm01_joints_by_name, teardown),
              cmocka_unit_test(test_pm01_bad_parameters))
