/* SPDX-License-Identifier: Apache-2.0 */
/* The G1 port (roz/port/unitree_g1.h) against the fake robot (fake_g1, its own
 * IDL and CRC, a separate process) over loopback DDS, beyond the conformance
 * suite:
 *  - all 29 joints map both ways, a distinct value per joint and field: the
 *    states the port reads, the LowCmd_ the robot gets (mode 1 for the
 *    joints, slots 29-34 mode 0 and all zero, mode_pr PR);
 *  - joints bound by name: a manifest listing the 29 joints in reverse
 *    order drives each joint's motor slot (a distinct value per joint); the
 *    23-DoF manifest drives its 23 slots and leaves 13, 14, 20, 21, 27, 28
 *    mode 0 and zero; an unknown or repeated name is refused at open;
 *  - a robot whose mode_machine says it lacks a listed joint (23-DoF 4/10,
 *    locked waist 6/12/14/16) gets no command, and the runtime latches
 *    ROZ_FAULT_ROBOT naming the joint and the mode_machine; 0 takes all;
 *  - the IMU: Unitree's w, x, y, z quaternion reaches the manifest's x, y,
 *    z, w; gyroscope and accelerometer in order;
 *  - padding zero under the CRC: the port's sample storage starts as
 *    garbage and the robot (which recomputes the CRC over a freshly zeroed
 *    struct) counts no bad CRC; the published CRC equals a bit-by-bit
 *    reference computed here from a raw subscription;
 *  - mode_machine is echoed, and a change under a running controller stops
 *    the commands and makes read() report it, until it changes back;
 *  - a motor fault code latches ROZ_FAULT_ROBOT in the runtime naming the
 *    joint and the code;
 *  - the wireless remote, laid out as Unitree's SDK does, reaches the
 *    runtime's operator inputs scaled (a NaN stick refused and counted, a
 *    frame with a bad CRC bringing none);
 *  - decimation 4 converts every 4th frame whole, checks every frame (bad
 *    CRC, fault codes) and converts the positions of every frame;
 *  - the periodic writer keeps publishing the last command, and a restarted
 *    robot gets nothing until the tick writes; the start-up hold with
 *    startup_damping; the damping command on shutdown;
 *  - the command watchdog, on a clock the test moves (so that nothing
 *    depends on the machine's pace: a loaded host, QEMU), exactly the
 *    timeout of silence no trip, 1 ns more a trip; and on real time while
 *    the tick is silent, judged on the writer's own counts: the tick stops
 *    writing; the robot gets the
 *    last command for at most the timeout's worth of writer periods, then
 *    the watchdog's hold (kp the stiffness default, the hold gain; kd the
 *    damping default; the last commanded positions), on the writer's own (periodic, and event-driven where
 *    nothing wakes it); read() reports the trip once and the runtime
 *    latches COMMAND_TIMEOUT naming the silence and the timeout; the first
 *    command after it is the start-up hold, a clear lets the stand's gains
 *    through again;
 *  - the command writer thread carries the affinity, stack size and
 *    scheduling its parameters ask for;
 *  - bad parameters and manifests are refused naming the key and value, or
 *    the joint or channel. */
#define _POSIX_C_SOURCE 200809L
/* white-box: test_g1_padding_and_crc fills the port's sample storage with
 * garbage before its writer runs, test_g1_writer_thread reads its writer
 * (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>
#include <dds/dds.h>

#include "crc32_reference.h"
#include "port_fixture.h"
#include "port_test.h"
#include "proc_threads.h"
#include "roz/runtime.h"
#include "roz/filter.h"
#include "roz/hold.h"
#include "roz/port/unitree_g1.h"
#include "support.h"
#include "support_runtime.h"
#include "support_wat.h"
#include "unitree_g1_fixture.h"
#include "unitree_g1_23dof_manifest.h"
#include "unitree_g1_manifest.h"
#include "unitree_hg.h"
#include "ur5_manifest.h"

/* the manifest the test opens the port with (teardown restores the G1's) */
static const roz_manifest_t *m = &roz_manifest_unitree_g1;
static roz_port_t port;
static double state[ROZ_CFG_MAX_STATES], sent[ROZ_CFG_MAX_STATES];
static double cmd[ROZ_CFG_MAX_COMMANDS];


static void open_g1(const roz_param_t *items, size_t n)
{
    roz_port_test_drive(&roz_fixture_unitree_g1, m, items, n, &port, state, cmd);
}

/* The tick alive: the robot's next frame read, command @p k written. */
static void tick_alive(int k)
{
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_distinct_command(m, k, cmd);
    roz_port_test_write();
}

static int teardown(void **st)
{
    (void)st;
    roz_fixture_unitree_g1.close();
    m = &roz_manifest_unitree_g1;
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

static roz_unitree_g1_counters_t counters(void)
{
    roz_unitree_g1_counters_t c;
    roz_unitree_g1_counters(roz_g1fx_port(), &c);
    return c;
}

/* The counters read while no pass of the writer was open, tried again
 * until they were (a periodic writer's passes go on): a pass counts the
 * watchdog's hold (safe_published) in its fill, before it publishes it, so
 * counters read during one can show a hold that is not yet among
 * published, and a pass begun between two of the loads can move one and
 * not the other. Read so, published holds exactly the safe_published
 * holds. */
static roz_unitree_g1_counters_t settled_counters(void)
{
    roz_unitree_g1_counters_t c;
    const roz_dds_writer_t *w = &roz_g1fx_port()->writer;
    ROZ_PORT_TEST_WAIT_UNTIL((c = counters(), c.writer_done == c.writer_passes &&
                                                  atomic_load(&w->passes) == c.writer_passes));
    return c;
}

/* Readers matched with the port's rt/lowcmd writer now. */
static uint32_t cmd_readers(void)
{
    uint32_t readers, writers;
    roz_unitree_g1_matched(roz_g1fx_port(), &readers, &writers);
    return readers;
}

static void get_command(roz_fake_g1_cmd_t *c)
{
    roz_g1fx_settle();
    assert_int_equal(roz_fake_g1_command(roz_g1fx_fake(), c), 1);
}

/* ---- mapping ------------------------------------------------------------------ */

/* The command the fake got, joint by joint at the slot of its name: mode 1
 * and the five fields of cmd; every other slot mode 0 and zero. */
static void assert_command_by_name(const roz_fake_g1_cmd_t *c)
{
    int driven[ROZ_UNITREE_G1_SLOTS] = { 0 };
    for (uint16_t j = 0; j < m->hardware->n_joints; j++) {
        int s = roz_g1fx_slot(m->hardware->joints[j]);
        driven[s] = 1;
        assert_int_equal(c->mode[s], 1);
        assert_true(c->q[s] == (float)cmd[cmd_index(j, "position")]);
        assert_true(c->dq[s] == (float)cmd[cmd_index(j, "velocity")]);
        assert_true(c->tau[s] == (float)cmd[cmd_index(j, "effort")]);
        assert_true(c->kp[s] == (float)cmd[cmd_index(j, "stiffness")]);
        assert_true(c->kd[s] == (float)cmd[cmd_index(j, "damping")]);
    }
    for (int s = 0; s < ROZ_UNITREE_G1_SLOTS; s++) {
        if (driven[s])
            continue;
        assert_int_equal(c->mode[s], 0);
        assert_true(c->q[s] == 0.0 && c->dq[s] == 0.0 && c->tau[s] == 0.0 && c->kp[s] == 0.0 &&
                    c->kd[s] == 0.0);
    }
}

/* Both ways through @p man, three frames and commands, the fake reporting
 * @p mode_machine (< 0: its default, 5). */
static void map_both_ways(const roz_manifest_t *man, int mode_machine)
{
    roz_fake_g1_cmd_t c;

    m = man;
    open_g1(NULL, 0);
    if (mode_machine >= 0)
        roz_g1fx_ask("mode_machine %d", mode_machine);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    for (int k = 1; k <= 3; k++) {
        roz_g1fx_send();
        assert_int_equal(roz_port_test_read(), 1);
        roz_g1fx_sent(sent);
        roz_port_test_assert_state(m, state, sent);
        roz_port_test_distinct_command(m, k, cmd);
        roz_port_test_write();
        get_command(&c);
        assert_int_equal(c.mode_pr, 0); /* PR */
        /* echoed: the one asked for, or the fake's own */
        assert_int_equal(c.mode_machine, mode_machine >= 0 ? mode_machine : 5);
        assert_command_by_name(&c);
    }
}

/* all 29 joints, each at its motor's slot (mode 1, the five fields as
 * written); slots 29-34 mode 0 and zero */
static void test_g1_joints_map_both_ways(void **st)
{
    (void)st;
    map_both_ways(&roz_manifest_unitree_g1, -1);
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) /* the manifest lists them by motor */
        assert_int_equal(roz_g1fx_slot(m->hardware->joints[j]), j);
}

/* The G1's manifest with its joints listed in reverse: the same channels,
 * so joint i's channels belong to motor 28 - i's name. */
static const char *reversed_joints[ROZ_UNITREE_G1_BODY];
static roz_hardware_t reversed_hw;
static roz_manifest_t reversed;

static const roz_manifest_t *reversed_g1(void)
{
    const roz_manifest_t *g1 = &roz_manifest_unitree_g1;
    assert_int_equal(g1->hardware->n_joints, ROZ_UNITREE_G1_BODY);
    for (int j = 0; j < ROZ_UNITREE_G1_BODY; j++)
        reversed_joints[j] = g1->hardware->joints[ROZ_UNITREE_G1_BODY - 1 - j];
    reversed_hw = *g1->hardware;
    reversed_hw.joints = reversed_joints;
    reversed = *g1;
    reversed.hardware = &reversed_hw;
    return &reversed;
}

static void test_g1_joints_by_name_reordered(void **st)
{
    (void)st;
    map_both_ways(reversed_g1(), -1);
    /* the first listed joint is the right wrist's yaw: motor 28 */
    assert_int_equal(roz_g1fx_slot(m->hardware->joints[0]), 28);
}

