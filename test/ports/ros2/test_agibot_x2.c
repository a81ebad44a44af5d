/* SPDX-License-Identifier: Apache-2.0 */
/* The X2 port (roz/port/agibot_x2.h) against the fake robot (fake_ros2 --robot
 * x2: its own IDL and robot description, a separate process) over loopback
 * DDS, beyond the conformance suite:
 *  - all 30 joints map both ways by name, a distinct value per joint and
 *    field: the states gathered from the four group topics, the commands
 *    scattered back per group, every slot named with the robot's name, the
 *    head's placeholder slot passive (its measured position, no gains);
 *    each topic's header sequence counts from 1, stamps from the system
 *    clock; the torso IMU in order; a peer without type information (as
 *    rmw_cyclonedds) matched by the names alone;
 *  - the frame is fresh only once every group and the IMU delivered: a
 *    group that falls silent makes the state stale on its own, and the
 *    runtime latches STALE while the other groups go on;
 *  - a group's DomainErrorState (1..4) latches ROBOT naming the group and
 *    the state, for as long as it is reported; a joint's error code names
 *    the joint and the code; one reported in a single sample, overtaken by
 *    a clean one before the tick read, is reported all the same;
 *  - the documentation's JointState layout, asked for by joint_state_layout
 *    = docs, reads right; what the wrong layout does either way;
 *  - a joint named otherwise than its slot, and a group of the wrong
 *    length, are dropped and counted;
 *  - link_check = stamp takes the header stamps instead of the sequence;
 *  - the command watchdog (on a clock the test moves): with the tick silent
 *    every driven group gets the watchdog's hold in the X2's messages; the
 *    trip reported, a hold next;
 *  - a manifest of the leg alone reads and drives the leg topic alone;
 *  - bad parameters and joints not on the X2 are refused by name. */
#define _POSIX_C_SOURCE 200809L
#define ROZ_PRIVATE_ACCESS /* the command path's test hook */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "agibot_x2_manifest.h"
#include "port_fixture.h"
#include "port_test.h"
#include "ros2_fixture.h"
#include "roz/filter.h"
#include "roz/hold.h"
#include "roz/port/agibot_x2.h"
#include "roz/runtime.h"
#include "support.h"
#include "support_runtime.h"

static const roz_manifest_t *const m = &roz_manifest_agibot_x2;
static roz_port_t port;
static double state[ROZ_CFG_MAX_STATES], sent[ROZ_CFG_MAX_STATES];
static double cmd[ROZ_CFG_MAX_COMMANDS];

enum { LEG = 0, WAIST, ARM, HEAD, IMU };

static void open_x2_on(const roz_manifest_t *man, const roz_param_t *items, size_t n)
{
    roz_port_test_drive(&roz_fixture_agibot_x2, man, items, n, &port, state, cmd);
}

static void open_x2(const roz_param_t *items, size_t n)
{
    open_x2_on(m, items, n);
}

/* The X2 on @p man, its command watchdog on the test's clock
 * (roz_port_test_watched). */
static void open_x2_watched(const roz_manifest_t *man)
{
    open_x2_on(man, roz_port_test_watched, ROZ_PORT_TEST_WATCHED_N);
    roz_port_test_watchdog_clock(&roz_ros2fx_bridge()->cmd);
}

static int teardown(void **st)
{
    (void)st;
    roz_fixture_agibot_x2.close();
    return 0;
}

static int state_index(const char *name)
{
    return roz_port_test_state(m, name);
}

static int cmd_of(const char *joint, const char *suffix)
{
    return roz_port_test_command(m, joint, suffix, 0);
}

static void assert_state_is_sent(void)
{
    roz_ros2fx_sent(sent);
    roz_port_test_assert_state(m, state, sent);
}

/* ---- mapping ---------------------------------------------------------------------- */

