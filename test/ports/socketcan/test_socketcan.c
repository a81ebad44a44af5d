/* SPDX-License-Identifier: Apache-2.0 */
/* The socketcan port against fake actuators (test/fakes/can) on a
 * socketpair carrying struct can_frame records, the example leg
 * (examples/can_leg/leg.toml: ids 1-3, temperature_error replies, the knee
 * turned round and offset, answering from id 0):
 *  - start-up: "enter motor mode" and nothing else before an actuator's
 *    first reply, no gains before every actuator replied, the holds at the
 *    measured position, the first command written after that a hold too;
 *  - commands reach their ids, in the actuator's frame (direction, offset),
 *    within half a step; states come back the same way;
 *  - replies to nothing (replays), frames of other ids, short, RTR, 29-bit
 *    and error frames are counted and change nothing;
 *  - an actuator that stops answering is named (fault(), STALE in the
 *    runtime), one that answers again makes read() return ROZ_ELINK once
 *    and starts over; an error code latches ROBOT naming joint and code; a
 *    frozen or jumping position is an actuator fault;
 *  - round-robin when the bus has no room for every joint each round;
 *  - shutdown: the stop's hold to each, in motor mode (never "exit motor
 *    mode", which leaves a robot limp); the torque a stop leaves never
 *    more than the controller's last command on any stop the port sends
 *    (test_socketcan_stops_keep_the_torque);
 *  - the command watchdog: the tick stops writing; with a period of 0 the
 *    writer wakes by itself and every actuator gets holds without gains at
 *    its measured position, repeatedly, and no command; read() reports it
 *    once; the next write goes out as the hold, then as written; on the
 *    runtime (periodic writer) COMMAND_TIMEOUT latches naming the silence,
 *    and a clear lets the controller drive again;
 *  - the PD controller on the runtime, periodic writer, threads throughout
 *    (label threads: ThreadSanitizer).
 * Waits are bounded and fail the test when they run out; nothing asserts a
 * time. */
/* white-box in part: a teardown reads whether the port is open (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "roz/hal/thread.h"

#include "can_leg_manifest.h"
#include "can_test_support.h"
#include "proc_threads.h"
#include "roz/hal/clock.h"
#include "roz/port/mit_codec.h"
#include "roz/runtime.h"
#include "support.h"

static roz_socketcan_t sc;
static fake_can_t bus;
static roz_test_can_t t;
static roz_runtime_t rt;
static int rt_up;

static const roz_manifest_t *const leg = &roz_manifest_can_leg;

enum { HIP, THIGH, KNEE };

/* ---- helpers ---------------------------------------------------------------- */

static roz_socketcan_counters_t counters(void)
{
    roz_socketcan_counters_t c;
    roz_socketcan_counters(&sc, &c);
    return c;
}

static roz_link_t link_now(void)
{
    roz_link_t l;
    roz_socketcan_link(&sc, &l);
    return l;
}

static fake_actuator_t actuator(unsigned j)
{
    fake_actuator_t a;
    fake_can_view(&bus, j, &a);
    return a;
}

static void open_on_write(const char *const *more)
{
    /* a timeout far above what a loaded machine takes to answer: only the
     * fake's silences count; the test's own pauses between writes are no
     * silent tick (the watchdog's cases set theirs) */
    const char *params[20] = { "command_writer_period_us", "0", "reply_timeout_us", "300000",
                               "command_timeout_us", "60000000" };
    size_t k = 6;
    for (size_t i = 0; more != NULL && more[i] != NULL && k < 18; i++)
        params[k++] = more[i];
    params[k] = NULL;
    roz_test_can_open(&t, &sc, &bus, leg, roz_test_leg_actuators, 3, 0.002, 0, params);
}

/* Rounds until every actuator has answered (auto replies). */
static void bring_up(void)
{
    while (actuator(HIP).replies == 0 || actuator(THIGH).replies == 0 ||
           actuator(KNEE).replies == 0)
        roz_test_can_round(&t);
    ROZ_WAIT_FOR(counters().replies >= 3);
}

/* A command inside the leg's limits, different for each k. */
static void command(double *cmd, int k)
{
    for (uint16_t i = 0; i < leg->n_commands; i++) {
        const roz_channel_t *ch = &leg->commands[i];
        cmd[i] = ch->min + (ch->max - ch->min) * (double)((k + 3 * i) % 11 + 1) / 12.0;
    }
}

static void write_round(const double *cmd)
{
    assert_int_equal(roz_port_write(&t.port, cmd, leg->n_commands), ROZ_OK);
    roz_test_can_settle(&t);
}

/* The step of a field of the leg's actuators. */
static double step_of(int field, unsigned j)
{
    const fake_actuator_cfg_t *c = &roz_test_leg_actuators[j];
    static const unsigned bits[5] = { 16, 12, 12, 12, 12 };
    return (c->range[field][1] - c->range[field][0]) / (double)((1u << bits[field]) - 1u);
}

static int read_leg(double *state)
{
    return roz_port_read(&t.port, state, leg->n_states);
}

/* ---- start-up ------------------------------------------------------------------ */

static void test_socketcan_start_up(void **st)
{
    double cmd[ROZ_CAN_LEG_N_COMMANDS], state[ROZ_CAN_LEG_N_STATES];
    (void)st;
    open_on_write(NULL);
    assert_int_equal(read_leg(state), ROZ_ENOENT);

    /* the knee keeps quiet: the others answer, and get holds only, however
     * the tick writes (every write is a round) */
    fake_can_mute(&bus, KNEE, 1);
    command(cmd, 1);
    for (int i = 0; i < 5; i++) {
        write_round(cmd);
        /* the hip and the thigh answer each frame; the writer knows of it
         * before the next round */
        ROZ_WAIT_FOR(counters().replies >= 2u * (uint64_t)(i + 1));
    }
    assert_int_equal(read_leg(state), ROZ_ENOENT); /* no whole state yet */
    for (unsigned j = 0; j < 3; j++) {
        fake_actuator_t a = actuator(j);
        assert_int_equal(a.before_first_reply, 0);
        assert_int_equal(a.gains_before_all, 0);
        assert_int_equal(a.commands, 0);
        assert_int_equal(a.outside_motor_mode, 0);
        assert_true(a.enters >= 1);
        assert_int_equal(bus.log[0][1], FAKE_ENTER);
    }
    assert_int_equal(actuator(KNEE).holds, 0); /* only "enter motor mode" */
    assert_true(actuator(KNEE).enters >= 5);
    assert_true(actuator(HIP).holds >= 4);

    /* the knee answers: a whole state */
    fake_can_mute(&bus, KNEE, 0);
    roz_test_can_round(&t);
    ROZ_WAIT_FOR(actuator(KNEE).replies >= 1 && counters().replies >= 3);
    ROZ_WAIT_FOR(read_leg(state) == 1);

    /* layer 3: the first command written now goes out as a hold, at the
     * measured position; the next as written */
    command(cmd, 2);
    write_round(cmd);
    for (unsigned j = 0; j < 3; j++) {
        fake_actuator_t a = actuator(j);
        assert_int_equal(a.commands, 0);
        assert_int_equal(a.code[FAKE_KP], 0);
        assert_int_equal(a.code[FAKE_KD], 0);
        /* the hold's position is the code of the last reply */
        assert_int_equal(a.code[FAKE_P], (a.last_reply[1] << 8) | a.last_reply[2]);
    }
    write_round(cmd);
    for (unsigned j = 0; j < 3; j++)
        assert_int_equal(actuator(j).commands, 1);
    assert_int_equal(counters().saturated, 0);
    roz_test_can_close(&t);
}