static void test_g1_23dof(void **st)
{
    static const int absent[6] = { 13, 14, 20, 21, 27, 28 };
    roz_fake_g1_cmd_t c;
    (void)st;

    assert_int_equal(roz_manifest_unitree_g1_23dof.hardware->n_joints, 23);
    /* a 23-DoF robot (10) gets commands for its 23 motors */
    map_both_ways(&roz_manifest_unitree_g1_23dof, 10);
    get_command(&c);
    for (int i = 0; i < 6; i++) {
        assert_int_equal(c.mode[absent[i]], 0);
        assert_true(c.q[absent[i]] == 0.0 && c.dq[absent[i]] == 0.0 &&
                    c.tau[absent[i]] == 0.0 && c.kp[absent[i]] == 0.0 &&
                    c.kd[absent[i]] == 0.0);
    }
    teardown(NULL);
    /* so do 4 (23-DoF rev 1.0), a locked waist, simulation */
    static const int others[] = { 4, 6, 0 };
    for (size_t i = 0; i < sizeof others / sizeof others[0]; i++) {
        map_both_ways(&roz_manifest_unitree_g1_23dof, others[i]);
        teardown(NULL);
    }
}

static void test_g1_imu_order(void **st)
{
    (void)st;
    open_g1(NULL, 0);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    roz_g1fx_ask("imu 0.5 0.25 -0.125 0.0625 1.5 -2.5 3.5 0.75 -1.25 9.75");
    roz_link_t before;
    roz_unitree_g1_link(roz_g1fx_port(), &before);
    roz_g1fx_ask("send");
    roz_g1fx_wait_judged(&before, 0);
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_assert_imu(m, state);
}

/* ---- the wire: padding and CRC ------------------------------------------------- */

static ROZ_ATOMIC(uint32_t) crc_checked, crc_bad;

static void on_raw_lowcmd(dds_entity_t rd, void *arg)
{
    unitree_hg_msg_dds__LowCmd_ s;
    void *ptr[1] = { &s };
    dds_sample_info_t info[1];
    (void)arg;
    for (;;) {
        memset(&s, 0, sizeof s); /* the robot's way: a zeroed struct, filled */
        if (dds_take(rd, ptr, info, 1, 1) != 1)
            return;
        if (!info[0].valid_data)
            continue;
        uint32_t words[sizeof s / 4];
        memcpy(words, &s, sizeof s);
        if (roz_crc32_reference(words, sizeof s / 4 - 1) != s.crc)
            atomic_fetch_add(&crc_bad, 1u);
        atomic_fetch_add(&crc_checked, 1u);
    }
}

static void test_g1_padding_and_crc(void **st)
{
    uint64_t good = 0, bad = 0;
    (void)st;

    atomic_store(&crc_checked, 0u);
    atomic_store(&crc_bad, 0u);
    /* the port, with garbage in its sample storage before its writer runs
     * (event-driven: one sample per write) */
    open_g1(NULL, 0);
    roz_unitree_g1_t *g1 = roz_g1fx_port();
    (void)roz_port_deactivate(&port);
    memset(g1->tx_sample, 0xA5, sizeof g1->tx_sample);
    assert_int_equal(roz_port_activate(&port), ROZ_OK);
    /* a raw subscriber of our own beside the fake (in the port's domain):
     * the CRC bit by bit */
    dds_entity_t part = dds_create_participant(ROZ_TEST_DDS_DOMAIN, NULL, NULL);
    assert_true(part > 0);
    dds_entity_t topic = dds_create_topic(part, &unitree_hg_msg_dds__LowCmd__desc, "rt/lowcmd",
                                          NULL, NULL);
    dds_qos_t *q = dds_create_qos();
    dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
    dds_listener_t *l = dds_create_listener(NULL);
    dds_lset_data_available(l, on_raw_lowcmd);
    dds_entity_t rd = dds_create_reader(part, topic, q, l);
    dds_delete_qos(q);
    dds_delete_listener(l);
    assert_true(rd > 0);

    /* matched both ways before the port speaks: the fake and this reader
     * see the port's writer, and it sees them */
    dds_subscription_matched_status_t sm;
    ROZ_PORT_TEST_WAIT_UNTIL(cmd_readers() >= 2 && dds_get_subscription_matched_status(rd, &sm) == 0 &&
               sm.current_count >= 1);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    for (int k = 1; k <= 50; k++) {
        roz_g1fx_send();
        (void)roz_port_test_read();
        roz_port_test_distinct_command(m, k, cmd);
        roz_port_test_write();
        roz_g1fx_settle(); /* one sample per write: none coalesced */
    }
    assert_int_equal(roz_fake_g1_commands(roz_g1fx_fake(), &good, &bad), 0);
    assert_true(good >= 50);
    assert_int_equal(bad, 0); /* stale padding under the CRC would show here */
    ROZ_PORT_TEST_WAIT_UNTIL(atomic_load(&crc_checked) >= 50u);
    assert_int_equal(atomic_load(&crc_bad), 0);
    dds_delete(part);
}

/* ---- mode_machine ------------------------------------------------------------------ */

static void test_g1_mode_machine(void **st)
{
    roz_fake_g1_cmd_t c;
    (void)st;

    open_g1(NULL, 0);
    roz_g1fx_ask("mode_machine 9");
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    roz_port_test_distinct_command(m, 1, cmd);
    roz_port_test_write();
    get_command(&c);
    assert_int_equal(c.mode_machine, 9); /* echoed */

    /* changed under a running controller: reported, nothing sent */
    roz_g1fx_ask("mode_machine 11"); /* another 29-DoF variant */
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EROBOT);
    roz_port_test_assert_fault("mode_machine", NULL, 11);
    uint64_t published = counters().published;
    for (int k = 2; k < 6; k++) {
        roz_port_test_distinct_command(m, k, cmd);
        roz_port_test_write();
    }
    roz_g1fx_settle();
    assert_int_equal(counters().published, published);
    assert_true(counters().refused_mode_machine >= 1);
    get_command(&c);
    assert_int_equal(c.mode_machine, 9); /* the robot kept the last good one */

    /* back: reads and commands again */
    roz_g1fx_ask("mode_machine 9");
    tick_alive(7);
    get_command(&c);
    assert_true(c.q[0] == (float)cmd[cmd_index(0, "position")]);
    assert_true(counters().published > published);
}

/* ---- a motor fault in the runtime -------------------------------------------------- */

static roz_runtime_t rt;

/* The runtime over the port (without the fall rule:
 * roz_port_test_without_fall()), the G1's stand controller started, on a
 * test clock, without the jitter monitor. */
static void start_runtime(void)
{
    static roz_test_clock_t clk;
    roz_runtime_config_t cfg;
    clk = (roz_test_clock_t){ 1, 1000 };
    roz_test_runtime_config(&cfg, roz_port_test_without_fall(m), port, &clk);
    cfg.monitor_jitter = 0;
    roz_test_runtime_start(&rt, &cfg, "g1_stand");
}

static void tick_rt(void)
{
    roz_port_test_tick(&rt);
}

/* The left knee's motor reports fault code 33 (@p on), or none. */
static void knee_motor_fault(int on)
{
    roz_g1fx_ask("motorstate 3 %d", on ? 33 : 0); /* left_knee_joint */
}

static void test_g1_motor_fault_latches(void **st)
{
    (void)st;

    open_g1(NULL, 0);
    start_runtime();
    roz_port_test_robot_fault(&rt, roz_g1fx_send, knee_motor_fault, "left_knee_joint", "33");
    assert_true(counters().motor_fault_frames >= 1);
    roz_runtime_deinit(&rt);
}

/* ---- the wireless remote ------------------------------------------------------------ */

/* The G1 with operator inputs on its remote: unitree_rl_gym's walking
 * command (vx = 0.8 ly, vy = -0.5 lx, yaw rate = -1.57 rx), a button and a
 * trigger; each input moves at most 10 a tick, so a value lands at once. */