static void test_x2_joints_map_both_ways(void **st)
{
    roz_fake_ros2_t *fake;
    roz_fake_ros2_cmd_t c;
    uint32_t seq[FAKE_ROS2_MAX_GROUPS] = { 0 };
    (void)st;

    open_x2(NULL, 0);
    fake = roz_ros2fx_fake();
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    for (unsigned g = 0; g < fake->n_groups; g++) {
        assert_int_equal(roz_fake_ros2_command(fake, g, &c), 1);
        seq[g] = c.seq; /* the hold: each topic's first sample */
        assert_int_equal(seq[g], 1);
    }
    for (int k = 1; k <= 3; k++) {
        roz_ros2fx_send();
        assert_int_equal(roz_port_test_read(), 1);
        assert_state_is_sent();
        roz_port_test_distinct_command(m, k, cmd);
        uint64_t before = roz_port_test_realtime_ns();
        roz_port_test_write();
        roz_ros2fx_settle();
        uint64_t after = roz_port_test_realtime_ns();
        roz_ros2fx_sent(sent);
        for (unsigned g = 0; g < fake->n_groups; g++) {
            assert_int_equal(roz_fake_ros2_command(fake, g, &c), 1);
            assert_int_equal(c.n, fake->n_joints[g]); /* every slot of the group */
            assert_int_equal(c.seq, seq[g] + 1);      /* per topic, one per pass */
            seq[g] = c.seq;
            uint64_t stamp = (uint64_t)c.sec * 1000000000u + c.nanosec;
            assert_true(stamp >= before && stamp <= after);
            for (unsigned s = 0; s < c.n; s++) {
                const char *joint = fake->joint[g][s];
                assert_string_equal(c.name[s], joint); /* named */
                int qi = cmd_of(joint, "position");
                if (qi < 0) {
                    /* the head's placeholder: no joint of the manifest */
                    assert_string_equal(joint, "head_pitch_joint");
                    assert_true(c.kp[s] == 0.0 && c.kd[s] == 0.0 && c.tau[s] == 0.0 &&
                                c.dq[s] == 0.0);
                    continue;
                }
                assert_true(c.q[s] == cmd[qi]);
                assert_true(c.dq[s] == cmd[cmd_of(joint, "velocity")]);
                assert_true(c.tau[s] == cmd[cmd_of(joint, "effort")]);
                assert_true(c.kp[s] == cmd[cmd_of(joint, "stiffness")]);
                assert_true(c.kd[s] == cmd[cmd_of(joint, "damping")]);
            }
        }
    }
}

static void test_x2_imu_order(void **st)
{
    (void)st;
    open_x2(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_ask("imu 0.25 -0.125 0.0625 0.5 1.5 -2.5 3.5 0.75 -1.25 9.75");
    roz_ros2fx_ask_judged(0, "send");
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_assert_imu(m, state);
}

/* A peer as rmw_cyclonedds is (no type information): matched by topic and
 * type name alone, both ways, on every group and the IMU. */
static void test_x2_ros2_names(void **st)
{
    static const char *const as_ros2[] = { "--typeinfo", "off", NULL };
    roz_fake_ros2_cmd_t c;
    (void)st;
    roz_ros2fx_set_fake_args(as_ros2);
    open_x2(NULL, 0); /* matched both ways, or it fails */
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    assert_state_is_sent();
    roz_port_test_distinct_command(m, 5, cmd);
    roz_port_test_write();
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), HEAD, &c), 1);
    assert_true(c.q[0] == cmd[cmd_of("head_yaw_joint", "position")]);
}

/* ---- the frame: every group ----------------------------------------------------------- */