/* An actuator measured past its joint's limits is held at the limit: no
 * position outside the manifest goes on the bus, even with no gains. */
static void test_socketcan_hold_inside_the_limits(void **st)
{
    double cmd[ROZ_CAN_LEG_N_COMMANDS], state[ROZ_CAN_LEG_N_STATES];
    (void)st;
    open_on_write(NULL);
    /* the knee joint is -act - 1.2 rad, its limits [-2.7, -0.5]: the
     * actuator at -1.0 rad is the joint at -0.2, past -0.5; the hip at
     * 0.25 rad is inside its limits */
    fake_can_set(&bus, KNEE, -1.0, 0.0);
    fake_can_set(&bus, HIP, 0.25, 0.0);
    bring_up();
    ROZ_WAIT_FOR(read_leg(state) == 1);
    assert_true(state[ROZ_CAN_LEG_STATE_KNEE_POSITION] > -0.5);
    command(cmd, 2);
    write_round(cmd); /* the start-up hold */
    uint16_t want;
    const fake_actuator_cfg_t *kc = &roz_test_leg_actuators[KNEE];
    roz_mit_range_t r = { kc->range[FAKE_P][0], kc->range[FAKE_P][1] };
    assert_int_equal(roz_mit_codec_encode(-(-0.5 + 1.2), &r, ROZ_MIT_POSITION_BITS, &want), 0);
    fake_actuator_t knee = actuator(KNEE), hip = actuator(HIP);
    assert_int_equal(knee.commands, 0);
    assert_int_equal(knee.code[FAKE_KP], 0);
    assert_int_equal(knee.code[FAKE_P], want); /* the limit, not the measured -0.2 */
    assert_int_not_equal(want, (knee.last_reply[1] << 8) | knee.last_reply[2]);
    /* inside its limits: the measured code itself */
    assert_int_equal(hip.code[FAKE_P], (hip.last_reply[1] << 8) | hip.last_reply[2]);
    roz_test_can_close(&t);
}

/* Until the port has taken every reply the actuators sent. MIT-mode
 * replies carry no sequence: a reply the port takes after the next frame
 * went out answers that frame, and its own reply is then dropped as a replay
 * (SAFETY.md: the state lags a round), or a silence goes unseen until a
 * later frame: with one round per write, a test waits here before a round
 * whose replies it looks at. */
static void replies_taken(void)
{
    ROZ_WAIT_FOR(counters().replies + link_now().replays >=
                 actuator(HIP).replies + actuator(THIGH).replies + actuator(KNEE).replies);
}

/* Whether @p state holds what the knee and the hip answer now, each within
 * half a code step (the assertions below say which one does not). */
static int states_are_the_fakes(const double *state)
{
    fake_actuator_t knee = actuator(KNEE), hip = actuator(HIP);
    return fabs(state[ROZ_CAN_LEG_STATE_KNEE_POSITION] - (-1.0 * knee.q - 1.2)) <=
               step_of(FAKE_P, KNEE) / 2 + 1e-9 &&
           fabs(state[ROZ_CAN_LEG_STATE_KNEE_VELOCITY] + knee.dq) <= step_of(FAKE_V, KNEE) / 2 + 1e-9 &&
           fabs(state[ROZ_CAN_LEG_STATE_HIP_POSITION] - hip.q) <= step_of(FAKE_P, HIP) / 2 + 1e-9 &&
           fabs(state[ROZ_CAN_LEG_STATE_KNEE_EFFORT] + knee.tau) <= step_of(FAKE_T, KNEE) / 2 + 1e-9;
}

/* Commands reach their actuators in the actuator's frame; states come back
 * in the joint's. */
static void test_socketcan_commands_and_states(void **st)
{
    double cmd[ROZ_CAN_LEG_N_COMMANDS], state[ROZ_CAN_LEG_N_STATES];
    static const int dir[3] = { 1, 1, -1 };
    static const double offset[3] = { 0.0, 0.0, -1.2 };
    (void)st;
    open_on_write(NULL);
    bring_up();
    command(cmd, 5);
    write_round(cmd);
    for (int k = 0; k < 4; k++) {
        command(cmd, 6 + k);
        write_round(cmd);
        for (unsigned j = 0; j < 3; j++) {
            fake_actuator_t a = actuator(j);
            const double *c = &cmd[5 * j];
            assert_near(a.cmd[FAKE_P], dir[j] * (c[0] - offset[j]), step_of(FAKE_P, j) / 2 + 1e-12);
            assert_near(a.cmd[FAKE_V], dir[j] * c[1], step_of(FAKE_V, j) / 2 + 1e-12);
            assert_near(a.cmd[FAKE_KP], c[2], step_of(FAKE_KP, j) / 2 + 1e-12);
            assert_near(a.cmd[FAKE_KD], c[3], step_of(FAKE_KD, j) / 2 + 1e-12);
            assert_near(a.cmd[FAKE_T], dir[j] * c[4], step_of(FAKE_T, j) / 2 + 1e-12);
        }
    }
    /* states: the knee's actuator at +1.0 rad and 2 rad/s is the joint at
     * -1 * 1.0 + (-1.2) rad, -2 rad/s */
    replies_taken();
    fake_can_mute(&bus, HIP, 1); /* hold the physics still: set, then one reply each */
    fake_can_set(&bus, KNEE, 1.0, 2.0);
    fake_can_set(&bus, HIP, -0.25, 0.0);
    fake_can_mute(&bus, HIP, 0);
    uint64_t before = counters().replies;
    write_round(cmd);
    /* this round's replies, all three: the counter alone could be met by
     * replies of the rounds before still on their way when `before` was
     * taken, and it rises just before the frame is published */
    ROZ_WAIT_FOR(counters().replies >= before + 3 && read_leg(state) >= 0 &&
                 states_are_the_fakes(state));
    assert_near(state[ROZ_CAN_LEG_STATE_KNEE_POSITION], -1.0 * actuator(KNEE).q - 1.2,
                step_of(FAKE_P, KNEE) / 2 + 1e-9);
    assert_near(state[ROZ_CAN_LEG_STATE_KNEE_VELOCITY], -actuator(KNEE).dq,
                step_of(FAKE_V, KNEE) / 2 + 1e-9);
    assert_near(state[ROZ_CAN_LEG_STATE_HIP_POSITION], actuator(HIP).q,
                step_of(FAKE_P, HIP) / 2 + 1e-9);
    assert_near(state[ROZ_CAN_LEG_STATE_KNEE_EFFORT], -actuator(KNEE).tau,
                step_of(FAKE_T, KNEE) / 2 + 1e-9);
    assert_int_equal(counters().saturated, 0);
    assert_int_equal(counters().unknown, 0);
    roz_test_can_close(&t);
}

