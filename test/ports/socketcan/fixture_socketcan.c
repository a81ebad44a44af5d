/* SPDX-License-Identifier: Apache-2.0 */
/* The socketcan port's conformance fixture: the example leg
 * (examples/can_leg/leg.toml) against fake MIT-mode actuators
 * (test/fakes/can) on a socketpair, a round per write
 * (command_writer_period_us = 0) and replies only when the fixture lets
 * them go, so that every call is one step of the suite.
 *
 * The peer is the three actuators. What the suite's frames are on a CAN
 * bus, where MIT-mode frames carry no CRC and no sequence number of their
 * own:
 *  - SEND: a round ("enter motor mode", a hold or a command to each) and
 *    one reply from each;
 *  - CORRUPT: what a damaged frame leaves of itself: the CAN controller
 *    refused it on its hardware CRC and reports an error frame, which the
 *    port counts as a CRC error; the frame never reaches the port;
 *  - REPLAY: the hip's last reply again while no frame to it is unanswered
 *    (a frame the bus delivered twice, a stuck gateway): the port's
 *    "sequence" is the frames it sent, a reply answers one of them;
 *  - RESTART: not expressible (no_sequence says so): an actuator that reboots
 *    comes back out of motor mode and says so nowhere; the port sees a
 *    restart only as a silence, VANISH; one shorter than reply_timeout_us
 *    goes unseen (a position jump aside, which the port's consistency check
 *    catches);
 *  - VANISH: the hip does not answer for longer than reply_timeout_us (the
 *    fixture's: 0.3 s, far above what a loaded machine takes to answer), then
 *    does: one actuator is one peer (link.returns counts actuators);
 *  - a command frame corrupted in transit: every actuator's controller
 *    refuses the next frame (its CRC); on a bus the sender would send it
 *    again, here nothing does, and each actuator keeps its last command.
 * A stuck actuator that still answers with its last values cannot be told
 * from a resting one by any of this; the port's check that position
 * follows velocity is tested in test/ports/socketcan/test_socketcan.c. */
/* white-box: the fake bus answers as the port's own joint table says (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#define _POSIX_C_SOURCE 200809L /* socketpair */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmocka.h>

#include "can_leg_manifest.h"
#include "can_test_support.h"
#include "port_fixture.h"
#include "roz/port/mit_codec.h"

static roz_socketcan_t sc;
static fake_can_t bus;
static roz_test_can_t t;
static double applied[ROZ_CFG_MAX_COMMANDS];

#define N_ACT 3

static roz_socketcan_counters_t counters(void)
{
    roz_socketcan_counters_t c;
    roz_socketcan_counters(&sc, &c);
    return c;
}

static roz_link_t link_copy(void)
{
    roz_link_t l;
    roz_socketcan_link(&sc, &l);
    return l;
}

static void sc_fx_close(void);

static int sc_fx_open(const roz_manifest_t *m, const roz_params_t *params, roz_port_t *port,
                      char *err, size_t errlen)
{
    /* a reply timeout far above what a loaded machine takes between a round
     * and the fixture's release: only VANISH is a silence */
    roz_param_t items[16] = { { "command_writer_period_us", "0" },
                              { "reply_timeout_us", "300000" },
                              /* the suite's pace is no silent tick */
                              { "command_timeout_us", "60000000" } };
    size_t n = 3;
    for (size_t i = 0; params != NULL && i < params->n && n < 16; i++)
        items[n++] = params->items[i];
    roz_params_t p = { items, n };

    if (sc.opened || bus.running)
        sc_fx_close(); /* a check that failed half-way left it open */
    memset(&t, 0, sizeof t);
    t.sc = &sc;
    t.bus = &bus;
    t.fds[0] = t.fds[1] = -1;
    if (socketpair(AF_UNIX, SOCK_SEQPACKET, 0, t.fds) != 0 ||
        fake_can_start(&bus, t.fds[1], roz_test_leg_actuators, N_ACT, 0.002, 1) != 0) {
        snprintf(err, errlen, "socketcan fixture: no socketpair or fake bus");
        return ROZ_EIO;
    }
    t.port = roz_socketcan_port(&sc, NULL, NULL);
    roz_socketcan_set_fd(&sc, t.fds[0]);
    *port = t.port;
    int rc = roz_port_open(&t.port, m, &p, err, errlen);
    *port = t.port;
    if (rc != ROZ_OK)
        return rc;
    rc = roz_port_activate(&t.port);
    *port = t.port;
    return rc;
}