static void test_x2_fresh_needs_every_group(void **st)
{
    double before[ROZ_CFG_MAX_STATES];
    (void)st;

    open_x2(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    memcpy(before, state, sizeof before);
    /* three groups and the IMU: not a frame yet; the old one stays */
    roz_ros2fx_set_state(40);
    roz_ros2fx_ask_judged((1u << LEG) | (1u << WAIST) | (1u << ARM) | (1u << IMU),
                          "send leg waist arm imu");
    assert_int_equal(roz_port_test_read(), 0);
    assert_memory_equal(state, before, m->n_states * sizeof state[0]);
    roz_ros2fx_ask_judged((1u << LEG) | (1u << ARM), "send leg arm");
    assert_int_equal(roz_port_test_read(), 0);
    /* the head at last: the frame, with every topic's latest */
    roz_ros2fx_ask_judged(1u << HEAD, "send head");
    assert_int_equal(roz_port_test_read(), 1);
    assert_state_is_sent();
    assert_int_equal(roz_port_test_read(), 0);
}

static roz_runtime_t rt;

static void tick_rt(void)
{
    roz_port_test_tick(&rt);
}

/* The runtime over the port (without the fall rule:
 * roz_port_test_without_fall()), the X2's stand controller started, on
 * @p clk, without the jitter monitor, STALE after @p stale_ticks. */
static void start_runtime(uint32_t stale_ticks, roz_test_clock_t *clk)
{
    roz_runtime_config_t cfg;
    roz_test_runtime_config(&cfg, roz_port_test_without_fall(m), port, clk);
    cfg.monitor_jitter = 0;
    cfg.stale_ticks = stale_ticks;
    roz_test_runtime_start(&rt, &cfg, "x2_stand");
}

/* One group falls silent while the others go on: STALE, on its own. */
static void test_x2_silent_group_is_stale(void **st)
{
    roz_test_clock_t clk = { 1, 1000 };
    (void)st;

    open_x2(NULL, 0);
    start_runtime(5, &clk);
    for (int t = 0; t < 20; t++) {
        roz_ros2fx_send();
        tick_rt();
    }
    assert_int_equal(roz_runtime_faults(&rt), 0);
    for (int t = 0; t < 6; t++) {
        roz_ros2fx_set_state(200u + (uint32_t)t);
        roz_ros2fx_ask_judged((1u << LEG) | (1u << WAIST) | (1u << HEAD) | (1u << IMU),
                              "send leg waist head imu");
        tick_rt();
    }
    assert_int_equal(roz_runtime_faults(&rt) & ROZ_FAULT_STALE, ROZ_FAULT_STALE);
    roz_runtime_deinit(&rt);
}

/* ---- the robot's faults ---------------------------------------------------------------- */

static void test_x2_error_states_latch(void **st)
{
    static const char *const kinds[5] = { NULL, "damping", "power-off", "disabled",
                                          "communication lost" };
    (void)st;

    open_x2(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    for (unsigned v = 1; v <= 4; v++) {
        roz_ros2fx_ask("error waist %u", v);
        roz_ros2fx_send();
        assert_int_equal(roz_port_test_read(), ROZ_EROBOT);
        roz_port_test_assert_fault("waist", kinds[v], v);
        roz_ros2fx_send(); /* a level: every frame while it lasts */
        assert_int_equal(roz_port_test_read(), ROZ_EROBOT);
    }
    roz_ros2fx_ask("error waist 0");
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    assert_true(roz_ros2fx_counters().topic[WAIST].fault_frames >= 8);

    /* a joint's error code: the joint and the code */
    roz_ros2fx_ask("joint_error leg 3 17");
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EROBOT);
    roz_port_test_assert_fault("left_knee_joint", "error_code", 17);
    roz_ros2fx_ask("joint_error leg 3 0");
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
}

/* A fault the robot reports in one sample only is not lost because a clean
 * sample followed before the tick read (the topics are latest-value): the
 * receive thread holds it until the tick took a frame that carries it, and
 * the tick until it read a fresh frame. */
static void test_x2_brief_error_state_is_not_lost(void **st)
{
    (void)st;

    open_x2(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    /* overtaken on the receive side: the tick never saw the faulted sample */
    roz_ros2fx_ask("error waist 2");
    roz_ros2fx_ask_judged(1u << WAIST, "send waist");
    roz_ros2fx_ask("error waist 0");
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EROBOT);
    roz_port_test_assert_fault("waist", "power-off", 2);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1); /* reported once; it is over */

    /* overtaken on the tick's side: taken by a read that was not a frame */
    roz_ros2fx_ask("joint_error arm 4 9");
    roz_ros2fx_ask_judged(1u << ARM, "send arm");
    assert_int_equal(roz_port_test_read(), 0);
    roz_ros2fx_ask("joint_error arm 4 0");
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EROBOT);
    roz_port_test_assert_fault("left_wrist_yaw_joint", NULL, 9);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
}

/* The arm group reports DomainErrorState 4, communication lost (@p on), or
 * none. */
static void arm_error_state(int on)
{
    roz_ros2fx_ask("error arm %d", on ? 4 : 0);
}

static void test_x2_error_state_in_the_runtime(void **st)
{
    roz_test_clock_t clk = { 1, 1000 };
    (void)st;

    open_x2(NULL, 0);
    start_runtime(1000, &clk);
    roz_port_test_robot_fault(&rt, roz_ros2fx_send, arm_error_state, "arm",
                              "communication lost");
    roz_runtime_deinit(&rt);
}

/* ---- JointState layouts ------------------------------------------------------------------ */

static void test_x2_docs_layout(void **st)
{
    static const char *const docs[] = { "--joint-state-layout", "docs", NULL };
    (void)st;
    roz_ros2fx_set_fake_args(docs);
    open_x2((roz_param_t[]){ { "joint_state_layout", "docs" } }, 1);
    for (int k = 0; k < 3; k++) {
        roz_ros2fx_send();
        assert_int_equal(roz_port_test_read(), 1);
        assert_state_is_sent();
    }
    assert_int_equal(roz_ros2fx_counters().topic[ARM].malformed, 0);
}

/* The wrong layout, either way (DDS matches the topics by name alone). The
 * layouts differ after each joint's effort only, and CDR aligns the next
 * joint's name to 4 bytes either way: the SDK's layout against a robot that
 * sends the documentation's reads the positions, velocities and efforts
 * right and the coil and motor temperatures as an error code, and stops the
 * robot naming its first joint; the documentation's against a robot that
 * sends the SDK's reads past the last joint's data, which Cyclone refuses:
 * no sample reaches the port, no state ever arrives. */