/* ---- what is not a reply ----------------------------------------------------------- */

static void test_socketcan_replays_and_strays(void **st)
{
    double state[ROZ_CAN_LEG_N_STATES], before[ROZ_CAN_LEG_N_STATES];
    const char *const params[] = { "command_writer_period_us", "0", "command_timeout_us",
                                   "60000000", NULL };
    uint8_t d[8] = { 1, 0x80, 0, 0x80, 0x08, 0x00, 0, 0 };
    (void)st;
    roz_test_can_open(&t, &sc, &bus, leg, roz_test_leg_actuators, 3, 0.002, 1, params);
    for (int i = 0; i < 2; i++) {
        roz_test_can_round(&t);
        assert_int_equal(fake_can_release(&bus), 3);
        ROZ_WAIT_FOR(counters().replies >= (uint64_t)(3 * (i + 1)));
    }
    assert_int_equal(read_leg(state), 1);
    memcpy(before, state, sizeof before);

    /* the hip's last reply again: nothing was sent to it since */
    assert_int_equal(fake_can_replay(&bus, HIP), 0);
    ROZ_WAIT_FOR(link_now().replays == 1);
    roz_socketcan_counters_t c0 = counters();
    /* a frame of another id; the hip's id byte from a third id; a short one
     * from the hip; a remote request; a 29-bit frame; a CRC error and a
     * bus-off reported by the controller */
    assert_int_equal(fake_can_send_raw(&bus, 0x123, d, 8), 0);
    assert_int_equal(fake_can_send_raw(&bus, 0x055, d, 8), 0);
    assert_int_equal(fake_can_send_raw(&bus, 0x001, d, 5), 0);
    assert_int_equal(fake_can_send_raw(&bus, 0x001 | 0x40000000u /* RTR */, d, 0), 0);
    assert_int_equal(fake_can_send_raw(&bus, 0x001 | 0x80000000u /* EFF */, d, 8), 0);
    uint8_t crc[8] = { 0, 0, 0x08 /* form */, 0x08 /* CRC sequence */, 0, 0, 0, 0 };
    assert_int_equal(fake_can_send_raw(&bus, 0x20000000u | 0x08u /* ERR, PROT */, crc, 8), 0);
    assert_int_equal(fake_can_send_raw(&bus, 0x20000000u | 0x40u /* ERR, BUSOFF */, crc, 8), 0);
    ROZ_WAIT_FOR(counters().frames_received >= c0.frames_received + 7);
    roz_socketcan_counters_t c = counters();
    assert_int_equal(c.unknown - c0.unknown, 4);
    assert_int_equal(c.short_frames - c0.short_frames, 1);
    assert_int_equal(c.bus_errors - c0.bus_errors, 2);
    assert_int_equal(c.bus_off - c0.bus_off, 1);
    assert_int_equal(link_now().crc_errors, 1);
    assert_int_equal(c.replies, c0.replies);
    /* none of it is a state */
    assert_int_equal(read_leg(state), 0);
    assert_memory_equal(state, before, sizeof before);

    /* a reply to the next frame is taken again; two replies to one frame
     * leave the second a replay */
    roz_test_can_round(&t);
    assert_int_equal(fake_can_release(&bus), 3);
    ROZ_WAIT_FOR(counters().replies >= c.replies + 3);
    assert_int_equal(read_leg(state), 1);
    roz_test_can_round(&t);
    roz_test_can_round(&t); /* two frames to each, one reply: one missing */
    assert_int_equal(fake_can_release(&bus), 3);
    ROZ_WAIT_FOR(counters().replies >= c.replies + 6);
    assert_int_equal(link_now().missing, 3);
    roz_test_can_close(&t);
}

/* ---- silence, return, faults -------------------------------------------------------- */


static void test_socketcan_silence_and_return(void **st)
{
    double cmd[ROZ_CAN_LEG_N_COMMANDS], state[ROZ_CAN_LEG_N_STATES];
    roz_port_fault_t f;
    (void)st;
    open_on_write(NULL); /* reply_timeout_us 300000 */
    bring_up();
    ROZ_WAIT_FOR(read_leg(state) == 1);
    command(cmd, 3);
    write_round(cmd);
    write_round(cmd);
    assert_int_equal(actuator(KNEE).commands, 1);

    replies_taken();
    fake_can_mute(&bus, KNEE, 1);
    write_round(cmd); /* the knee's frame goes unanswered ... */
    ROZ_WAIT_FOR(counters().lost >= 1); /* ... longer than the timeout */
    uint64_t before = counters().replies;
    write_round(cmd);
    ROZ_WAIT_FOR(counters().replies >= before + 2);
    assert_int_equal(read_leg(state), 0);
    assert_int_equal(roz_socketcan_ops.fault(&sc, &f), ROZ_OK);
    assert_string_equal(f.what, "knee");
    assert_string_equal(f.kind, "its actuator (CAN id 3) stopped answering (no reply in 300000 us)");
    assert_int_equal(f.code, 3);

    /* back: ROZ_ELINK once, "enter motor mode" again, the holds, then commands
     * (the round that finds it back still sends what it sent while it was
     * away: the writer learns of the return from the reply) */
    uint64_t enters = actuator(KNEE).enters;
    fake_can_mute(&bus, KNEE, 0);
    before = counters().replies;
    write_round(cmd);
    ROZ_WAIT_FOR(counters().replies >= before + 3);
    uint64_t commands = actuator(KNEE).commands;
    assert_int_equal(read_leg(state), ROZ_ELINK);
    assert_int_equal(link_now().returns, 1);
    write_round(cmd); /* "enter motor mode": it may have rebooted */
    ROZ_WAIT_FOR(counters().replies >= before + 6);
    assert_int_equal(read_leg(state), 1);
    assert_int_equal(actuator(KNEE).enters, enters + 1);
    assert_int_equal(actuator(KNEE).commands, commands);
    uint64_t hip = actuator(HIP).commands;
    write_round(cmd); /* the first command since it came back: a hold */
    assert_int_equal(actuator(KNEE).commands, commands);
    assert_int_equal(actuator(KNEE).code[FAKE_KP], 0);
    assert_int_equal(actuator(HIP).commands, hip + 1); /* the others carry on */
    command(cmd, 4);
    write_round(cmd);
    assert_int_equal(actuator(KNEE).commands, commands + 1);
    assert_true(actuator(KNEE).code[FAKE_KP] != 0);
    roz_test_can_close(&t);
}