static const roz_channel_t remote_inputs[] = {
    { .name = "operator/velocity.x", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -0.8,
      .max = 0.8, .default_value = 0.0, .max_rate = 10.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/velocity.y", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -0.5,
      .max = 0.5, .default_value = 0.0, .max_rate = 10.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/yaw_rate", .type = ROZ_IF_VELOCITY, .unit = "rad/s", .min = -1.57,
      .max = 1.57, .default_value = 0.0, .max_rate = 10.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/walk", .type = ROZ_IF_POSITION, .unit = "", .min = 0.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 10.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/brake", .type = ROZ_IF_POSITION, .unit = "", .min = 0.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 10.0, .position_state = ROZ_CHANNEL_UNPAIRED },
    { .name = "operator/pitch", .type = ROZ_IF_POSITION, .unit = "", .min = -1.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 10.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_input_rule_t remote_rules[] = {
    { .stale_after_ms = 500, .source = ROZ_OPERATOR_REMOTE_LY, .scale = 0.8 },
    { .stale_after_ms = 500, .source = ROZ_OPERATOR_REMOTE_LX, .scale = -0.5 },
    { .stale_after_ms = 500, .source = ROZ_OPERATOR_REMOTE_RX, .scale = -1.57 },
    { .stale_after_ms = 500, .source = ROZ_OPERATOR_REMOTE_BTN_A, .scale = 1.0 },
    { .stale_after_ms = 500, .source = ROZ_OPERATOR_REMOTE_L2, .scale = 1.0 },
    { .stale_after_ms = 500, .source = ROZ_OPERATOR_REMOTE_RY, .scale = 1.0 },
};

/* The inputs as the runtime's last tick left them. */
static const double *inputs_now(void)
{
    return roz_runtime_last_state(&rt) + m->n_states;
}

/* A robot that sends a remote frame as Unitree's SDK fills it (the SDK's
 * struct and key union, each key set by the SDK's name, copied as one
 * memory image): every stick, the trigger and the keys land where the
 * port reads them (every key but A leaves A's input at 0); the port decodes it from
 * accepted frames only and hands it, wait-free, to the runtime's inputs,
 * which a controller reads scaled; a NaN stick is refused and counted (the
 * other fields of the frame still count), a frame that fails its CRC
 * brings no remote, and the port accepts a manifest with inputs. */
/* Between the port's open and its activate: the runtime, then the port's
 * operator sink into it (the order rozrun keeps). */
static void remote_runtime(const roz_port_t *p)
{
    static roz_test_clock_t clk = { 1, 1000 };
    roz_runtime_config_t cfg;
    roz_operator_sink_t sink = roz_runtime_operator_sink(&rt);
    roz_test_runtime_config(&cfg, m, *p, &clk);
    cfg.monitor_jitter = 0;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_port_set_operator(p, &sink), ROZ_OK);
}

static void test_g1_wireless_remote(void **st)
{
    static roz_manifest_t with_inputs;
    roz_operator_sink_t sink = roz_runtime_operator_sink(&rt);
    roz_link_t before;
    /* a controller of no robot in particular (the inputs change the
     * manifest's identity): it commands nothing, the filter holds */
    static uint8_t w[128];
    size_t len = roz_test_wat("(module (func (export \"process\") (param i64)))", w, sizeof w);
    const double *in;
    (void)st;

    with_inputs = roz_manifest_unitree_g1;
    with_inputs.inputs = remote_inputs;
    with_inputs.input_rules = remote_rules;
    with_inputs.n_inputs = sizeof remote_inputs / sizeof remote_inputs[0];
    m = &with_inputs;
    roz_g1fx_set_before_activate(remote_runtime);
    open_g1(NULL, 0);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    assert_int_equal(roz_port_set_operator(&port, &sink), ROZ_ESTATE); /* active: too late */

    /* A (bit 8) and L2 (bit 5) held; lx 0.4, rx -1, ry 0.25, L2 0.75, ly 0.5 */
    roz_g1fx_ask("remote A+L2 0.4 -1 0.25 0.75 0.5");
    roz_g1fx_send();
    tick_rt();
    in = inputs_now();
    assert_true(in[0] == 0.8 * (double)0.5f);
    assert_true(in[1] == -0.5 * (double)0.4f);
    assert_true(in[2] == 1.57);
    assert_true(in[3] == 1.0);
    assert_true(in[4] == (double)0.75f);
    assert_true(in[5] == (double)0.25f);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    assert_int_equal(counters().remote_frames, 1);

    /* every key but A, each set by the SDK's name: no neighbour read as A */
    roz_g1fx_ask("remote R1+L1+start+select+R2+F1+F2+B+X+Y+up+right+down+left "
                 "0.4 -1 0.25 0.75 0.5");
    roz_g1fx_send();
    tick_rt();
    in = inputs_now();
    assert_true(in[3] == 0.0);
    assert_int_equal(roz_runtime_faults(&rt), 0); /* B without L2: no e-stop */
    roz_g1fx_ask("remote A 0.4 -1 0.25 0.75 0.5");
    roz_g1fx_send();
    tick_rt();
    assert_true(inputs_now()[3] == 1.0);

    /* a NaN stick: that input keeps its value, counted by the inputs and by
     * the port; the frame's other fields are taken */
    roz_g1fx_ask("remote - nan -1 0.25 0.75 0.25");
    roz_g1fx_send();
    tick_rt();
    in = inputs_now();
    assert_true(in[1] == -0.5 * (double)0.4f);
    assert_true(in[0] == 0.8 * 0.25);
    assert_true(in[3] == 0.0); /* A released */
    assert_int_equal(roz_runtime_input_counters(&rt)->nonfinite, 1);
    assert_int_equal(counters().remote_nonfinite, 1);

    /* a frame that fails its CRC brings no remote */
    roz_g1fx_ask("remote A 0.1 0.1 0.1 0.1 -0.5");
    roz_unitree_g1_link(roz_g1fx_port(), &before);
    roz_g1fx_ask("corrupt");
    roz_g1fx_wait_judged(&before, 0);
    tick_rt();
    in = inputs_now();
    assert_true(in[0] == 0.8 * 0.25);
    assert_true(in[3] == 0.0);
    assert_int_equal(counters().remote_frames, 4);

    /* the G1's remote e-stop, L2 (bit 5) + B (bit 9), from the robot */
    assert_int_equal(m->remote_estop, 32 | 512);
    roz_g1fx_ask("remote L2+B 0 0 0 0 0");
    roz_g1fx_send();
    tick_rt();
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    roz_g1fx_ask("remote - 0 0 0 0 0"); /* released: latched still */
    roz_g1fx_send();
    tick_rt();
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_ESTOP);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    roz_g1fx_send();
    tick_rt();
    assert_int_equal(roz_runtime_faults(&rt), 0);
    roz_runtime_deinit(&rt);
}

/* ---- the robot's variant ------------------------------------------------------------ */

/* The 29-DoF manifest on a robot whose @p mode_machine lacks @p joint: the
 * runtime latches ROZ_FAULT_ROBOT naming the joint and the mode_machine, and
 * the robot gets no command at all. */
static void expect_variant_refused(int mode_machine, const char *joint)
{
    uint64_t good = 1, bad = 1;
    char code[16];

    open_g1(NULL, 0);
    roz_g1fx_ask("mode_machine %d", mode_machine);
    start_runtime();
    for (int t = 0; t < 20; t++) {
        roz_g1fx_send();
        tick_rt();
    }
    assert_int_equal(roz_runtime_faults(&rt) & ROZ_FAULT_ROBOT, ROZ_FAULT_ROBOT);
    const char *msg = roz_runtime_fault_message(&rt);
    snprintf(code, sizeof code, "%d", mode_machine);
    if (strstr(msg, joint) == NULL || strstr(msg, "mode_machine") == NULL ||
        strstr(msg, code) == NULL)
        fail_msg("the fault names not the joint %s and mode_machine %d: \"%s\"", joint,
                 mode_machine, msg);
    roz_port_test_assert_fault(joint, NULL, (uint32_t)mode_machine);
    /* written to the port straight, past the latch: still nothing goes out */
    roz_port_test_distinct_command(m, 3, cmd);
    roz_port_test_write();
    roz_g1fx_settle();
    assert_int_equal(counters().published, 0);
    assert_true(counters().refused_mode_machine >= 1);
    assert_int_equal(roz_fake_g1_commands(roz_g1fx_fake(), &good, &bad), 0);
    assert_int_equal(good, 0);
    assert_int_equal(bad, 0);
    roz_runtime_deinit(&rt);
}

static void test_g1_variant_mismatch(void **st)
{
    (void)st;
    /* 23-DoF: the first listed joint of slots 13, 14, 20, 21, 27, 28 */
    expect_variant_refused(10, "waist_roll_joint");
    teardown(NULL);
    expect_variant_refused(4, "waist_roll_joint");
    teardown(NULL);
    /* a locked waist */
    expect_variant_refused(12, "waist_roll_joint");
    teardown(NULL);
    /* listed in reverse, the first absent one is the right wrist's yaw */
    m = reversed_g1();
    expect_variant_refused(10, "right_wrist_yaw_joint");
}

/* ---- decimation ----------------------------------------------------------------------- */

static void test_g1_decimation(void **st)
{
    (void)st;

    open_g1((roz_param_t[]){ { "state_decimation", "4" } }, 1);
    roz_port_test_decimation("left_hip_pitch_joint", roz_g1fx_send, roz_g1fx_sent);
    assert_int_equal(counters().full_conversions, 3);
    assert_int_equal(counters().frames, 12);
    /* every frame is still checked: a bad CRC on a frame between two whole
     * conversions, and a fault code */
    roz_link_t before;
    roz_unitree_g1_link(roz_g1fx_port(), &before);
    roz_g1fx_ask("corrupt");
    roz_g1fx_wait_judged(&before, 0);
    assert_int_equal(roz_port_test_read(), 0);
    roz_g1fx_ask("motorstate 20 7");
    roz_g1fx_send(); /* frame 13: not converted whole */
    assert_int_equal(roz_port_test_read(), ROZ_EROBOT);
    roz_port_test_assert_fault("left_wrist_pitch_joint", NULL, 7);
    assert_int_equal(counters().full_conversions, 4); /* frames 1, 5, 9, 13 of the robot */
}

/* ---- the writer -------------------------------------------------------------------- */

static void test_g1_periodic_writer(void **st)
{
    roz_fake_g1_cmd_t c;
    uint64_t good = 0, bad = 0, good0 = 0;
    (void)st;

    open_g1((roz_param_t[]){ { "command_writer_period_us", "2000" } }, 1);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    for (int k = 0; k < 70; k++) /* past the replay window: a restart shows */
        tick_alive(3);
    get_command(&c);
    /* no more writes: the writer goes on publishing the last command */
    assert_int_equal(roz_fake_g1_commands(roz_g1fx_fake(), &good0, &bad), 0);
    ROZ_PORT_TEST_WAIT_UNTIL(roz_fake_g1_commands(roz_g1fx_fake(), &good, &bad) == 0 && good >= good0 + 50);
    assert_int_equal(bad, 0);
    get_command(&c);
    assert_true(c.q[5] == (float)cmd[cmd_index(5, "position")]);

    /* a restarted robot gets nothing until the tick writes for it */
    roz_g1fx_ask("restart");
    roz_link_t before;
    roz_unitree_g1_link(roz_g1fx_port(), &before);
    roz_g1fx_set_state(100);
    roz_g1fx_ask("send");
    roz_g1fx_wait_judged(&before, 2); /* the new writer: again until discovered */
    assert_int_equal(roz_port_test_read(), ROZ_ELINK);
    /* (until its first frame reached the port, the port could not know:
     * the old command went on; from then on, nothing) */
    /* a pass of the writer after it: stale, nothing sent; then what it
     * published before has reached the robot (however slowly a loaded
     * machine runs either), and nothing more comes */
    ROZ_PORT_TEST_WAIT_UNTIL(counters().stale_session >= 1);
    roz_g1fx_settle();
    uint64_t after = 0, later = 0, published = counters().published;
    assert_int_equal(roz_fake_g1_commands(roz_g1fx_fake(), &after, &bad), 0);
    roz_fake_g1_sleep_ms(50); /* 25 periods of the writer */
    assert_int_equal(roz_fake_g1_commands(roz_g1fx_fake(), &later, &bad), 0);
    assert_int_equal(later, after);
    assert_int_equal(counters().published, published);
    /* the tick writes: the hold of the restarted robot's positions */
    roz_port_test_distinct_command(m, 4, cmd);
    roz_port_test_write();
    get_command(&c);
    roz_g1fx_sent(sent);
    assert_true(c.q[3] == sent[state_index("left_knee_joint/position")]);
    assert_true(c.kp[3] == 0.0 && c.kd[3] == 0.0);

    /* the monitors saw the writer's periods and the state handler */
    roz_monitor_stat_t s;
    assert_int_equal(
        roz_monitor_snapshot(roz_unitree_g1_writer_monitor(roz_g1fx_port()), ROZ_MON_JITTER, &s),
        ROZ_OK);
    assert_true(s.count >= 50);
    assert_int_equal(
        roz_monitor_snapshot(roz_unitree_g1_state_monitor(roz_g1fx_port()), ROZ_MON_STATE_HANDLER,
                             &s),
        ROZ_OK);
    assert_true(s.count >= 1);
}