static void test_x2_wrong_layout(void **st)
{
    static const char *const docs[] = { "--joint-state-layout", "docs", NULL };
    (void)st;
    roz_ros2fx_set_fake_args(docs);
    open_x2(NULL, 0);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EROBOT);
    assert_state_is_sent();
    roz_port_test_assert_fault("left_hip_pitch_joint", "error_code", 41u + 256u * 38u); /* the fake's coil and motor temperatures */
    roz_fixture_agibot_x2.close();

    open_x2((roz_param_t[]){ { "joint_state_layout", "docs" } }, 1);
    roz_ros2fx_set_state(2);
    for (int i = 0; i < 20; i++) {
        roz_ros2fx_ask("send");
        roz_fake_sleep_ms(10);
        assert_int_equal(roz_port_test_read(), ROZ_ENOENT);
    }
    /* the IMU's type is the same: it arrives (waited for: the last of the
     * 20 may still be on its way on a loaded machine), the joints' never */
    ROZ_PORT_TEST_WAIT_UNTIL(roz_ros2fx_counters().topic[IMU].samples >= 1);
    roz_ros2_counters_t c = roz_ros2fx_counters();
    for (int g = LEG; g <= HEAD; g++)
        assert_int_equal(c.topic[g].samples, 0);
}

/* ---- shapes ------------------------------------------------------------------------------- */

static void test_x2_names_and_lengths(void **st)
{
    (void)st;
    open_x2(NULL, 0);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);

    /* the arm's slot 3 names another joint: the robot's order is not ours */
    uint64_t before = roz_ros2fx_counters().topic[ARM].malformed;
    roz_ros2fx_ask("name arm 3 right_elbow_joint");
    roz_ros2fx_set_state(70);
    roz_ros2fx_ask("send");
    roz_ros2fx_wait_malformed(ARM, before);
    assert_int_equal(roz_port_test_read(), 0);
    /* unnamed joints are taken by their slot */
    roz_ros2fx_ask("name arm 3 -");
    roz_ros2fx_ask("name waist 0 none"); /* an empty name on the wire */
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);

    /* a group of the wrong length */
    before = roz_ros2fx_counters().topic[LEG].malformed;
    roz_ros2fx_ask("length leg 11");
    roz_ros2fx_ask("send leg");
    roz_ros2fx_wait_malformed(LEG, before);
    before = roz_ros2fx_counters().topic[HEAD].malformed;
    roz_ros2fx_ask("length head 1");
    roz_ros2fx_ask("send head");
    roz_ros2fx_wait_malformed(HEAD, before);
    /* longer than the room the sample was given at open (14 joints): Cyclone
     * grows the sequence, which owns its buffer (roz_dds_seq_reserve()), the
     * port sees 32 joints and drops the sample */
    before = roz_ros2fx_counters().topic[ARM].malformed;
    roz_ros2fx_ask("length arm 32");
    roz_ros2fx_ask("send arm");
    roz_ros2fx_wait_malformed(ARM, before);
    roz_ros2fx_ask("length arm 14");
    roz_ros2fx_ask("length leg 12");
    roz_ros2fx_ask("length head 2");
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    assert_state_is_sent();
}

/* ---- link checks by stamp ----------------------------------------------------------------- */

static void test_x2_link_by_stamp(void **st)
{
    roz_link_t l;
    (void)st;
    open_x2((roz_param_t[]){ { "link_check", "stamp" } }, 1);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_ask("stamp 1800000000 0");
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_ros2_link(roz_ros2fx_bridge(), &l);
    uint64_t replays = l.replays;
    /* a new sequence number, an old stamp: a replay by the stamp */
    roz_ros2fx_ask("stamp 1799999999 900000000");
    roz_ros2fx_ask_judged(1u << LEG, "send leg");
    roz_ros2_link(roz_ros2fx_bridge(), &l);
    assert_int_equal(l.replays, replays + 1);
    assert_int_equal(l.missing, 0); /* stamps tell no frame missing */
}

/* ---- a manifest of part of the robot ------------------------------------------------------- */

/* The left leg's six joints alone: the leg topic read (no IMU, no other
 * group), the leg commanded, the other groups never. */