static void test_socketcan_error_code_and_consistency(void **st)
{
    double cmd[ROZ_CAN_LEG_N_COMMANDS], state[ROZ_CAN_LEG_N_STATES];
    roz_port_fault_t f;
    (void)st;
    open_on_write(NULL);
    bring_up();
    ROZ_WAIT_FOR(read_leg(state) == 1);
    command(cmd, 1);

    /* an error code: every fresh frame while it is reported */
    fake_can_error(&bus, THIGH, 0x21);
    uint64_t before = counters().replies;
    for (int i = 0; i < 3; i++) {
        write_round(cmd);
        ROZ_WAIT_FOR(counters().replies >= before + 3 * (uint64_t)(i + 1));
        assert_int_equal(read_leg(state), ROZ_EROBOT);
        assert_int_equal(roz_socketcan_ops.fault(&sc, &f), ROZ_OK);
        assert_string_equal(f.what, "thigh");
        assert_string_equal(f.kind, "actuator error code");
        assert_int_equal(f.code, 0x21);
        assert_int_equal(read_leg(state), 0); /* nothing fresh: not reported again */
    }
    fake_can_error(&bus, THIGH, 0);
    before = counters().replies;
    write_round(cmd);
    ROZ_WAIT_FOR(counters().replies >= before + 3);
    assert_int_equal(read_leg(state), 1);

    /* frozen: the hip's replies repeat while they say it moves at 3 rad/s */
    fake_can_set(&bus, HIP, 0.2, 3.0);
    before = counters().replies;
    write_round(cmd);
    ROZ_WAIT_FOR(counters().replies >= before + 3);
    (void)read_leg(state);
    fake_can_freeze(&bus, HIP, 1);
    int rc = 0;
    for (int i = 0; i < 200 && rc != ROZ_EROBOT; i++) {
        before = counters().replies;
        write_round(cmd);
        ROZ_WAIT_FOR(counters().replies >= before + 3);
        rc = read_leg(state);
    }
    assert_int_equal(rc, ROZ_EROBOT);
    assert_int_equal(roz_socketcan_ops.fault(&sc, &f), ROZ_OK);
    assert_string_equal(f.what, "hip");
    assert_non_null(strstr(f.kind, "position does not follow velocity (CAN id 1)"));
    /* thawed, the hip's position catches up with where it went: a jump too */
    fake_can_freeze(&bus, HIP, 0);
    fake_can_set(&bus, HIP, 0.2, 0.0);
    for (int i = 0; i < 3; i++) {
        before = counters().replies;
        write_round(cmd);
        ROZ_WAIT_FOR(counters().replies >= before + 3);
        (void)read_leg(state);
    }
    assert_int_equal(read_leg(state), 0);

    /* a jump: the knee's position moves 0.5 rad between two replies */
    uint64_t inconsistent = counters().inconsistent;
    fake_can_jump(&bus, KNEE, 0.5);
    before = counters().replies;
    write_round(cmd);
    ROZ_WAIT_FOR(counters().replies >= before + 3);
    assert_int_equal(read_leg(state), ROZ_EROBOT);
    assert_int_equal(roz_socketcan_ops.fault(&sc, &f), ROZ_OK);
    assert_string_equal(f.what, "knee");
    assert_int_equal(counters().inconsistent, inconsistent + 1);
    roz_test_can_close(&t);
}

/* ---- the bus -------------------------------------------------------------------------- */

/* Six effort joints at 125 kbit/s, a round of 5 ms (200 Hz, period 0): 500
 * bits a round at 80 %, 250 a joint (6-byte replies): two joints a round,
 * three groups, every joint every 15 ms. */
static roz_channel_t six_commands[6];
static char six_names[6][2][16];
static const char *six_joints[6];
static roz_hardware_t six_hw;
static roz_manifest_t six;
static const roz_param_t six_params[] = {
    { "can_id", "j0=0x10, j1=0x11, j2=0x12, j3=0x13, j4=0x14, j5=0x15" },
    { "reply", "basic" }, { "position_range", "-12.5:12.5" }, { "velocity_range", "-45:45" },
    { "stiffness_range", "0:500" }, { "damping_range", "0:5" }, { "effort_range", "-18:18" },
    { "bitrate", "125000" }, { "command_writer_period_us", "0" },
};

static void test_socketcan_round_robin(void **st)
{
    fake_actuator_cfg_t acts[6];
    roz_socketcan_info_t info;
    (void)st;
    for (unsigned j = 0; j < 6; j++) {
        snprintf(six_names[j][0], sizeof six_names[j][0], "j%u", j);
        snprintf(six_names[j][1], sizeof six_names[j][1], "j%u/effort", j);
        six_joints[j] = six_names[j][0];
        six_commands[j] = (roz_channel_t){ .name = six_names[j][1], .type = ROZ_IF_EFFORT,
                                           .unit = "N.m", .min = -1.0, .max = 1.0,
                                           .position_state = ROZ_CHANNEL_UNPAIRED };
        acts[j] = (fake_actuator_cfg_t){ (uint16_t)(0x10 + j), (uint16_t)(0x10 + j), FAKE_BASIC,
                                         { { -12.5, 12.5 }, { -45, 45 }, { 0, 500 }, { 0, 5 },
                                           { -18, 18 } } };
    }
    six_hw = (roz_hardware_t){ "socketcan", six_joints, 6, six_params,
                               sizeof six_params / sizeof six_params[0] };
    six = (roz_manifest_t){ "six", "arm", 200, six_commands, 6, NULL, 0, &six_hw, NULL, 0, 0, NULL, NULL };
    roz_test_can_open(&t, &sc, &bus, &six, acts, 6, 0.005, 0, NULL);
    roz_socketcan_info(&sc, &info);
    assert_int_equal(info.groups, 3);
    assert_int_equal(info.round_us, 5000);
    assert_int_equal(info.joint_interval_us, 15000);
    assert_true(fabs(info.bus_load - 0.8) < 1e-12);
    assert_string_equal(info.network_interface, "");

    for (int r = 0; r < 9; r++) {
        roz_test_can_round(&t);
        /* round r went to joints r mod 3 and r mod 3 + 3 */
        for (unsigned j = 0; j < 6; j++) {
            int g = (int)(j % 3), want = r >= g ? (r - g) / 3 + 1 : 0;
            assert_int_equal(actuator(j).frames, want);
        }
    }
    for (unsigned j = 0; j < 6; j++)
        assert_int_equal(actuator(j).frames, 3);
    roz_test_can_close(&t);
}

/* ---- the device: what a consumer learns without knowing the port ---------------------- */

/* rozrun prints the port's lines and its link from the port's own ops
 * (roz_port_report(), roz_port_link_counters()); no other test runs rozrun
 * on a bus, so this checks them against the port's own functions. */