/* A round and one reply from each actuator that has a frame to answer. */
static void send_and_answer(void)
{
    uint64_t before = counters().replies;
    roz_test_can_round(&t);
    unsigned n = fake_can_release(&bus);
    ROZ_WAIT_FOR(counters().replies >= before + n);
}

static void sc_fx_peer(roz_peer_frame_t what)
{
    switch (what) {
    case ROZ_PEER_SEND:
        send_and_answer();
        break;
    case ROZ_PEER_SILENT:
        roz_test_can_nap();
        break;
    case ROZ_PEER_CORRUPT: {
        uint64_t crc = link_copy().crc_errors;
        uint8_t d[8] = { 0, 0, 0x08 /* form */, 0x08 /* in the CRC sequence */, 0, 0, 0, 0 };
        assert_int_equal(fake_can_send_raw(&bus, 0x20000000u | 0x08u /* ERR | PROT */, d, 8), 0);
        ROZ_WAIT_FOR(link_copy().crc_errors > crc);
        break;
    }
    case ROZ_PEER_REPLAY: {
        uint64_t replays = link_copy().replays;
        assert_int_equal(fake_can_replay(&bus, 0), 0);
        ROZ_WAIT_FOR(link_copy().replays > replays);
        break;
    }
    case ROZ_PEER_RESTART:
        fail_msg("socketcan: a restart cannot be told on this wire (no_sequence)");
        break;
    case ROZ_PEER_VANISH: {
        /* the hip's frames go unanswered past the timeout; then it answers */
        uint64_t lost = counters().lost;
        fake_can_mute(&bus, 0, 1);
        while (counters().lost == lost) {
            send_and_answer();
            roz_test_can_nap();
        }
        fake_can_mute(&bus, 0, 0);
        send_and_answer();
        break;
    }
    }
}

/* A command value as it reaches the actuator and back in the joint's
 * terms: the same arithmetic for what was written and what the fake
 * applied, so equal codes give equal doubles. */
static double joint_of_code(const roz_can_joint_t *jt, roz_interface_t type, uint16_t code)
{
    double dir = (double)jt->direction;
    switch (type) {
    case ROZ_IF_POSITION:
        return dir * roz_mit_codec_decode(code, &jt->ranges.position, ROZ_MIT_POSITION_BITS) +
               jt->zero_offset;
    case ROZ_IF_VELOCITY:
        return dir * roz_mit_codec_decode(code, &jt->ranges.velocity, ROZ_MIT_VELOCITY_BITS);
    case ROZ_IF_STIFFNESS:
        return roz_mit_codec_decode(code, &jt->ranges.kp, ROZ_MIT_KP_BITS);
    case ROZ_IF_DAMPING:
        return roz_mit_codec_decode(code, &jt->ranges.kd, ROZ_MIT_KD_BITS);
    default:
        return dir * roz_mit_codec_decode(code, &jt->ranges.torque, ROZ_MIT_TORQUE_BITS);
    }
}

static const roz_can_joint_t *joint_of_command(uint16_t i, int *field)
{
    for (uint16_t j = 0; j < sc.cfg.n_joints; j++) {
        const roz_can_joint_t *jt = &sc.cfg.joints[j];
        const int32_t slots[5] = { jt->pos_cmd, jt->vel_cmd, jt->kp_cmd, jt->kd_cmd, jt->eff_cmd };
        for (int k = 0; k < 5; k++) {
            if (slots[k] == (int32_t)i) {
                *field = k;
                return jt;
            }
        }
    }
    fail_msg("command %u has no joint", (unsigned)i);
    return NULL;
}