static const roz_channel_t leg_commands[] = {
    { .name = "left_knee_joint/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = 0.0,
      .max = 2.4, .default_value = 0.0, .max_rate = 0.0, .position_state = 0 },
    { .name = "left_knee_joint/stiffness", .type = ROZ_IF_STIFFNESS, .unit = "", .min = 0.0,
      .max = 100.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_channel_t leg_states[] = {
    { .name = "left_knee_joint/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = 0.0,
      .max = 2.4, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const char *const leg_joints[] = { "left_knee_joint" };
static const roz_hardware_t leg_hw = { "agibot/X2", leg_joints, 1, NULL, 0 };
static const roz_manifest_t leg_only = { "leg_only", "humanoid", 500, leg_commands, 2,
                                         leg_states, 1, &leg_hw, NULL, 0, 0, NULL, NULL };

static void test_x2_part_of_the_robot(void **st)
{
    roz_fake_ros2_cmd_t c;
    uint64_t counts[FAKE_ROS2_MAX_GROUPS];
    double s1[1], c1[2] = { 1.25, 60.0 };
    (void)st;

    open_x2_on(&leg_only, NULL, 0);
    roz_ros2fx_ask("joint leg 3 0.75 0 0");
    roz_ros2fx_ask("joint leg 9 0.5 0 0");
    int rc = ROZ_ENOENT;
    for (int ms = 0; ms < 10000 && rc != 1; ms += 10) {
        if (ms % 500 == 0)
            roz_ros2fx_ask("send leg");
        roz_fake_sleep_ms(10);
        rc = roz_port_read(&port, s1, 1);
    }
    assert_int_equal(rc, 1); /* the leg alone makes the frame */
    assert_true(s1[0] == 0.75);
    assert_int_equal(roz_port_write(&port, c1, 2), ROZ_OK); /* the hold */
    roz_ros2fx_settle(); /* the writes after it are holds until it went out */
    assert_int_equal(roz_port_write(&port, c1, 2), ROZ_OK);
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), LEG, &c), 1);
    assert_int_equal(c.n, 12);
    assert_true(c.q[3] == 1.25 && c.kp[3] == 60.0);
    assert_true(c.q[9] == 0.5 && c.kp[9] == 0.0 && c.kd[9] == 0.0); /* not ours: passive */
    assert_int_equal(roz_fake_ros2_commands(roz_ros2fx_fake(), counts), 0);
    assert_int_equal(counts[WAIST], 0);
    assert_int_equal(counts[ARM], 0);
    assert_int_equal(counts[HEAD], 0);
}

/* ---- non-finite robot state never on the wire --------------------------------------------- */

/* Every value of every group's last command is finite; the manifest's
 * channels inside their limits (checked by the caller). */
static void assert_all_finite(const roz_fake_ros2_cmd_t *c, const char *when)
{
    for (unsigned s = 0; s < c->n; s++) {
        if (!isfinite(c->q[s]) || !isfinite(c->dq[s]) || !isfinite(c->tau[s]) ||
            !isfinite(c->kp[s]) || !isfinite(c->kd[s]))
            fail_msg("%s: slot %u (%s): q %g dq %g tau %g kp %g kd %g: not finite", when, s,
                     c->name[s], c->q[s], c->dq[s], c->tau[s], c->kp[s], c->kd[s]);
    }
}

/* The left knee driven by stiffness alone (no position command: the port
 * sends its measured position), the left hip pitch by position; the robot
 * reports NaN and Inf positions for the knee, an unlisted leg slot and the
 * built-in manifest's missing head_pitch_joint. */
static const roz_channel_t stiff_commands[] = {
    { .name = "left_knee_joint/stiffness", .type = ROZ_IF_STIFFNESS, .unit = "", .min = 10.0,
      .max = 100.0, .default_value = 10.0, .max_rate = 0.0,
      .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "left_hip_pitch_joint/position", .type = ROZ_IF_POSITION, .unit = "rad",
      .min = -1.0, .max = 1.0, .default_value = 0.0, .max_rate = 0.0,
      .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "left_hip_pitch_joint/damping", .type = ROZ_IF_DAMPING, .unit = "", .min = 1.0,
      .max = 5.0, .default_value = 2.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_channel_t stiff_states[] = {
    { .name = "left_knee_joint/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = 0.0,
      .max = 2.4, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "left_hip_pitch_joint/position", .type = ROZ_IF_POSITION, .unit = "rad",
      .min = -1.0, .max = 1.0, .default_value = 0.0, .max_rate = 0.0,
      .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const char *const stiff_joints[] = { "left_knee_joint", "left_hip_pitch_joint" };
static const roz_hardware_t stiff_hw = { "agibot/X2", stiff_joints, 2, NULL, 0 };
static const roz_manifest_t stiff_only = { "stiff_only", "humanoid", 500, stiff_commands, 3,
                                           stiff_states, 2, &stiff_hw, NULL, 0, 0, NULL, NULL };

static void read_leg(double *s2)
{
    int rc = ROZ_ENOENT;
    for (int ms = 0; ms < 10000 && rc != 1; ms += 10) {
        if (ms % 500 == 0)
            roz_ros2fx_ask("send leg");
        roz_fake_sleep_ms(10);
        rc = roz_port_read(&port, s2, 2);
    }
    assert_int_equal(rc, 1);
}

static void test_x2_nonfinite_state_never_on_the_wire(void **st)
{
    roz_fake_ros2_cmd_t c;
    double s2[2], c3[3] = { 80.0, 0.5, 3.0 };
    (void)st;

    open_x2_watched(&stiff_only);
    /* never a finite position: the knee gets no stiffness it could use
     * against a made-up target, the unlisted slot nothing */
    roz_ros2fx_ask("joint leg 3 nan 0 0");
    roz_ros2fx_ask("joint leg 9 inf 0 0");
    read_leg(s2);
    assert_int_equal(roz_port_write(&port, c3, 3), ROZ_OK); /* the hold */
    roz_ros2fx_settle();
    assert_int_equal(roz_port_write(&port, c3, 3), ROZ_OK);
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), LEG, &c), 1);
    assert_all_finite(&c, "never measured");
    assert_true(c.q[3] == 0.0 && c.kp[3] == 10.0); /* the stiffness channel's minimum */
    assert_true(c.q[0] == 0.5 && c.kd[0] == 3.0);
    assert_true(c.kp[9] == 0.0);

    /* a finite position, then NaN and -Inf: the last finite one (inside
     * the state's limits) stays the target the stiffness acts on */
    roz_ros2fx_ask("joint leg 3 0.75 0 0");
    read_leg(s2);
    assert_int_equal(roz_port_write(&port, c3, 3), ROZ_OK);
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), LEG, &c), 1);
    assert_true(c.q[3] == 0.75 && c.kp[3] == 80.0);
    roz_ros2fx_ask("joint leg 3 nan 0 0");
    read_leg(s2);
    assert_true(isnan(s2[0])); /* the runtime sees what the robot said */
    assert_int_equal(roz_port_write(&port, c3, 3), ROZ_OK);
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), LEG, &c), 1);
    assert_all_finite(&c, "NaN measured");
    assert_true(c.q[3] == 0.75 && c.kp[3] == 80.0);
    roz_ros2fx_ask("joint leg 3 -inf 0 0");
    read_leg(s2);
    assert_int_equal(roz_port_write(&port, c3, 3), ROZ_OK);
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), LEG, &c), 1);
    assert_all_finite(&c, "-Inf measured");
    roz_ros2fx_ask("joint leg 3 7.5 0 0"); /* beyond the state's limit of 2.4 */
    read_leg(s2);
    assert_int_equal(roz_port_write(&port, c3, 3), ROZ_OK);
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), LEG, &c), 1);
    assert_true(c.q[3] == 2.4);

    /* the tick stops: the damping command, finite, its stiffness the
     * channel's minimum (not 0, outside the manifest), its damping inside */
    roz_ros2fx_ask("joint leg 3 nan 0 0");
    read_leg(s2);
    roz_port_test_watchdog_trip(&roz_ros2fx_bridge()->cmd, 100000u, roz_ros2fx_commands);
    uint64_t n0[FAKE_ROS2_MAX_GROUPS];
    roz_fake_ros2_t *fk = roz_ros2fx_fake();
    assert_int_equal(roz_fake_ros2_commands(fk, n0), 0);
    assert_int_equal(roz_fake_ros2_ask(fk, "wait_commands leg %llu 60000",
                                       (unsigned long long)n0[LEG] + 2u),
                     0);
    assert_int_equal(roz_fake_ros2_command(fk, LEG, &c), 1);
    assert_all_finite(&c, "damping");
    assert_true(c.kp[3] == 10.0 && c.kp[0] == 0.0 && c.kp[9] == 0.0);
    assert_true(c.kd[0] >= 1.0 && c.kd[0] <= 5.0);
}