static void test_socketcan_device(void **st)
{
    double cmd[ROZ_CAN_LEG_N_COMMANDS];
    static char text[2048];
    char want[128];
    roz_socketcan_info_t info;
    roz_port_link_counters_t pc;
    roz_link_t before;
    (void)st;
    open_on_write(NULL);
    uint32_t caps = roz_port_caps(&t.port);
    assert_true(caps & ROZ_PORT_CAP_CRC);
    assert_true(caps & ROZ_PORT_CAP_WATCHDOG);
    assert_true(caps & ROZ_PORT_CAP_START_HOLD);
    assert_true(caps & ROZ_PORT_CAP_ROBOT);
    assert_false(caps & ROZ_PORT_CAP_SEQUENCE);
    assert_false(caps & ROZ_PORT_CAP_SIMULATOR);
    const roz_port_info_t *pi = roz_port_info(&t.port);
    assert_non_null(pi->no_sequence);
    assert_null(pi->no_crc);
    int keys = 0;
    for (size_t i = 0; i < pi->n_params; i++)
        keys += !strcmp(pi->params[i].key, "can_id") || !strcmp(pi->params[i].key, "bitrate");
    assert_int_equal(keys, 2);

    bring_up();
    command(cmd, 1);
    write_round(cmd);
    roz_socketcan_info(&sc, &info);
    int n = roz_port_report(&t.port, ROZ_PORT_REPORT_OPENED, text, sizeof text);
    assert_true(n > 0 && (size_t)n < sizeof text);
    snprintf(want, sizeof want, "socketcan: %u actuators on %s at %u kbit/s; ",
             (unsigned)info.n_joints, info.network_interface, (unsigned)(info.bitrate / 1000u));
    assert_int_equal(strncmp(text, want, strlen(want)), 0);
    assert_null(strchr(text, '\n'));
    n = roz_port_report(&t.port, ROZ_PORT_REPORT_SUMMARY, text, sizeof text);
    assert_true(n > 0 && (size_t)n < sizeof text);
    assert_int_equal(strncmp(text, "CAN bus                ", 23), 0);
    snprintf(want, sizeof want, "; %llu frames sent (", (unsigned long long)counters().frames_sent);
    assert_non_null(strstr(text, want));
    assert_non_null(strstr(text, " fields saturated"));
    assert_non_null(strstr(text, "\nCAN replies            "));
    /* a text that does not fit is cut and terminated; the length it needs */
    assert_int_equal(roz_port_report(&t.port, ROZ_PORT_REPORT_SUMMARY, want, 8), n);
    assert_int_equal(strlen(want), 7);

    roz_socketcan_link(&sc, &before);
    assert_int_equal(roz_port_link_counters(&t.port, &pc), ROZ_OK);
    assert_true(pc.accepted >= before.accepted && pc.accepted > 0);
    assert_int_equal(pc.malformed, 0);
    assert_int_equal(pc.restarts, before.restarts);
    roz_test_can_close(&t);
}

/* ---- shutdown ------------------------------------------------------------------------- */

static int last_is_hold(unsigned j, uint32_t p_code);

static void test_socketcan_shutdown(void **st)
{
    double cmd[ROZ_CAN_LEG_N_COMMANDS];
    (void)st;
    open_on_write(NULL);
    bring_up();
    command(cmd, 7);
    write_round(cmd);
    write_round(cmd);
    (void)roz_port_deactivate(&t.port);
    ROZ_WAIT_FOR(fake_can_received(&bus) >= counters().frames_sent);
    for (unsigned j = 0; j < 3; j++) {
        fake_actuator_t a = actuator(j);
        unsigned last = 0;
        for (unsigned i = 0; i < bus.n_log; i++) {
            if (bus.log[i][0] == (char)('0' + j))
                last = i;
        }
        /* the exit is the stop: the leg's, damping (its hold stiffness is
         * 0) at the measured position, in motor mode (it was a hold
         * without gains and "exit motor mode": limp) */
        assert_int_equal(bus.log[last][1], FAKE_HOLD);
        assert_true(last_is_hold(j, UINT32_MAX)); /* at the position measured with the
                                                     last command: no rate cap, no band */
        assert_int_equal(a.motor_mode, 1);
        assert_int_equal(a.exits, 0);
        assert_int_equal(a.zeros, 0); /* the port never sets zero */
    }
    assert_int_equal(counters().exit_sent, 0);
    roz_test_can_close(&t);
}

/* ---- opening ---------------------------------------------------------------------------- */

/* Both threads carry the scheduling their parameters ask for: affinity and
 * stack size always, SCHED_FIFO where permitted (roz/hal/thread.h); read
 * back from the running threads. */
static void test_socketcan_threads(void **st)
{
    roz_thread_config_t rx, tx;
    char cpus[8];
    int may_fifo;
    (void)st;
    int cpu = roz_test_thread_probe(7, cpus, sizeof cpus, &may_fifo);
    if (!may_fifo)
        print_message("SCHED_FIFO not permitted here: the threads' affinity and stack only\n");
    const char *more[] = { "receive_thread_cpus", cpus, "receive_thread_stack_kib", "256",
                           "command_writer_stack_kib", "512",
                           may_fifo ? "command_writer_sched" : NULL, "fifo",
                           "command_writer_priority", "7", NULL };
    open_on_write(more);
    bring_up(); /* frames flow both ways */
    assert_int_equal(roz_thread_describe(sc.rx_thread, &rx), ROZ_OK);
    assert_int_equal(roz_thread_describe(sc.tx_thread, &tx), ROZ_OK);
    assert_int_equal(rx.cpus, 1ull << cpu);
    assert_int_equal(rx.stack_kib, 256);
    assert_int_equal(rx.sched, ROZ_THREAD_OTHER);
    assert_int_equal(tx.stack_kib, 512);
    assert_int_equal(tx.sched, may_fifo ? ROZ_THREAD_FIFO : ROZ_THREAD_OTHER);
    assert_int_equal(tx.priority, may_fifo ? 7 : 0);
}

static void test_socketcan_open_errors(void **st)
{
    roz_port_t p;
    char err[300];
    roz_param_t item;
    roz_params_t params = { &item, 1 };
    double x[ROZ_CAN_LEG_N_COMMANDS] = { 0 };
    (void)st;

    item = (roz_param_t){ "can_id", "hip=1, thigh=2, knee=2048" };
    p = roz_socketcan_port(&sc, NULL, NULL);
    assert_int_equal(roz_port_open(&p, leg, &params, err, sizeof err), ROZ_EINVAL);
    assert_string_equal(err, "socketcan: hardware.params: can_id \"knee=2048\": expected an "
                             "actuator's CAN id, 1..2047 (11 bits; decimal or 0x hex)");
    assert_int_equal(p.opened, 0);

    item = (roz_param_t){ "network_interface", "nosuchcan7" };
    p = roz_socketcan_port(&sc, NULL, NULL);
    assert_int_equal(roz_port_open(&p, leg, &params, err, sizeof err), ROZ_ENOENT);
    assert_non_null(strstr(err, "socketcan: network_interface \"nosuchcan7\": no such interface"));


    /* sizes */
    open_on_write(NULL);
    assert_int_equal(roz_port_read(&t.port, x, (size_t)leg->n_states + 1), ROZ_EINVAL);
    assert_int_equal(roz_port_write(&t.port, x, (size_t)leg->n_commands - 1), ROZ_EINVAL);
    roz_test_can_close(&t);
}

/* ---- the PD controller on the runtime, the periodic writer ------------------------------- */

static void tick_for(int n)
{
    for (int i = 0; i < n; i++) {
        int rc = roz_runtime_tick(&rt); /* a latched fault is looked at by the caller */
        (void)rc;
        struct timespec ts = { 0, 2000000 };
        nanosleep(&ts, NULL);
    }
}