static void test_g1_startup_and_shutdown_damping(void **st)
{
    roz_fake_g1_cmd_t c;
    (void)st;

    /* damping on exit is a choice (the default is the hold:
     * test_g1_exit_is_the_hold) */
    open_g1((roz_param_t[]){ { "startup_damping", "2.5" }, { "exit_stop", "damping" } }, 2);
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_g1fx_sent(sent);
    roz_port_test_distinct_command(m, 1, cmd);
    roz_port_test_write(); /* the first write: the hold, with the damping asked for */
    get_command(&c);
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) {
        char name[160];
        snprintf(name, sizeof name, "%s/position", m->hardware->joints[j]);
        assert_true(c.q[j] == sent[state_index(name)]);
        assert_true(c.kp[j] == 0.0 && c.dq[j] == 0.0 && c.tau[j] == 0.0);
        assert_true(c.kd[j] == 2.5);
    }
    assert_int_equal(counters().holds, 1);
    roz_port_test_write(); /* the next goes out as written */
    get_command(&c);
    assert_true(c.kp[0] == (float)cmd[cmd_index(0, "stiffness")]);

    /* shutdown: the damping command, kd the manifest's damping default,
     * repeated for ROZ_DDS_SHUTDOWN_REPEAT_MS (the robot's reader may be best
     * effort and lose one): all of them, or on a loaded machine most */
    const uint64_t repeats = ROZ_DDS_SHUTDOWN_REPEAT_MS * 1000u / ROZ_DDS_SHUTDOWN_REPEAT_US;
    uint64_t good0 = 0, good = 0, bad = 0;
    assert_int_equal(roz_fake_g1_commands(roz_g1fx_fake(), &good0, &bad), 0);
    assert_int_equal(roz_port_deactivate(&port), ROZ_OK);
    ROZ_PORT_TEST_WAIT_UNTIL(roz_fake_g1_commands(roz_g1fx_fake(), &good, &bad) == 0 && good > good0);
    for (int i = 0; i < 2000 && good < good0 + repeats; i++) {
        roz_fake_g1_sleep_ms(1);
        assert_int_equal(roz_fake_g1_commands(roz_g1fx_fake(), &good, &bad), 0);
    }
    assert_true(good > good0 && good <= good0 + repeats);
    assert_int_equal(roz_fake_g1_command(roz_g1fx_fake(), &c), 1);
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) {
        const roz_channel_t *kd = &m->commands[cmd_index(j, "damping")];
        assert_int_equal(c.mode[j], 1);
        assert_true(c.kp[j] == 0.0 && c.dq[j] == 0.0 && c.tau[j] == 0.0);
        assert_true(c.kd[j] == (float)kd->default_value);
        assert_true(c.q[j] == (float)cmd[cmd_index(j, "position")]);
    }
}

/* ---- the command watchdog --------------------------------------------------------------- */

static uint64_t fake_good(void)
{
    uint64_t good = 0, bad = 0;
    assert_int_equal(roz_fake_g1_commands(roz_g1fx_fake(), &good, &bad), 0);
    assert_int_equal(bad, 0);
    return good;
}

/* The command path of the port under test. */
static roz_dds_cmd_t *path(void)
{
    return &roz_g1fx_port()->cmd;
}

static void clock_before_activate(const roz_port_t *pt)
{
    roz_port_test_watchdog_clock(&((roz_unitree_g1_t *)pt->self)->cmd);
}

/* The next open's command watchdog counts on the test's clock
 * (roz_port_test_clock(): standing still at 5 s until the test moves it),
 * from before its writer starts: an event-driven writer judges on it when
 * the watchdog is due. */
static void clock_next_open(void)
{
    roz_g1fx_set_before_activate(clock_before_activate);
}

/* The tick's period on the watchdog's clock: an event-driven writer
 * repeats the watchdog's hold at it. */
static uint64_t tick_ns(void)
{
    return 1000000000u / m->control_rate_hz;
}

/* The watchdog's clock @p ns on, and the writer woken to look at it (an
 * event-driven one; a periodic one looks every period). */
static void clock_on(uint64_t ns)
{
    roz_port_test_clock_add(ns);
    roz_dds_writer_nudge(&roz_g1fx_port()->writer);
}

/* Whether @p c is the watchdog's hold over the positions @p q (manifest
 * order of the joints): mode 1, q, kp the stiffness channel's default,
 * dq 0, tau 0, kd the damping channel's default, for every joint; the
 * unused slots zero. */
/* The positions the watchdog's hold sends after the command in cmd[] went
 * out against the state last read: each joint's setpoint moved to keep
 * the torque it went out with at the hold gain, within the band of the
 * measured position (roz/hold.h), from the values as the wire carried them. */
static void watchdog_positions(double *q)
{
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) {
        const roz_channel_t *qc = &m->commands[cmd_index(j, "position")];
        const roz_channel_t *kc = &m->commands[cmd_index(j, "stiffness")];
        double sent_q = (float)cmd[cmd_index(j, "position")];
        double sent_kp = (float)cmd[cmd_index(j, "stiffness")];
        double measured = (float)state[qc->position_state];
        roz_hold_from_t from = { sent_q, sent_kp, measured };
        q[j] = roz_channel_clamp_float(qc, roz_hold_setpoint(&from, kc->default_value,
                                                             roz_hold_band(qc)));
    }
}

/* Whether @p c is the stop's hold the port sends when the tick comes back
 * after a trip (roz_joints_hold_keep()): from @p last, the tick's last
 * command before it, and @p measured (state order), each joint at its hold
 * gain, the setpoint keeping the torque of @p last within the band, kd the
 * damping command's: never a frame without stiffness between the
 * watchdog's hold and the tick's (test_g1_trip_write_trip_keeps_the_torque). */
static void assert_hold_after_trip(const roz_fake_g1_cmd_t *c, const double *last,
                                   const double *measured)
{
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) {
        const roz_channel_t *qc = &m->commands[cmd_index(j, "position")];
        const roz_channel_t *kc = &m->commands[cmd_index(j, "stiffness")];
        roz_hold_from_t from = { roz_channel_clamp(qc, last[cmd_index(j, "position")]),
                                 roz_channel_clamp(kc, last[cmd_index(j, "stiffness")]),
                                 measured[qc->position_state] };
        double q = roz_channel_clamp_float(qc, roz_channel_clamp(qc, roz_hold_setpoint(
                                                   &from, kc->default_value, roz_hold_band(qc))));
        if (fabs(c->q[j] - q) > 4.0 * FLT_EPSILON * (1.0 + fabs(q)) ||
            c->kp[j] != (float)kc->default_value ||
            c->kd[j] != (float)m->commands[cmd_index(j, "damping")].default_value)
            fail_msg("%s: q %g kp %g kd %g after the trip: not the stop's hold (q %g kp %g)",
                     m->hardware->joints[j], (double)c->q[j], (double)c->kp[j],
                     (double)c->kd[j], q, kc->default_value);
    }
}

static int is_watchdog_hold(const roz_fake_g1_cmd_t *c, const double *q)
{
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) {
        const roz_channel_t *kd = &m->commands[cmd_index(j, "damping")];
        /* the watchdog's hold: kp the manifest's hold gain (test_mujoco_stops) */
        const roz_channel_t *kp = &m->commands[cmd_index(j, "stiffness")];
        /* q within a float's rounding of the double arithmetic */
        if (c->mode[j] != 1 || fabs(c->q[j] - q[j]) > 4.0 * FLT_EPSILON * (1.0 + fabs(q[j])) ||
            c->kp[j] != (float)kp->default_value ||
            c->dq[j] != 0.0 ||
            c->tau[j] != 0.0 || c->kd[j] != (float)kd->default_value) {
            return 0;
        }
    }
    for (int j = ROZ_UNITREE_G1_BODY; j < ROZ_UNITREE_G1_SLOTS; j++) {
        if (c->mode[j] != 0 || c->kp[j] != 0.0 || c->kd[j] != 0.0 || c->q[j] != 0.0)
            return 0;
    }
    return 1;
}

/* Whether @p c carries the command in cmd[] (every joint's five fields). */
static int is_written(const roz_fake_g1_cmd_t *c)
{
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) {
        if (c->q[j] != (float)cmd[cmd_index(j, "position")] ||
            c->kp[j] != (float)cmd[cmd_index(j, "stiffness")] ||
            c->kd[j] != (float)cmd[cmd_index(j, "damping")])
            return 0;
    }
    return 1;
}

/* The tick back after a trip that read() reported: its write of command
 * @p k goes out as the stop's hold from @p last, the tick's command before
 * the trip, against the frame read with the report; after the next frame,
 * command @p k + 1 as written; one trip in all. */