/* The start-up hold reaches every group before the controller's command,
 * however soon the tick writes again (the writer held back across it). */
static void test_x2_hold_reaches_the_wire_first(void **st)
{
    roz_fake_ros2_cmd_t c;
    (void)st;
    open_x2(NULL, 0);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_write_held_back(&roz_ros2fx_bridge()->cmd);
    roz_ros2fx_settle();
    roz_fake_ros2_t *fk = roz_ros2fx_fake();
    for (unsigned g = 0; g < fk->n_groups; g++) {
        assert_int_equal(roz_fake_ros2_command(fk, g, &c), 1);
        for (unsigned s = 0; s < c.n; s++) {
            if (c.kp[s] != 0.0)
                fail_msg("%s: the robot's first command is not the hold (kp %g)", c.name[s],
                         c.kp[s]);
        }
    }
    roz_port_test_write();
    roz_ros2fx_settle();
    int g, s;
    assert_int_equal(roz_ros2fx_place(0, &g, &s), 0);
    assert_int_equal(roz_fake_ros2_command(fk, (unsigned)g, &c), 1);
    assert_true(c.kp[s] == cmd[cmd_of(m->hardware->joints[0], "stiffness")]);
}

/* The built-in manifest leaves head_pitch_joint out: whatever the robot
 * reports there never goes back out. */