static void runtime_up_with(const char *command_timeout_us)
{
    roz_runtime_config_t cfg;
    size_t len;
    const uint8_t *w = roz_test_controller("leg_pd", &len);
    const char *const params[] = { "command_writer_period_us", "2000", "reply_timeout_us",
                                   "100000", "command_timeout_us", command_timeout_us, NULL };
    roz_test_can_open(&t, &sc, &bus, leg, roz_test_leg_actuators, 3, 0.002, 0, params);
    roz_runtime_config_default(&cfg);
    cfg.manifest = leg;
    cfg.port = t.port;
    cfg.clock = roz_clock_monotonic_ns;
    cfg.budget_ns = ROZ_BUDGET_OFF; /* fuel alone: sanitizer builds are slow */
    cfg.stale_ticks = 50;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    rt_up = 1;
}

/* generous timeouts: the threads of a loaded machine are no silent actuator,
 * and no silent tick */
static void runtime_up(void)
{
    runtime_up_with("60000000");
}

static void runtime_down(void)
{
    roz_test_can_close(&t);
    roz_runtime_deinit(&rt);
    rt_up = 0;
}

static void test_socketcan_pd_on_the_runtime(void **st)
{
    (void)st;
    runtime_up();
    tick_for(750); /* 1.5 s: the gains are in, the leg squats */
    assert_int_equal(roz_runtime_faults(&rt), 0);
    /* the actuators got what the filter applied, in their own frames */
    const double *applied = roz_runtime_last_commands(&rt);
    for (unsigned j = 0; j < 3; j++) {
        fake_actuator_t a = actuator(j);
        assert_near(a.cmd[FAKE_KP], applied[5 * j + 2], 0.5); /* one tick apart at most */
        assert_true(a.commands > 100);
        assert_int_equal(a.gains_before_all, 0);
    }
    /* the knee followed its target (its own PD in the fake): within 0.2 rad */
    const double *s = roz_runtime_last_state(&rt);
    assert_near(s[ROZ_CAN_LEG_STATE_KNEE_POSITION], applied[ROZ_CAN_LEG_CMD_KNEE_POSITION], 0.2);
    /* each round: one frame to each actuator, then the exit's hold to
     * each, nothing else */
    assert_int_equal(roz_port_deactivate(&t.port), ROZ_OK);
    roz_socketcan_counters_t c = counters();
    assert_true(c.commands_sent > 0);
    assert_int_equal(c.saturated, 0);
    assert_int_equal(c.unknown, 0);
    assert_int_equal(c.inconsistent, 0);
    assert_int_equal(c.frames_sent + c.send_errors, 3 * c.rounds + 3);
    runtime_down();
}

static void test_socketcan_silent_actuator_latches_stale(void **st)
{
    char msg[ROZ_CFG_ERROR_LEN];
    (void)st;
    runtime_up();
    tick_for(100);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    fake_can_mute(&bus, KNEE, 1);
    for (int i = 0; i < 2000 && !(roz_runtime_faults(&rt) & ROZ_FAULT_STALE); i++)
        tick_for(1);
    assert_true(roz_runtime_faults(&rt) & ROZ_FAULT_STALE);
    roz_runtime_fault_message_copy(&rt, msg, sizeof msg);
    assert_non_null(strstr(msg, "no fresh state for 50 ticks: knee: its actuator (CAN id 3) "
                                "stopped answering"));
    runtime_down();
}

static void test_socketcan_error_code_latches_robot(void **st)
{
    char msg[ROZ_CFG_ERROR_LEN];
    (void)st;
    runtime_up();
    tick_for(100);
    fake_can_error(&bus, THIGH, 0x21);
    for (int i = 0; i < 2000 && !(roz_runtime_faults(&rt) & ROZ_FAULT_ROBOT); i++)
        tick_for(1);
    assert_true(roz_runtime_faults(&rt) & ROZ_FAULT_ROBOT);
    roz_runtime_fault_message_copy(&rt, msg, sizeof msg);
    assert_string_equal(msg, "robot fault: thigh: actuator error code 33 (0x21)");
    runtime_down();
}

/* ---- the command watchdog --------------------------------------------------------- */

/* The leg's hold damping: its damping channels' default (0.5 N.m.s/rad,
 * the same for every joint of the leg). */
static double hold_damping(void)
{
    for (uint16_t i = 0; i < leg->n_commands; i++) {
        if (leg->commands[i].type == ROZ_IF_DAMPING)
            return leg->commands[i].default_value;
    }
    fail_msg("the leg has no damping command");
    return 0.0;
}

/* Whether actuator j's last frame was a hold: no stiffness (the leg's hold
 * stiffness, its stiffness channels' default, is 0), the hold damping, no
 * velocity, no torque; at position code @p p_code (UINT32_MAX: not
 * compared). The leg's position commands have no rate cap, so its holds
 * have no band (roz_hold_band()): the position measured with the last
 * command, which the fake actuators do not report here. */
static int last_is_hold(unsigned j, uint32_t p_code)
{
    fake_actuator_t a = actuator(j);
    uint32_t p = a.code[FAKE_P];
    return a.code[FAKE_KP] == 0 &&
           fabs(a.cmd[FAKE_KD] - hold_damping()) <= step_of(FAKE_KD, j) / 2 + 1e-12 &&
           fabs(a.cmd[FAKE_V]) <= step_of(FAKE_V, j) / 2 + 1e-12 &&
           fabs(a.cmd[FAKE_T]) <= step_of(FAKE_T, j) / 2 + 1e-12 &&
           (p_code == UINT32_MAX || (p + 1u >= p_code && p <= p_code + 1u));
}

static void test_socketcan_watchdog_on_write(void **st)
{
    double cmd[ROZ_CAN_LEG_N_COMMANDS], state[ROZ_CAN_LEG_N_STATES];
    uint64_t commands[3], holds[3];
    roz_port_fault_t f;
    (void)st;
    /* a round per write: once the tick stops, nothing wakes the writer but
     * the watchdog (100 ms: the test's own steps on a loaded machine are
     * no silence) */
    const char *const more[] = { "command_timeout_us", "100000", NULL };
    open_on_write(more);
    bring_up();
    ROZ_WAIT_FOR(read_leg(state) == 1);
    command(cmd, 1);
    write_round(cmd); /* the start-up hold */
    command(cmd, 2);
    write_round(cmd);
    for (unsigned j = 0; j < 3; j++) {
        commands[j] = actuator(j).commands;
        assert_int_equal(commands[j], 1);
        assert_true(actuator(j).code[FAKE_KP] != 0);
    }
    assert_int_equal(counters().command_timeouts, 0);

    /* the tick stops: the writer holds every actuator by itself, again and
     * again, at the hold gains (damping, kd 0.5: not limp), and sends no
     * command */
    ROZ_WAIT_FOR(counters().command_timeouts == 1);
    for (unsigned j = 0; j < 3; j++)
        holds[j] = actuator(j).holds;
    ROZ_WAIT_FOR(actuator(HIP).holds >= holds[HIP] + 3 && actuator(THIGH).holds >= holds[THIGH] + 3 &&
                 actuator(KNEE).holds >= holds[KNEE] + 3);
    for (unsigned j = 0; j < 3; j++) {
        assert_int_equal(actuator(j).commands, commands[j]); /* one round per write, no more */
        assert_true(last_is_hold(j, UINT32_MAX));
    }
    assert_true(counters().watchdog_holds >= 9);
    assert_int_equal(counters().command_timeouts, 1);

    /* the tick is back: read() reports once, naming the silence */
    assert_int_equal(read_leg(state), ROZ_EWATCHDOG);
    assert_int_equal(roz_socketcan_ops.fault(&sc, &f), ROZ_OK);
    assert_string_equal(f.what, "command_timeout_us");
    assert_int_equal(f.limit, 100000);
    assert_true(f.code >= 100000);
    assert_true(read_leg(state) >= 0);
    /* the first write goes out as the hold (the damping kept: no frame of
     * kd 0 between the watchdog's and the tick's), the next as written */
    command(cmd, 3);
    write_round(cmd);
    for (unsigned j = 0; j < 3; j++) {
        assert_int_equal(actuator(j).commands, commands[j]);
        assert_true(last_is_hold(j, UINT32_MAX));
    }
    write_round(cmd);
    for (unsigned j = 0; j < 3; j++) {
        assert_int_equal(actuator(j).commands, commands[j] + 1u);
        assert_true(actuator(j).code[FAKE_KP] != 0);
    }
    assert_int_equal(counters().command_timeouts, 1);
    roz_test_can_close(&t);
}