static void sc_fx_wire_command(const double *in, double *out)
{
    const roz_manifest_t *m = sc.m;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        int field;
        const roz_can_joint_t *jt = joint_of_command(i, &field);
        const roz_mit_range_t *ranges[5] = { &jt->ranges.position, &jt->ranges.velocity,
                                             &jt->ranges.kp, &jt->ranges.kd, &jt->ranges.torque };
        static const unsigned bits[5] = { ROZ_MIT_POSITION_BITS, ROZ_MIT_VELOCITY_BITS,
                                          ROZ_MIT_KP_BITS, ROZ_MIT_KD_BITS, ROZ_MIT_TORQUE_BITS };
        double dir = (double)jt->direction, x = in[i];
        if (field == 0)
            x = dir * (x - jt->zero_offset);
        else if (field == 1 || field == 4)
            x = dir * x;
        uint16_t code;
        (void)roz_mit_codec_encode(x, ranges[field], bits[field], &code);
        out[i] = joint_of_code(jt, m->commands[i].type, code);
    }
}

static void sc_fx_peer_sent(double *state)
{
    const roz_manifest_t *m = sc.m;
    for (uint16_t j = 0; j < sc.cfg.n_joints; j++) {
        const roz_can_joint_t *jt = &sc.cfg.joints[j];
        fake_actuator_t a;
        roz_mit_reply_t rep;
        fake_can_view(&bus, j, &a);
        assert_true(a.last_reply_len > 0);
        assert_int_equal(roz_mit_codec_unpack(&jt->ranges, jt->reply, a.last_reply,
                                              (size_t)a.last_reply_len, &rep),
                         ROZ_OK);
        double dir = (double)jt->direction;
        if (jt->pos_state >= 0)
            state[jt->pos_state] = dir * rep.position + jt->zero_offset;
        if (jt->vel_state >= 0)
            state[jt->vel_state] = dir * rep.velocity;
        if (jt->eff_state >= 0)
            state[jt->eff_state] = dir * rep.torque;
    }
    (void)m;
}

static void sc_fx_settle(void)
{
    roz_test_can_settle(&t);
}

/* What the actuators apply, in the joints' terms; NULL until each has a
 * command (a hold is one; "enter motor mode" is not). */
static const double *sc_fx_peer_command(void)
{
    const roz_manifest_t *m = sc.m;
    fake_actuator_t a[N_ACT];
    for (unsigned j = 0; j < N_ACT; j++) {
        fake_can_view(&bus, j, &a[j]);
        if (!a[j].have_cmd)
            return NULL;
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        int field;
        const roz_can_joint_t *jt = joint_of_command(i, &field);
        unsigned j = (unsigned)(jt - sc.cfg.joints);
        applied[i] = joint_of_code(jt, m->commands[i].type, a[j].code[field]);
    }
    return applied;
}

static void sc_fx_corrupt_next_command(void)
{
    for (unsigned j = 0; j < N_ACT; j++)
        fake_can_drop_next(&bus, j);
}

static void sc_fx_link(roz_link_t *out)
{
    roz_socketcan_link(&sc, out);
}

static void sc_fx_close(void)
{
    if (sc.opened) {
        (void)roz_port_deactivate(&t.port);
        roz_port_close(&t.port);
    }
    if (bus.running)
        fake_can_stop(&bus);
    for (int k = 0; k < 2; k++) {
        if (t.fds[k] > 0)
            close(t.fds[k]);
    }
    memset(&t, 0, sizeof t);
}

static const roz_manifest_t *const leg_only[] = { &roz_manifest_can_leg, NULL };

const roz_port_fixture_t roz_fixture_socketcan = {
    .name = "socketcan",
    .manifests = leg_only,
    .wire_command = sc_fx_wire_command,
    .open = sc_fx_open,
    .peer = sc_fx_peer,
    .peer_sent = sc_fx_peer_sent,
    .settle = sc_fx_settle,
    .peer_command = sc_fx_peer_command,
    .corrupt_next_command = sc_fx_corrupt_next_command,
    .link = sc_fx_link,
    .close = sc_fx_close,
};