static void expect_back_after_trip(const double *last, int k)
{
    roz_fake_g1_cmd_t c;
    roz_port_test_distinct_command(m, k, cmd);
    roz_port_test_write();
    get_command(&c);
    roz_g1fx_sent(sent);
    assert_hold_after_trip(&c, last, sent);
    tick_alive(k + 1);
    get_command(&c);
    assert_true(is_written(&c));
    assert_int_equal(counters().command_timeouts, 1);
}

/* The start-up hold is one frame of the latest-value hand-off: the tick
 * writing again before the writer sent it must not make the controller's
 * command the robot's first. The writer is held back (the command path's
 * test hook) across the hold and two writes more. */
static void test_g1_hold_reaches_the_wire_first(void **st)
{
    roz_fake_g1_cmd_t c;
    (void)st;

    open_g1(NULL, 0);
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_g1fx_sent(sent);
    roz_port_test_write_held_back(&roz_g1fx_port()->cmd);
    roz_g1fx_settle();
    ROZ_PORT_TEST_WAIT_UNTIL(fake_good() >= 1);
    assert_int_equal(roz_fake_g1_command_at(roz_g1fx_fake(), 1, &c), 1);
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) {
        char name[160];
        snprintf(name, sizeof name, "%s/position", m->hardware->joints[j]);
        if (c.kp[j] != 0.0 || c.q[j] != (float)sent[state_index(name)])
            fail_msg("the robot's first command is not the hold: %s q %g kp %g",
                     m->hardware->joints[j], c.q[j], c.kp[j]);
    }
    roz_port_test_write(); /* the hold went out: the controller drives now */
    get_command(&c);
    assert_true(is_written(&c));
    assert_int_equal(counters().holds, 1);
}

/* Every value on the wire is inside the manifest as the robot compares it
 * (float): a position limit of 2.8798 (2.87980008 as the nearest float)
 * narrows toward the inside, and the damping command after a watchdog trip
 * keeps the stiffness at the channel's minimum when that is above 0. */
static roz_channel_t tight_commands[ROZ_CFG_MAX_COMMANDS];
static roz_manifest_t tight;

static void test_g1_wire_inside_the_manifest(void **st)
{
    roz_fake_g1_cmd_t c;
    const roz_manifest_t *g1 = &roz_manifest_unitree_g1;
    (void)st;

    memcpy(tight_commands, g1->commands, g1->n_commands * sizeof tight_commands[0]);
    tight = *g1;
    tight.commands = tight_commands;
    int q0 = roz_port_test_command(g1, g1->hardware->joints[0], "position", 1);
    tight_commands[q0].max = 2.8798;
    assert_true((double)(float)2.8798 > 2.8798); /* the case at hand */
    tight.fall = NULL; /* a stiffness floor: no fallen stop (its kp 0) can be sent */
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) {
        roz_channel_t *kp =
            &tight_commands[roz_port_test_command(g1, g1->hardware->joints[j], "stiffness", 1)];
        kp->min = 5.0;
        kp->default_value = 5.0;
    }
    assert_int_equal(roz_manifest_validate(&tight, NULL), ROZ_OK);
    clock_next_open(); /* the trip when the test says, not after a stall */
    /* driven: read() and write() on it, run alone or after another case */
    roz_port_test_drive(&roz_fixture_unitree_g1, &tight,
                        (roz_param_t[]){ { "command_timeout_us", "100000" },
                                         { "peer_timeout_ms", "60000" } },
                        2, &port, state, cmd);
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_port_test_distinct_command(&tight, 1, cmd);
    cmd[q0] = 2.8798;
    roz_port_test_write(); /* the hold */
    roz_g1fx_settle();
    roz_port_test_write();
    get_command(&c);
    int s0 = roz_g1fx_slot(g1->hardware->joints[0]);
    if ((double)c.q[s0] > 2.8798)
        fail_msg("q %.9g on the wire: outside the limit 2.8798", (double)c.q[s0]);
    assert_true(c.q[s0] == nextafterf((float)2.8798, 0.0f));

    roz_port_test_watchdog_trip(path(), 100000u, fake_good);
    uint64_t tripped = fake_good();
    clock_on(tick_ns()); /* two more of the event-driven writer's holds */
    ROZ_PORT_TEST_WAIT_UNTIL(counters().safe_published >= 2);
    clock_on(tick_ns());
    assert_int_equal(roz_fake_g1_ask(roz_g1fx_fake(), "wait_commands %llu 60000",
                                     (unsigned long long)tripped + 2u),
                     0);
    assert_int_equal(roz_fake_g1_command(roz_g1fx_fake(), &c), 1);
    for (uint16_t j = 0; j < ROZ_UNITREE_G1_BODY; j++) {
        int sj = roz_g1fx_slot(g1->hardware->joints[j]);
        if (c.kp[sj] != 5.0f || !(c.kd[sj] > 0.0f))
            fail_msg("%s in the damping command: kp %g kd %g: kp outside [5, ...]",
                     g1->hardware->joints[j], (double)c.kp[sj], (double)c.kd[sj]);
    }
    assert_true((double)c.q[s0] <= 2.8798);
}

/* A joint without a position command (the knee here: stiffness, damping
 * alone) is sent its measured position, the last finite one: NaN from the
 * robot never goes out, and a joint never measured finite gets no
 * stiffness against a made-up target. */
static roz_channel_t no_q_commands[ROZ_CFG_MAX_COMMANDS];
static roz_manifest_t no_q;

static void send_raw(void)
{
    roz_link_t before;
    roz_unitree_g1_link(roz_g1fx_port(), &before);
    roz_g1fx_ask("send");
    roz_g1fx_wait_judged(&before, 1);
}

static void test_g1_joint_without_position_command(void **st)
{
    roz_fake_g1_cmd_t c;
    const roz_manifest_t *g1 = &roz_manifest_unitree_g1;
    (void)st;

    int knee_q = roz_port_test_command(g1, "left_knee_joint", "position", 1);
    uint16_t n = 0;
    for (uint16_t i = 0; i < g1->n_commands; i++) {
        if (i != knee_q)
            no_q_commands[n++] = g1->commands[i];
    }
    no_q = *g1;
    no_q.commands = no_q_commands;
    no_q.n_commands = n;
    assert_int_equal(roz_manifest_validate(&no_q, NULL), ROZ_OK);
    int kp = roz_port_test_command(&no_q, "left_knee_joint", "stiffness", 1);
    int slot = roz_g1fx_slot("left_knee_joint");
    roz_port_test_open(&roz_fixture_unitree_g1, &no_q, NULL, 0, &port);

    roz_g1fx_set_state(1);
    roz_g1fx_ask("motor %d nan 0 0", slot);
    send_raw();
    assert_int_equal(roz_port_read(&port, state, m->n_states), 1);
    roz_port_test_distinct_command(&no_q, 1, cmd);
    cmd[kp] = 80.0;
    assert_int_equal(roz_port_write(&port, cmd, no_q.n_commands), ROZ_OK); /* the hold */
    roz_g1fx_settle();
    assert_int_equal(roz_port_write(&port, cmd, no_q.n_commands), ROZ_OK);
    get_command(&c);
    assert_true(c.q[slot] == 0.0f && c.kp[slot] == 0.0f); /* never measured */

    roz_g1fx_ask("motor %d 0.75 0 0", slot);
    send_raw();
    assert_int_equal(roz_port_read(&port, state, m->n_states), 1);
    assert_int_equal(roz_port_write(&port, cmd, no_q.n_commands), ROZ_OK);
    get_command(&c);
    assert_true(c.q[slot] == 0.75f && c.kp[slot] == 80.0f);

    roz_g1fx_ask("motor %d nan 0 0", slot);
    send_raw();
    assert_int_equal(roz_port_read(&port, state, m->n_states), 1);
    assert_int_equal(roz_port_write(&port, cmd, no_q.n_commands), ROZ_OK);
    get_command(&c);
    if (!(c.q[slot] == 0.75f && c.kp[slot] == 80.0f))
        fail_msg("NaN measured: q %g kp %g on the wire; expected the last finite 0.75",
                 (double)c.q[slot], (double)c.kp[slot]);
}

/* The watchdog on real time, counting the periodic writer's passes: the
 * tick alive on the test's clock standing still (a loaded machine's stall
 * between two writes is no silence), the last command written and on the
 * robot; from then the clock follows the monotonic one, and the tick is
 * silent. The writer's own counts say what it sent after that: the last
 * command on no more passes than the timeout's periods allow (one more
 * for the interval's ends, two late ones caught up, one in progress when
 * the clock started: however slow the machine, a late writer sends
 * fewer, never a burst), then the watchdog's hold alone; on the wire in
 * that order. Once the trip is seen the clock stands still again, so
 * read() names the silence exactly and the tick's return is not timed. */