static void test_socketcan_watchdog_latches_on_the_runtime(void **st)
{
    char msg[ROZ_CFG_ERROR_LEN];
    unsigned long silent = 0, limit = 0;
    (void)st;
    runtime_up_with("100000"); /* the periodic writer, 100 ms */
    tick_for(100);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    uint64_t commands = actuator(KNEE).commands;
    assert_true(commands > 0);

    /* the tick stops */
    ROZ_WAIT_FOR(counters().command_timeouts == 1);
    uint64_t holds = actuator(KNEE).holds;
    ROZ_WAIT_FOR(actuator(KNEE).holds >= holds + 5); /* every period, by itself */
    assert_true(last_is_hold(KNEE, UINT32_MAX)); /* the stand's last position: not known here */
    uint64_t at_trip = actuator(KNEE).commands;
    tick_for(1);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_COMMAND_TIMEOUT);
    roz_runtime_fault_message_copy(&rt, msg, sizeof msg);
    const char *at = strstr(msg, "the tick wrote no command for ");
    if (at == NULL || sscanf(at, "the tick wrote no command for %lu us, longer than the port's "
                                 "command_timeout_us (%lu)",
                             &silent, &limit) != 2)
        fail_msg("the fault names neither the silence nor the timeout: \"%s\"", msg);
    assert_int_equal(limit, 100000);
    assert_true(silent >= 100000);
    /* latched (an immediate stop) until cleared; then the controller again */
    tick_for(20);
    assert_int_equal(roz_runtime_faults(&rt), ROZ_FAULT_COMMAND_TIMEOUT);
    assert_int_equal(roz_runtime_clear_faults(&rt), ROZ_OK);
    tick_for(50);
    assert_int_equal(roz_runtime_faults(&rt), 0);
    ROZ_WAIT_FOR(actuator(KNEE).commands > at_trip);
    assert_int_equal(counters().command_timeouts, 1);
    runtime_down();
}

/* A test that failed half-way leaves things open: close them. */
/* ---- the property on the CAN path ---------------------------------------------- */

/* The torque a stop leaves on a joint never exceeds what the controller
 * last commanded (roz/hold.h), on every stop the port sends by itself: the
 * watchdog's hold, the hold after a trip (back for one write, stalled
 * again), the exit; over random hold gains, measured positions, setpoints,
 * gains and stop kinds; through the real port (its writer thread, its
 * shutdown) to the fake actuators, as they decode the frames. The leg's own
 * hold stiffness is 0 (damping): here its stiffness channels' default, the
 * hold gain, is random, and its position commands are capped at 0.1 rad a
 * tick (the band: 0.5 rad). test/core/test_hold.c holds the same property
 * for the filter and the DDS ports' hold. */

static roz_channel_t prop_cmds[ROZ_CFG_MAX_COMMANDS];
static roz_manifest_t prop_leg;
static uint64_t prop_rng = 0x2545f4914f6cdd1dull;

static double prop_uniform(double lo, double hi)
{
    return roz_test_uniform(&prop_rng, lo, hi);
}

/* Actuator j's last frame is the stop's hold against the command @p c (as
 * the actuator decoded it) about position @p p (the actuator's frame): kp
 * the hold gain, the hold damping, no velocity, no torque; no more torque
 * about p than the command, the setpoint on its side within max(|sp - p|,
 * band). Quantisation (the reply, the command and the hold each within half
 * a step of the port's doubles) is the only tolerance. */
static void check_stop(const char *path, int n, unsigned j, const double *c, double p,
                       double kp_hold, double band)
{
    fake_actuator_t a = actuator(j);
    double dp = step_of(FAKE_P, j), dk = step_of(FAKE_KP, j);
    double sp = c[FAKE_P], kp_c = c[FAKE_KP], q = a.cmd[FAKE_P], kp = a.cmd[FAKE_KP];
    double torque_c = fabs(kp_c * (sp - p)), torque = fabs(kp * (q - p));
    double tol = dk * (fabs(q - p) + fabs(sp - p) + 2.0 * dp) + (kp + kp_c + dk) * 2.0 * dp + 1e-9;
    if (torque > torque_c + tol)
        fail_msg("case %d, %s, actuator %u: the stop's torque %.6g N*m (kp %.6g at %.6g) exceeds "
                 "the controller's %.6g N*m (kp %.6g at %.6g), position %.6g",
                 n, path, j, torque, kp, q, torque_c, kp_c, sp, p);
    if (fabs(q - p) > fmax(fabs(sp - p), band) + 2.0 * dp ||
        ((q - p) * (sp - p) < 0.0 && fabs(q - p) > 2.0 * dp))
        fail_msg("case %d, %s, actuator %u: setpoint %.6g past the controller's %.6g by more "
                 "than the band %.6g around the position %.6g", n, path, j, q, sp, band, p);
    if (!(fabs(kp - kp_hold) <= dk / 2 + 1e-9 &&
          fabs(a.cmd[FAKE_KD] - hold_damping()) <= step_of(FAKE_KD, j) / 2 + 1e-9 &&
          fabs(a.cmd[FAKE_V]) <= step_of(FAKE_V, j) / 2 + 1e-9 &&
          fabs(a.cmd[FAKE_T]) <= step_of(FAKE_T, j) / 2 + 1e-9 && a.motor_mode == 1))
        fail_msg("case %d, %s, actuator %u: not the stop's hold: kp %.6g (hold %.6g), kd %.6g, "
                 "v %.6g, t %.6g, motor mode %d", n, path, j, kp, kp_hold, a.cmd[FAKE_KD],
                 a.cmd[FAKE_V], a.cmd[FAKE_T], a.motor_mode);
}

/* A controller's command: each joint to a random setpoint near or far from
 * where it is, a random stiffness (some at the limit, some 0), the rest
 * random inside the channels. */