static void test_x2_head_pitch_nan(void **st)
{
    roz_fake_ros2_cmd_t c;
    (void)st;
    open_x2(NULL, 0);
    roz_ros2fx_ask("joint head 1 nan nan nan");
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_distinct_command(m, 1, cmd);
    roz_port_test_write();
    roz_ros2fx_settle();
    assert_int_equal(roz_fake_ros2_command(roz_ros2fx_fake(), HEAD, &c), 1);
    assert_string_equal(c.name[1], "head_pitch_joint");
    assert_all_finite(&c, "head");
    assert_true(c.kp[1] == 0.0 && c.kd[1] == 0.0);
}

/* ---- refusals ------------------------------------------------------------------------------- */

static void expect_refused(const roz_manifest_t *man, const char *key, const char *value,
                           const char *want1, const char *want2)
{
    static roz_agibot_x2_t x2;
    roz_port_t pt = roz_agibot_x2_port(&x2, NULL, NULL);
    roz_port_test_expect_refused(&pt, man, key, value, want1, want2);
}

static const char *const alien_joints[] = { "tail_joint" };
static const roz_channel_t alien_commands[] = {
    { .name = "tail_joint/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_hardware_t alien_hw = { "agibot/X2", alien_joints, 1, NULL, 0 };
static const roz_manifest_t alien = { "alien", "humanoid", 500, alien_commands, 1, NULL, 0,
                                      &alien_hw, NULL, 0, 0, NULL, NULL };

static void test_x2_bad_parameters(void **st)
{
    (void)st;
    static const struct { const char *key, *value; } bad[] = {
        { "joint_state_layout", "v2" },     { "link_check", "crc" },
        { "dds_domain", "999" },            { "command_writer_period_us", "10" },
        { "state_decimation", "0" },        { "peer_timeout_ms", "5" },
        { "startup_damping", "11" },        { "network_interface", "eth0;rm" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        expect_refused(m, bad[i].key, bad[i].value, bad[i].key, bad[i].value);
    expect_refused(m, "no_such_key", "1", "no_such_key", "agibot/X2");
    expect_refused(m, "parallel_parser_type", "rl", "parallel_parser_type", "agibot/X2");
    expect_refused(&alien, NULL, NULL, "tail_joint", "agibot/X2");
}

/* The command watchdog (roz::ros2, tested whole on the PM01), on a clock
 * the test moves: once the tick stops, every group's topic gets the
 * watchdog's hold (the hold gains, the torque kept) in the X2's messages,
 * repeatedly, by the writer alone; read() reports it once; the next write
 * is the hold. */
static void test_x2_watchdog_every_group(void **st)
{
    roz_fake_ros2_cmd_t c;
    uint64_t n0[FAKE_ROS2_MAX_GROUPS];
    double q[ROZ_CFG_MAX_JOINTS];
    (void)st;
    open_x2_watched(m);
    roz_port_test_start(roz_ros2fx_send, roz_ros2fx_settle);
    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_ros2fx_sent(sent);
    roz_port_test_distinct_command(m, 1, cmd);
    /* each setpoint moved to keep the torque it went out with at the hold
     * gain, within the band of the measured position, inside the limits
     * (test_pm01_watchdog_keeps_the_torque) */
    for (uint16_t j = 0; j < m->hardware->n_joints; j++) {
        int i = cmd_of(m->hardware->joints[j], "position");
        int kp = cmd_of(m->hardware->joints[j], "stiffness");
        q[j] = NAN;
        if (i < 0 || kp < 0)
            continue;
        const roz_channel_t *qc = &m->commands[i];
        roz_hold_from_t from = { cmd[i], cmd[kp], sent[qc->position_state] };
        double v = roz_hold_setpoint(&from, m->commands[kp].default_value, roz_hold_band(qc));
        q[j] = roz_channel_clamp(qc, roz_channel_clamp(&m->states[qc->position_state], v));
    }
    roz_port_test_write();
    roz_ros2fx_settle();
    assert_int_equal(roz_ros2fx_counters().command_timeouts, 0);

    roz_port_test_watchdog_trip(&roz_ros2fx_bridge()->cmd, 100000u, roz_ros2fx_commands);
    roz_fake_ros2_t *fk = roz_ros2fx_fake();
    assert_int_equal(roz_fake_ros2_commands(fk, n0), 0);
    for (unsigned g = 0; g < fk->n_groups; g++) {
        if (n0[g] == 0)
            continue; /* a group the manifest does not drive */
        assert_int_equal(roz_fake_ros2_ask(fk, "wait_commands %s %llu 60000", fk->group[g],
                                           (unsigned long long)n0[g] + 3u),
                         0);
    }
    unsigned checked = 0;
    for (uint16_t j = 0; j < m->hardware->n_joints; j++) {
        int g, s, kd = cmd_of(m->hardware->joints[j], "damping");
        int kp = cmd_of(m->hardware->joints[j], "stiffness"); /* the hold gain */
        if (isnan(q[j]) || kd < 0 || kp < 0 || roz_ros2fx_place(j, &g, &s) != 0)
            continue;
        assert_int_equal(roz_fake_ros2_command(fk, (unsigned)g, &c), 1);
        if (c.q[s] != q[j] || c.kp[s] != m->commands[kp].default_value || c.dq[s] != 0.0 ||
            c.tau[s] != 0.0 || c.kd[s] != m->commands[kd].default_value)
            fail_msg("%s after the tick stopped: q %g kp %g kd %g dq %g tau %g: not the "
                     "watchdog's hold",
                     m->hardware->joints[j], c.q[s], c.kp[s], c.kd[s], c.dq[s], c.tau[s]);
        checked++;
    }
    assert_true(checked >= 4);
    assert_int_equal(roz_ros2fx_counters().command_timeouts, 1);

    roz_ros2fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EWATCHDOG);
    double before_trip[ROZ_CFG_MAX_COMMANDS];
    memcpy(before_trip, cmd, sizeof before_trip);
    roz_port_test_distinct_command(m, 2, cmd);
    roz_port_test_write();
    roz_ros2fx_settle();
    roz_ros2fx_sent(sent);
    int g, s;
    assert_int_equal(roz_ros2fx_place(0, &g, &s), 0);
    assert_int_equal(roz_fake_ros2_command(fk, (unsigned)g, &c), 1);
    char name[160];
    snprintf(name, sizeof name, "%s/position", m->hardware->joints[0]);
    /* the stop's hold from the last command before the trip, at the hold
     * gain and the damping the robot is in already: never a frame without
     * stiffness between the watchdog's hold and the tick's */
    {
        int qi = cmd_of(m->hardware->joints[0], "position");
        int ki = cmd_of(m->hardware->joints[0], "stiffness");
        const roz_channel_t *qc = &m->commands[qi];
        roz_hold_from_t from = { before_trip[qi], before_trip[ki], sent[state_index(name)] };
        double want = roz_channel_clamp(qc, roz_hold_setpoint(&from, m->commands[ki].default_value,
                                                              roz_hold_band(qc)));
        assert_true(fabs(c.q[s] - want) < 1e-12);
        assert_true(c.kp[s] == m->commands[ki].default_value);
    }
    assert_true(c.kd[s] == m->commands[cmd_of(m->hardware->joints[0], "damping")].default_value);
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_x2_joints_map_both_ways, teardown),
              cmocka_unit_test_teardown(test_x2_imu_order, teardown),
              cmocka_unit_test_teardown(test_x2_ros2_names, teardown),
              cmocka_unit_test_teardown(test_x2_fresh_needs_every_group, teardown),
              cmocka_unit_test_teardown(test_x2_silent_group_is_stale, teardown),
              cmocka_unit_test_teardown(test_x2_error_states_latch, teardown),
              cmocka_unit_test_teardown(test_x2_brief_error_state_is_not_lost, teardown),
              cmocka_unit_test_teardown(test_x2_error_state_in_the_runtime, teardown),
              cmocka_unit_test_teardown(test_x2_docs_layout, teardown),
              cmocka_unit_test_teardown(test_x2_wrong_layout, teardown),
              cmocka_unit_test_teardown(test_x2_names_and_lengths, teardown),
              cmocka_unit_test_teardown(test_x2_link_by_stamp, teardown),
              cmocka_unit_test_teardown(test_x2_part_of_the_robot, teardown),
              cmocka_unit_test_teardown(test_x2_nonfinite_state_never_on_the_wire, teardown),
              cmocka_unit_test_teardown(test_x2_head_pitch_nan, teardown),
              cmocka_unit_test_teardown(test_x2_hold_reaches_the_wire_first, teardown),
              cmocka_unit_test_teardown(test_x2_watchdog_every_group, teardown),
              cmocka_unit_test(test_x2_bad_parameters))