static void test_g1_watchdog_on_the_wire(void **st)
{
    roz_fake_g1_cmd_t c;
    double q[ROZ_UNITREE_G1_BODY];
    const unsigned period_us = 2000, timeout_us = 100000;
    (void)st;

    /* the robot says nothing while the tick is away: no link fault meanwhile */
    clock_next_open();
    open_g1(roz_port_test_watched, ROZ_PORT_TEST_WATCHED_N);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    for (int k = 1; k <= 5; k++) { /* a tick alive: commands as written */
        tick_alive(k);
    }
    get_command(&c);
    assert_true(is_written(&c));
    assert_int_equal(counters().command_timeouts, 0);

    /* the last write, on the robot; then the tick stops, on real time */
    roz_port_test_distinct_command(m, 6, cmd);
    watchdog_positions(q);
    uint64_t written_at = roz_port_test_clock(NULL);
    roz_port_test_write();
    get_command(&c);
    assert_true(is_written(&c));
    uint64_t before = fake_good();
    roz_unitree_g1_counters_t c0 = settled_counters();
    roz_port_test_clock_follow(1);
    ROZ_PORT_TEST_WAIT_UNTIL(counters().command_timeouts == 1);
    roz_port_test_clock_follow(0);
    uint64_t silent_until = roz_port_test_clock(NULL);
    ROZ_PORT_TEST_WAIT_UNTIL(counters().safe_published >= c0.safe_published + 5u);
    /* one reading between two passes: the five holds among published (read
     * during the fifth's pass, published lacked it, and the robot, waited
     * for up to published below, could have shown four) */
    roz_unitree_g1_counters_t c1 = settled_counters();
    uint64_t published = c1.published;
    uint64_t copies = published - c0.published - (c1.safe_published - c0.safe_published);
    if (copies > timeout_us / period_us + 4u)
        fail_msg("the writer sent the last command %llu times after the tick stopped: more "
                 "than the timeout allows (%u)",
                 (unsigned long long)copies, timeout_us / period_us + 4u);
    assert_int_equal(counters().command_timeouts, 1); /* once, however long */

    /* on the wire: copies of the last command, then only the hold (the
     * robot has counted every command the port published so far, the
     * five holds among them) */
    assert_int_equal(roz_fake_g1_ask(roz_g1fx_fake(), "wait_commands %llu 60000",
                                     (unsigned long long)published),
                     0);
    uint64_t now = fake_good();
    unsigned damping = 0;
    for (uint64_t k = before + 1; k <= now; k++) {
        assert_int_equal(roz_fake_g1_command_at(roz_g1fx_fake(), k, &c), 1);
        if (is_watchdog_hold(&c, q))
            damping++;
        else if (damping != 0 || !is_written(&c))
            fail_msg("command %llu: neither the last command before the watchdog's hold nor "
                     "the hold", (unsigned long long)k);
    }
    assert_true(damping >= 5);
    assert_true(counters().safe_published >= damping);

    /* the tick is back: read() reports the trip once, naming the silence
     * by the clock, to the microsecond */
    roz_port_fault_t f;
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EWATCHDOG);
    assert_int_equal(roz_unitree_g1_ops.fault(roz_g1fx_port(), &f), ROZ_OK);
    assert_string_equal(f.what, "command_timeout_us");
    assert_int_equal(f.limit, timeout_us);
    assert_int_equal(f.code, (silent_until - written_at) / 1000u);
    assert_true(f.code >= timeout_us);
    roz_g1fx_sent(sent);
    assert_true(state[state_index("left_knee_joint/position")] ==
                sent[state_index("left_knee_joint/position")]); /* read with the report */
    assert_int_equal(roz_port_test_read(), 0);
    /* its first write is the stop's hold from the last command before the
     * trip, at the hold gains, the damping the robot is in already */
    static double before_trip[ROZ_CFG_MAX_COMMANDS];
    memcpy(before_trip, cmd, sizeof before_trip);
    expect_back_after_trip(before_trip, 7);
}

/* Command @p k written, which the robot gets as written: the tick's last
 * before it stops; @p q the positions the watchdog's hold will keep
 * (watchdog_positions()). */
static void write_last(int k, double *q)
{
    roz_fake_g1_cmd_t c;
    roz_port_test_distinct_command(m, k, cmd);
    watchdog_positions(q);
    roz_port_test_write();
    get_command(&c);
    assert_true(is_written(&c));
}

/* The silence the watchdog's report names after expect_trip_on_clock():
 * the timeout, 1 ns, and four tick periods, in whole microseconds. */
#define SILENCE_ON_CLOCK_US (100000u + 4u * 2000u)

/* The tick has stopped after write_last() on an event-driven writer whose
 * watchdog (100 ms) counts on the test's clock (clock_next_open()): 100 ms
 * of silence to the ns is not a trip (a pass posted sends the last command
 * again), 1 ns more is, found by the writer itself
 * (roz_port_test_watchdog_trip()); its pass sends the watchdog's hold over
 * @p q, and so does exactly one pass for each tick period the clock moves
 * on after it (the writer woken to look: roz_dds_writer_nudge()), nothing
 * else: on the wire the last command once more, then five holds. */
static void expect_trip_on_clock(const double *q)
{
    roz_fake_g1_cmd_t c;
    uint64_t written = fake_good();
    assert_int_equal(tick_ns(), 2000000u); /* SILENCE_ON_CLOCK_US */
    roz_port_test_watchdog_trip(path(), 100000u, fake_good);
    ROZ_PORT_TEST_WAIT_UNTIL(counters().safe_published == 1);
    for (uint64_t k = 2; k <= 5; k++) {
        clock_on(tick_ns());
        ROZ_PORT_TEST_WAIT_UNTIL(counters().safe_published >= k);
    }
    assert_int_equal(roz_fake_g1_ask(roz_g1fx_fake(), "wait_commands %llu 60000",
                                     (unsigned long long)written + 6u),
                     0);
    assert_int_equal(counters().safe_published, 5); /* one pass a period, none of its own */
    assert_int_equal(counters().command_timeouts, 1);
    assert_int_equal(roz_fake_g1_command_at(roz_g1fx_fake(), written + 1u, &c), 1);
    if (!is_written(&c))
        fail_msg("command %llu, at exactly the timeout: not the last command",
                 (unsigned long long)written + 1u);
    for (uint64_t k = written + 2u; k <= written + 6u; k++) {
        assert_int_equal(roz_fake_g1_command_at(roz_g1fx_fake(), k, &c), 1);
        if (!is_watchdog_hold(&c, q))
            fail_msg("command %llu after the tick stopped: not the watchdog's hold",
                     (unsigned long long)k);
    }
}

/* Event-driven: nothing wakes the writer once the tick stops but the
 * watchdog itself, due by the path's clock (the test's: how late the
 * writer runs on a loaded machine does not change what it sends), which
 * then repeats the hold at the tick's rate on that clock; read() reports
 * the silence exactly; the tick's next write is the stop's hold. */
static void test_g1_watchdog_event_driven(void **st)
{
    roz_port_fault_t f;
    double q[ROZ_UNITREE_G1_BODY];
    static double last[ROZ_CFG_MAX_COMMANDS];
    (void)st;

    clock_next_open();
    open_g1((roz_param_t[]){ { "command_writer_period_us", "0" },
                             { "command_timeout_us", "100000" },
                             { "peer_timeout_ms", "60000" } },
            3);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    write_last(1, q);
    memcpy(last, cmd, sizeof last);
    expect_trip_on_clock(q);
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EWATCHDOG);
    assert_int_equal(roz_unitree_g1_ops.fault(roz_g1fx_port(), &f), ROZ_OK);
    assert_string_equal(f.what, "command_timeout_us");
    assert_int_equal(f.code, SILENCE_ON_CLOCK_US);
    assert_int_equal(f.limit, 100000u);
    assert_int_equal(roz_port_test_read(), 0);
    expect_back_after_trip(last, 2);
}

/* The watchdog on a clock the test moves (the command path's, set here
 * before the first write; the writer reads it only with a frame): the
 * tick alive, however slowly the machine runs it (QEMU's emulation, a
 * loaded host), commands as written; then silent for 150 ms by that
 * clock: the robot gets the watchdog's hold, read() reports the trip once
 * naming exactly 150000 us, the next write is the stop's hold from the
 * last command, then commands as written again. test_g1_watchdog_on_the_wire
 * lets the clock follow real time while the tick is silent and counts the
 * writer's passes meanwhile. */
static void test_g1_watchdog_on_its_clock(void **st)
{
    roz_fake_g1_cmd_t c;
    roz_port_fault_t f;
    double q[ROZ_UNITREE_G1_BODY];
    static double last[ROZ_CFG_MAX_COMMANDS];
    (void)st;

    /* periodic (event-driven: test_g1_watchdog_event_driven) */
    clock_next_open();
    open_g1(roz_port_test_watched, ROZ_PORT_TEST_WATCHED_N);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    for (int k = 1; k <= 3; k++) { /* alive: 99.999 ms between writes is not silence */
        tick_alive(k);
        get_command(&c);
        assert_true(is_written(&c));
        roz_port_test_clock_add(99999000u);
        /* two more of the periodic writer's passes judged it at that age */
        assert_int_equal(roz_fake_g1_ask(roz_g1fx_fake(), "wait_commands %llu 60000",
                                         (unsigned long long)fake_good() + 2u),
                         0);
        assert_int_equal(roz_fake_g1_command(roz_g1fx_fake(), &c), 1);
        assert_true(is_written(&c));
    }
    assert_int_equal(counters().command_timeouts, 0);
    watchdog_positions(q);
    memcpy(last, cmd, sizeof last);
    uint64_t before = fake_good();
    roz_port_test_clock_add(150000000u - 99999000u); /* 150 ms since the last write */
    ROZ_PORT_TEST_WAIT_UNTIL(counters().command_timeouts == 1);
    assert_int_equal(roz_fake_g1_ask(roz_g1fx_fake(), "wait_commands %llu 60000",
                                     (unsigned long long)fake_good() + 5u),
                     0);
    /* the periodic writer's copies of the last command (some in flight
     * when the clock moved), then the watchdog's hold alone */
    uint64_t now = fake_good();
    unsigned holds = 0;
    for (uint64_t k = before + 1; k <= now; k++) {
        assert_int_equal(roz_fake_g1_command_at(roz_g1fx_fake(), k, &c), 1);
        if (is_watchdog_hold(&c, q))
            holds++;
        else if (holds != 0 || !is_written(&c))
            fail_msg("command %llu: neither the last command before the watchdog's hold nor "
                     "the hold", (unsigned long long)k);
    }
    assert_true(holds >= 5);
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EWATCHDOG);
    assert_int_equal(roz_unitree_g1_ops.fault(roz_g1fx_port(), &f), ROZ_OK);
    assert_string_equal(f.what, "command_timeout_us");
    assert_int_equal(f.code, 150000u);
    assert_int_equal(f.limit, 100000u);
    assert_int_equal(roz_port_test_read(), 0);
    expect_back_after_trip(last, 4);
}

/* The port's exit is the robot class's stop: the hold, as the watchdog
 * sends it, from the controller's last command (the damping command the
 * exit sent before drops a standing humanoid: SAFETY.md section 8). */