static void random_command(const double *p_joint, double *cmd)
{
    for (uint16_t i = 0; i < prop_leg.n_commands; i++) {
        const roz_channel_t *ch = &prop_leg.commands[i];
        cmd[i] = prop_uniform(ch->min, ch->max);
        if (ch->type == ROZ_IF_STIFFNESS) {
            double r = prop_uniform(0.0, 1.0);
            cmd[i] = r < 0.2 ? ch->max : r < 0.3 ? 0.0 : cmd[i];
        }
        if (ch->type == ROZ_IF_POSITION) {
            double reach = prop_uniform(0.0, 1.0) < 0.5 ? 0.05 : 1.0;
            double v = p_joint[i / 5u] + prop_uniform(-reach, reach);
            cmd[i] = v < ch->min ? ch->min : v > ch->max ? ch->max : v;
        }
    }
}

static void test_socketcan_stops_keep_the_torque(void **st)
{
    double cmd[ROZ_CAN_LEG_N_COMMANDS], state[ROZ_CAN_LEG_N_STATES];
    double sent[3][FAKE_FIELDS], p_act[3], p_joint[3];
    static const char *const paths[3] = { "the watchdog's hold", "the hold after a trip",
                                          "the exit" };
    (void)st;
    for (int n = 0; n < 12; n++) {
        int kind = n % 3;
        double kp_hold = n % 4 == 0 ? 60.0 : prop_uniform(0.0, 60.0);
        prop_leg = *leg;
        memcpy(prop_cmds, leg->commands, leg->n_commands * sizeof prop_cmds[0]);
        for (uint16_t i = 0; i < leg->n_commands; i++) {
            if (prop_cmds[i].type == ROZ_IF_STIFFNESS)
                prop_cmds[i].default_value = kp_hold;
            if (prop_cmds[i].type == ROZ_IF_POSITION)
                prop_cmds[i].max_rate = 0.1;
        }
        prop_leg.commands = prop_cmds;
        double band = 5.0 * 0.1;
        /* the joints do not move (dt 0): each stays where it is set */
        const char *params[] = { "command_writer_period_us", "0", "reply_timeout_us", "300000",
                                 "command_timeout_us", "200000", NULL };
        roz_test_can_open(&t, &sc, &bus, &prop_leg, roz_test_leg_actuators, 3, 0.0, 0, params);
        for (unsigned j = 0; j < 3; j++) {
            const roz_can_joint_t *jt = &sc.cfg.joints[j];
            const roz_channel_t *pc = &prop_leg.commands[jt->pos_cmd];
            p_joint[j] = prop_uniform(pc->min, pc->max);
            p_act[j] = (double)jt->direction * (p_joint[j] - jt->zero_offset);
            fake_can_set(&bus, j, p_act[j], 0.0);
        }
        bring_up();
        ROZ_WAIT_FOR(read_leg(state) == 1);
        random_command(p_joint, cmd);
        write_round(cmd); /* the start-up hold */
        uint64_t commands = counters().commands_sent;
        random_command(p_joint, cmd);
        write_round(cmd);
        /* a machine so loaded that the watchdog tripped in between: the
         * command went out as a hold; the case says nothing, try the next */
        if (counters().commands_sent != commands + 3u || counters().command_timeouts != 0) {
            print_message("case %d: the watchdog tripped before the command went out\n", n);
            roz_test_can_close(&t);
            continue;
        }
        for (unsigned j = 0; j < 3; j++) {
            fake_actuator_t a = actuator(j);
            memcpy(sent[j], a.cmd, sizeof sent[j]);
            p_act[j] = a.q;
        }
        if (kind < 2) {
            /* the tick stops: the watchdog's hold, every round */
            ROZ_WAIT_FOR(counters().command_timeouts == 1);
            uint64_t holds = counters().watchdog_holds;
            ROZ_WAIT_FOR(counters().watchdog_holds >= holds + 3u &&
                         fake_can_received(&bus) >= counters().frames_sent);
            for (unsigned j = 0; j < 3; j++)
                check_stop(paths[0], n, j, sent[j], p_act[j], kp_hold, band);
        }
        if (kind == 1) {
            /* back for one write: it goes out as the stop's hold from the
             * controller's last command that went out */
            assert_int_equal(read_leg(state), ROZ_EWATCHDOG);
            random_command(p_joint, cmd);
            write_round(cmd);
            for (unsigned j = 0; j < 3; j++)
                check_stop(paths[1], n, j, sent[j], p_act[j], kp_hold, band);
            /* and stalls again: the second trip holds that command's torque */
            ROZ_WAIT_FOR(counters().command_timeouts == 2);
            uint64_t holds = counters().watchdog_holds;
            ROZ_WAIT_FOR(counters().watchdog_holds >= holds + 3u &&
                         fake_can_received(&bus) >= counters().frames_sent);
            for (unsigned j = 0; j < 3; j++)
                check_stop(paths[0], n, j, sent[j], p_act[j], kp_hold, band);
        }
        /* every case ends in the exit: the stop's hold again */
        (void)roz_port_deactivate(&t.port);
        ROZ_WAIT_FOR(fake_can_received(&bus) >= counters().frames_sent);
        for (unsigned j = 0; j < 3; j++)
            check_stop(paths[2], n, j, sent[j], p_act[j], kp_hold, band);
        assert_int_equal(counters().saturated, 0);
        roz_test_can_close(&t);
    }
}

static int teardown(void **st)
{
    (void)st;
    if (t.sc != NULL && t.sc->opened)
        roz_test_can_close(&t);
    else if (bus.running)
        fake_can_stop(&bus);
    if (rt_up) {
        roz_runtime_deinit(&rt);
        rt_up = 0;
    }
    memset(&t, 0, sizeof t);
    return 0;
}

ROZ_TEST_MAIN(cmocka_unit_test_teardown(test_socketcan_start_up, teardown),
              cmocka_unit_test_teardown(test_socketcan_hold_inside_the_limits, teardown),
              cmocka_unit_test_teardown(test_socketcan_commands_and_states, teardown),
              cmocka_unit_test_teardown(test_socketcan_replays_and_strays, teardown),
              cmocka_unit_test_teardown(test_socketcan_silence_and_return, teardown),
              cmocka_unit_test_teardown(test_socketcan_error_code_and_consistency, teardown),
              cmocka_unit_test_teardown(test_socketcan_round_robin, teardown),
              cmocka_unit_test_teardown(test_socketcan_device, teardown),
              cmocka_unit_test_teardown(test_socketcan_shutdown, teardown),
              cmocka_unit_test_teardown(test_socketcan_threads, teardown),
              cmocka_unit_test_teardown(test_socketcan_open_errors, teardown),
              cmocka_unit_test_teardown(test_socketcan_pd_on_the_runtime, teardown),
              cmocka_unit_test_teardown(test_socketcan_silent_actuator_latches_stale, teardown),
              cmocka_unit_test_teardown(test_socketcan_error_code_latches_robot, teardown),
              cmocka_unit_test_teardown(test_socketcan_watchdog_on_write, teardown),
              cmocka_unit_test_teardown(test_socketcan_watchdog_latches_on_the_runtime, teardown),
              cmocka_unit_test_teardown(test_socketcan_stops_keep_the_torque, teardown))