static void test_g1_exit_is_the_hold(void **st)
{
    roz_fake_g1_cmd_t c;
    double q[ROZ_UNITREE_G1_BODY];
    (void)st;

    open_g1(NULL, 0);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    write_last(1, q);
    uint64_t good0 = 0, good = 0, bad = 0;
    assert_int_equal(roz_fake_g1_commands(roz_g1fx_fake(), &good0, &bad), 0);
    assert_int_equal(roz_port_deactivate(&port), ROZ_OK);
    ROZ_PORT_TEST_WAIT_UNTIL(roz_fake_g1_commands(roz_g1fx_fake(), &good, &bad) == 0 && good > good0);
    roz_fake_g1_sleep_ms(20);
    assert_int_equal(roz_fake_g1_command(roz_g1fx_fake(), &c), 1);
    if (!is_watchdog_hold(&c, q))
        fail_msg("the last command on the way out is not the stop's hold: kp %g q %g (want %g)",
                 (double)c.kp[3], (double)c.q[3], q[3]);
    assert_true(c.kp[3] > 0.0f);
}

/* The watchdog's hold on a G1 whose left knee has a stiffness command but
 * no position command: the knee holds the position measured with the last
 * command, at its hold gain, never 0 rad (a knee at 0.75 rad once got q 0
 * at kp 200). And a tick that comes back for one write and stalls again:
 * its write goes out as the stop's hold (hold gains, never kp 0), and the
 * second trip holds the controller's last command's torque again, not that
 * of the frame the port made up: each joint gets what the first trip gave
 * it. */
static void test_g1_trip_write_trip_keeps_the_torque(void **st)
{
    static roz_channel_t cmds[ROZ_CFG_MAX_COMMANDS];
    static roz_manifest_t kneeless;
    roz_fake_g1_cmd_t c, first;
    double measured[ROZ_CFG_MAX_STATES];
    roz_port_fault_t f;
    (void)st;
    uint16_t n = 0;
    for (uint16_t i = 0; i < roz_manifest_unitree_g1.n_commands; i++) {
        if (strcmp(roz_manifest_unitree_g1.commands[i].name, "left_knee_joint/position") != 0)
            cmds[n++] = roz_manifest_unitree_g1.commands[i];
    }
    kneeless = roz_manifest_unitree_g1;
    kneeless.commands = cmds;
    kneeless.n_commands = n;
    m = &kneeless; /* the teardown puts the G1 back */
    int knee = roz_g1fx_slot("left_knee_joint"), hip = roz_g1fx_slot("left_hip_pitch_joint");
    int knee_q = state_index("left_knee_joint/position");
    int hip_kp = cmd_index((uint16_t)hip, "stiffness"), hip_q = cmd_index((uint16_t)hip, "position");
    int knee_kp = cmd_index((uint16_t)knee, "stiffness");

    clock_next_open(); /* the trips when the test says, however slow the machine */
    open_g1((roz_param_t[]){ { "command_timeout_us", "100000" },
                             { "peer_timeout_ms", "60000" } },
            2);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle);
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), 1);
    roz_g1fx_sent(measured);
    roz_port_test_distinct_command(m, 1, cmd);
    cmd[hip_kp] = 80.0;
    double p_before = measured[m->commands[hip_q].position_state];
    cmd[hip_q] = p_before + 0.02; /* 1.6 N*m */
    roz_port_test_write();
    get_command(&c);
    assert_true(c.kp[hip] == 80.0f);

    /* the first trip */
    roz_port_test_watchdog_trip(path(), 100000u, fake_good);
    roz_g1fx_settle();
    ROZ_PORT_TEST_WAIT_UNTIL(roz_fake_g1_command(roz_g1fx_fake(), &first) == 1 && first.kp[hip] != 80.0f);
    const roz_channel_t *ks = &m->states[knee_q];
    float knee_at = roz_channel_clamp_float(ks, measured[knee_q]);
    print_message("left knee without a position command, measured %.4f: the watchdog's hold "
                  "q %.4f kp %g; left hip pitch kp 80 at +0.02 rad: q %+.4f kp %g\n",
                  measured[knee_q], (double)first.q[knee], (double)first.kp[knee],
                  first.q[hip] - measured[m->commands[hip_q].position_state],
                  (double)first.kp[hip]);
    assert_true(first.q[knee] == knee_at);
    assert_true(first.kp[knee] == (float)m->commands[knee_kp].default_value);
    double torque = 80.0 * 0.02;
    double held = first.kp[hip] * (first.q[hip] - measured[m->commands[hip_q].position_state]);
    assert_true(fabs(held - torque) < 1e-3 * torque);

    /* back for one write: the stop's hold, at the hold gains */
    roz_g1fx_send();
    assert_int_equal(roz_port_test_read(), ROZ_EWATCHDOG);
    assert_int_equal(roz_unitree_g1_ops.fault(roz_g1fx_port(), &f), ROZ_OK);
    roz_port_test_distinct_command(m, 2, cmd);
    roz_port_test_write();
    get_command(&c);
    assert_true(c.kp[hip] == (float)m->commands[hip_kp].default_value);
    assert_true(c.kp[knee] == (float)m->commands[knee_kp].default_value);

    /* stalled again: the second trip holds the controller's torque about
     * where the joint is now (the frame read with the report) */
    clock_on(100000001u);
    ROZ_PORT_TEST_WAIT_UNTIL(counters().command_timeouts == 2);
    roz_g1fx_settle();
    get_command(&c);
    roz_g1fx_sent(measured);
    const roz_channel_t *qc = &m->commands[hip_q];
    double p = measured[qc->position_state];
    roz_hold_from_t from = { (float)(p_before + 0.02), 80.0, p };
    double want = roz_hold_setpoint(&from, m->commands[hip_kp].default_value, roz_hold_band(qc));
    print_message("second trip: left hip pitch q %+.4f kp %g (the controller's torque kept: "
                  "%+.4f)\n", c.q[hip] - p, (double)c.kp[hip], want - p);
    assert_true(c.kp[hip] == (float)m->commands[hip_kp].default_value);
    assert_true(fabs(c.q[hip] - want) < 4.0 * FLT_EPSILON * (1.0 + fabs(want)));
    assert_true(fabs(want - p) > 1e-4); /* a torque to keep: the test can fail */
    assert_true(c.q[knee] == roz_channel_clamp_float(ks, measured[knee_q]));
}

static void test_g1_watchdog_spinning_writer(void **st)
{
    double q[ROZ_UNITREE_G1_BODY];
    (void)st;

    /* a writer that spins for the tick's command after each LowState_,
     * fifty times longer than the robot's period: with the robot
     * publishing every 200 us a heads-up is always pending when a spin
     * ends, and the watchdog must still fire when the tick stops (a writer
     * that looked for the deadline only when a wait timed out never did,
     * unless the frames paused for a whole spin) */
    static const char *const periodic[] = { "--period-us", "200", NULL };
    roz_port_fault_t f;
    roz_g1fx_set_fake_args(periodic);
    clock_next_open(); /* the trip found by the writer itself, by the test's clock */
    open_g1((roz_param_t[]){ { "command_writer_period_us", "0" },
                             { "command_writer_spin_us", "10000" },
                             { "command_timeout_us", "100000" },
                             { "peer_timeout_ms", "60000" } },
            4);
    ROZ_PORT_TEST_WAIT_UNTIL(roz_port_test_read() == 1); /* one look, one read */
    roz_port_test_distinct_command(m, 0, cmd);
    roz_port_test_write(); /* the hold */
    roz_g1fx_settle(); /* the writes after it are holds until it went out */
    ROZ_PORT_TEST_WAIT_UNTIL(roz_port_test_read() == 1);
    write_last(1, q);
    expect_trip_on_clock(q);
    assert_int_equal(roz_port_test_read(), ROZ_EWATCHDOG); /* a frame read or not */
    assert_int_equal(roz_unitree_g1_ops.fault(roz_g1fx_port(), &f), ROZ_OK);
    assert_int_equal(f.code, SILENCE_ON_CLOCK_US);
}

static void test_g1_watchdog_latches_in_the_runtime(void **st)
{
    roz_fake_g1_cmd_t c;
    int knee_kp = cmd_index(3, "stiffness");
    (void)st;

    /* on the test's clock: however slowly a loaded machine runs the ticks,
     * the tick is silent only when the test says */
    clock_next_open();
    open_g1((roz_param_t[]){ { "command_timeout_us", "100000" }, { "peer_timeout_ms", "60000" } },
            2);
    start_runtime();
    /* past verification: the stand's gains reach the robot (before the
     * first tick the runtime's commands are the manifest's defaults) */
    for (int t = 0; t < 400 && (t == 0 || roz_runtime_last_commands(&rt)[knee_kp] <= 0.0); t++) {
        roz_g1fx_send();
        tick_rt();
    }
    assert_true(roz_runtime_last_commands(&rt)[knee_kp] > 0.0);
    /* and on the wire: a write before the writer sent the start-up hold
     * went out as the hold again (test_g1_hold_reaches_the_wire_first), so
     * tick on until the robot has a command with the stand's gains */
    roz_g1fx_settle();
    get_command(&c);
    for (int t = 0; t < 400 && !(c.kp[3] > 0.0); t++) {
        roz_g1fx_send();
        tick_rt();
        roz_g1fx_settle();
        get_command(&c);
    }
    assert_true(c.kp[3] > 0.0);
    if (roz_runtime_faults(&rt) != 0)
        fail_msg("a fault before the tick stopped: %s", roz_runtime_fault_message(&rt));

    /* the tick stops; the watchdog trips; the tick is back 150 ms after
     * its last write */
    roz_port_test_watchdog_trip(path(), 100000u, fake_good);
    roz_port_test_clock_add(50000000u - 1u);
    roz_g1fx_send();
    tick_rt();
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_COMMAND_TIMEOUT);
    const char *msg = roz_runtime_fault_message(&rt);
    unsigned long silent = 0, limit = 0;
    const char *at = strstr(msg, "the tick wrote no command for ");
    if (strstr(msg, "command timeout") == NULL || at == NULL ||
        sscanf(at, "the tick wrote no command for %lu us, longer than the port's "
                   "command_timeout_us (%lu)",
               &silent, &limit) != 2)
        fail_msg("the fault names neither the timeout nor the silence: \"%s\"", msg);
    assert_int_equal(limit, 100000);
    assert_int_equal(silent, 150000);
    assert_int_equal(roz_fault_name(ROZ_FAULT_COMMAND_TIMEOUT)[0], 'c');
    /* the tick's write after the trip: the stop's hold, the knee at its
     * hold gain (never a frame without stiffness) and the damping
     * command's kd */
    roz_g1fx_settle();
    get_command(&c);
    assert_true(c.kp[3] == (float)m->commands[cmd_index(3, "stiffness")].default_value);
    assert_true(c.kd[3] == (float)m->commands[cmd_index(3, "damping")].default_value);
    assert_true(counters().holds >= 2);

    /* latched (an immediate stop: the safe defaults) until cleared; then
     * the stand drives again */
    for (int t = 0; t < 20; t++) {
        roz_g1fx_send();
        tick_rt();
    }
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_COMMAND_TIMEOUT);
    /* the stop holds: the knee at its hold gain */
    assert_true(roz_runtime_last_commands(&rt)[knee_kp] == m->commands[knee_kp].default_value);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    for (int t = 0; t < 400 && roz_runtime_last_commands(&rt)[knee_kp] ==
                                   m->commands[knee_kp].default_value; t++) {
        roz_g1fx_send();
        tick_rt();
    }
    assert_int_equal(roz_runtime_faults(&rt), 0);
    roz_g1fx_settle();
    get_command(&c);
    assert_true(c.kp[3] > 0.0);
    assert_int_equal(counters().command_timeouts, 1);
    roz_runtime_deinit(&rt);
}

/* ---- refusals ----------------------------------------------------------------------- */

static void expect_refused(const roz_manifest_t *man, const char *key, const char *value,
                           const char *want1, const char *want2)
{
    static roz_unitree_g1_t g1;
    roz_port_t pt = roz_unitree_g1_port(&g1, NULL, NULL);
    roz_port_test_expect_refused(&pt, man, key, value, want1, want2);
}

/* a robot whose manifest has a channel the G1 has no place for */
static const roz_channel_t odd_commands[] = {
    { .name = "left_knee_joint/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 0.0, .position_state = 0 },
    { .name = "base/velocity.x", .type = ROZ_IF_VELOCITY, .unit = "m/s", .min = -1.0, .max = 1.0,
      .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_channel_t odd_states[] = {
    { .name = "left_knee_joint/position", .type = ROZ_IF_POSITION, .unit = "rad", .min = -1.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const char *const odd_joints[] = { "j1" };
static const char *const real_joints[] = { "left_knee_joint" };
static const roz_hardware_t real_hw = { "unitree/G1", real_joints, 1, NULL, 0 };
static const roz_hardware_t odd_hw = { "unitree/G1", odd_joints, 1, NULL, 0 };
static const roz_manifest_t odd = { "odd", "humanoid", 500, odd_commands, 2, odd_states, 1,
                                    &real_hw, NULL, 0, 0, NULL, NULL };
/* joint j1 is not a G1's */
static const roz_manifest_t unknown = { "unknown", "humanoid", 500, odd_commands, 1, odd_states,
                                        1, &odd_hw, NULL, 0, 0, NULL, NULL };
static const roz_channel_t typo_commands[] = {
    { .name = "left_knee_joint/stiffness", .type = ROZ_IF_DAMPING, .unit = "", .min = 0.0,
      .max = 1.0, .default_value = 0.0, .max_rate = 0.0, .position_state = ROZ_CHANNEL_UNPAIRED },
};
static const roz_manifest_t typo = { "typo", "humanoid", 500, typo_commands, 1, odd_states, 1,
                                     &real_hw, NULL, 0, 0, NULL, NULL };


/* The command writer thread carries the scheduling its parameters ask for:
 * affinity and stack size always, SCHED_FIFO where the process may have it
 * (roz/hal/thread.h); read back from the running thread. */
static void test_g1_writer_thread(void **st)
{
    roz_thread_config_t got;
    char cpus[8];
    int may_fifo;
    (void)st;
    int cpu = roz_test_thread_probe(5, cpus, sizeof cpus, &may_fifo);
    if (!may_fifo)
        print_message("SCHED_FIFO not permitted here: the writer's affinity and stack only\n");
    roz_param_t items[] = { { "command_writer_cpus", cpus },
                            { "command_writer_stack_kib", "384" },
                            { "command_writer_sched", "fifo" },
                            { "command_writer_priority", "5" } };
    open_g1(items, may_fifo ? 4 : 2);
    roz_port_test_start(roz_g1fx_send, roz_g1fx_settle); /* commands reach the robot */
    assert_int_equal(roz_dds_writer_thread(&roz_g1fx_port()->writer, &got), ROZ_OK);
    assert_int_equal(got.cpus, 1ull << cpu);
    assert_int_equal(got.stack_kib, 384);
    assert_int_equal(got.sched, may_fifo ? ROZ_THREAD_FIFO : ROZ_THREAD_OTHER);
    assert_int_equal(got.priority, may_fifo ? 5 : 0);
}

static void test_g1_bad_parameters(void **st)
{
    (void)st;
    static const struct { const char *key, *value; } bad[] = {
        { "network_interface", "eth0;rm" }, { "network_interface", "roznosuch0" },
        { "dds_domain", "999" },            { "command_writer_period_us", "10" },
        { "state_decimation", "0" },        { "enable_monitor", "maybe" },
        { "mode_pr", "XY" },                { "peer_timeout_ms", "5" },
        { "startup_damping", "11" },        { "shutdown_damping", "-1" },
        { "startup_damping", "nan" },       { "command_timeout_us", "3999" },
        { "command_timeout_us", "60000001" }, { "command_timeout_us", "fast" },
        { "command_writer_sched", "fast" },   { "command_writer_cpus", "64" },
        { "command_writer_stack_kib", "1" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        expect_refused(m, bad[i].key, bad[i].value, bad[i].key, bad[i].value);
    expect_refused(m, "no_such_key", "1", "no_such_key", "unitree/G1");
    /* manifests the G1 cannot serve */
    expect_refused(&roz_manifest_ur5, NULL, NULL, "[hardware] joints", NULL);
    expect_refused(&odd, NULL, NULL, "base/velocity.x", NULL);
    expect_refused(&typo, NULL, NULL, "left_knee_joint/stiffness", "damping");
    /* a joint by a name the G1 does not have, or twice */
    expect_refused(&unknown, NULL, NULL, "[hardware] joints[0] \"j1\"",
                   "is not one of the robot's joints");
    static const char *twice[29];
    static roz_hardware_t twice_hw;
    static roz_manifest_t twice_m;
    twice_m = *reversed_g1();
    memcpy(twice, reversed_joints, sizeof twice);
    twice[5] = twice[4];
    twice_hw = reversed_hw;
    twice_hw.joints = twice;
    twice_m.hardware = &twice_hw;
    expect_refused(&twice_m, NULL, NULL, "joints[5]", "duplicate of joints[4]");
}

int main(int argc, char **argv)
{
    static const struct CMUnitTest tests[] = {
        cmocka_unit_test_teardown(test_g1_joints_map_both_ways, teardown),
        cmocka_unit_test_teardown(test_g1_joints_by_name_reordered, teardown),
        cmocka_unit_test_teardown(test_g1_23dof, teardown),
        cmocka_unit_test_teardown(test_g1_variant_mismatch, teardown),
        cmocka_unit_test_teardown(test_g1_imu_order, teardown),
        cmocka_unit_test_teardown(test_g1_padding_and_crc, teardown),
        cmocka_unit_test_teardown(test_g1_mode_machine, teardown),
        cmocka_unit_test_teardown(test_g1_motor_fault_latches, teardown),
        cmocka_unit_test_teardown(test_g1_wireless_remote, teardown),
        cmocka_unit_test_teardown(test_g1_decimation, teardown),
        cmocka_unit_test_teardown(test_g1_periodic_writer, teardown),
        cmocka_unit_test_teardown(test_g1_startup_and_shutdown_damping, teardown),
        cmocka_unit_test_teardown(test_g1_exit_is_the_hold, teardown),
        cmocka_unit_test_teardown(test_g1_hold_reaches_the_wire_first, teardown),
        cmocka_unit_test_teardown(test_g1_wire_inside_the_manifest, teardown),
        cmocka_unit_test_teardown(test_g1_joint_without_position_command, teardown),
        cmocka_unit_test_teardown(test_g1_watchdog_on_the_wire, teardown),
        cmocka_unit_test_teardown(test_g1_watchdog_event_driven, teardown),
        cmocka_unit_test_teardown(test_g1_watchdog_on_its_clock, teardown),
        cmocka_unit_test_teardown(test_g1_trip_write_trip_keeps_the_torque, teardown),
        cmocka_unit_test_teardown(test_g1_watchdog_spinning_writer, teardown),
        cmocka_unit_test_teardown(test_g1_watchdog_latches_in_the_runtime, teardown),
        cmocka_unit_test_teardown(test_g1_writer_thread, teardown),
        cmocka_unit_test(test_g1_bad_parameters),
    };
    enum { N = sizeof tests / sizeof tests[0] };
    /* cases named on the command line: those alone (test/aarch64 runs the
     * ones that prove the port under QEMU) */
    static struct CMUnitTest some[N];
    size_t n = 0;
    for (int a = 1; a < argc; a++) {
        size_t i = 0;
        while (i < N && strcmp(tests[i].name, argv[a]) != 0)
            i++;
        if (i == N) {
            fprintf(stderr, "test_unitree_g1: no case %s\n", argv[a]);
            return 2;
        }
        some[n++] = tests[i];
    }
    if (n != 0)
        return _cmocka_run_group_tests("test_unitree_g1", some, n, NULL, NULL);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
