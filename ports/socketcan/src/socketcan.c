/* SPDX-License-Identifier: Apache-2.0 */
/* The socketcan port: the receive thread (replies to joint states, the
 * link and consistency checks), the command writer (rounds, the start-up
 * layers, loss of an actuator), the tick's read() and write(), shutdown.
 * Linux's CAN headers stay in socketcan_adapt.c.
 *
 * Who writes what (roz_socketcan_shared_t, per joint):
 *   sent       writer (and shutdown, after the writer stopped), counted
 *              before each frame goes out, so that a quick reply finds its
 *              frame counted;
 *   replies, session, hold_code   the receive thread; hold_code before
 *              session and replies (release), so a reader that sees a
 *              session sees a position of it;
 *   answered   the receive thread: `sent` as the last accepted reply found
 *              it (frames after it are unanswered);
 *   lost       the writer: "replies + 1" when the oldest unanswered frame
 *              is older than the reply timeout. It is true while replies
 *              still has that value; a reply makes it false by itself.
 * The tick reads the receive thread's frames through state_buf and the
 * writer reads the tick's commands through cmd_buf (roz/buffer.h). */
#define _GNU_SOURCE /* sem_clockwait */
#include "roz/port/socketcan.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <semaphore.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "roz/hal/clock.h"
#include "roz/hal/joints.h"
#include "roz/port/mit_codec.h"
#include "socketcan_adapt.h"

_Static_assert(sizeof(pthread_t) <= sizeof(unsigned long), "pthread_t must fit the opaque field");
_Static_assert(sizeof(sem_t) <= sizeof(((roz_socketcan_t *)0)->wake.bytes),
               "sem_t must fit the opaque field");
_Static_assert(sizeof(roz_socketcan_counters_t) % sizeof(uint64_t) == 0, "counters are uint64_t");

#define NS_PER_US 1000u
#define NS_PER_S 1000000000ull
#define RX_POLL_MS 20        /* the receive thread looks at its stop flag this often */
#define IDLE_WAKE_NS 10000000u /* a writer without a period looks for losses this often */
#define DEADBAND_STEPS 4.0   /* velocities within this many codes of 0 count as at rest */

#define C(field) (offsetof(roz_socketcan_counters_t, field) / sizeof(uint64_t))

enum { L_ACCEPTED, L_CRC, L_REPLAYS, L_RESTARTS, L_RETURNS, L_MISSING };
enum { FAULT_NONE, FAULT_CODE, FAULT_CONSISTENCY, FAULT_SILENT, FAULT_WATCHDOG };
enum { META_SESSION, META_ERROR, META_INCONSISTENT, META_N };

/* ---- small things ------------------------------------------------------------ */

static void bump(roz_socketcan_t *sc, size_t i, uint64_t by)
{
    atomic_fetch_add_explicit(&sc->n[i], by, memory_order_relaxed);
}

static void link_bump(roz_socketcan_t *sc, size_t i, uint64_t by)
{
    atomic_fetch_add_explicit(&sc->link_n[i], by, memory_order_relaxed);
}

static uint64_t now_ns(void)
{
    return roz_clock_monotonic_ns(NULL);
}

static sem_t *wake_sem(roz_socketcan_t *sc)
{
    return (sem_t *)(void *)sc->wake.bytes;
}

static size_t image_len(const roz_socketcan_t *sc)
{
    return (size_t)sc->m->n_states + META_N * (size_t)sc->cfg.n_joints;
}

static size_t meta(const roz_socketcan_t *sc, size_t j, int what)
{
    return (size_t)sc->m->n_states + META_N * j + (size_t)what;
}

static struct timespec to_timespec(uint64_t ns)
{
    struct timespec ts = { (time_t)(ns / NS_PER_S), (long)(ns % NS_PER_S) };
    return ts;
}

static void sleep_ns(uint64_t ns)
{
    struct timespec ts = to_timespec(ns);
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
        ;
}

/* ---- receive ------------------------------------------------------------------ */

/* The joint a reply belongs to: its id byte, from its actuator or master_id. */
static int joint_of(const roz_socketcan_t *sc, const roz__can_frame_t *f)
{
    if (f->len == 0)
        return -1;
    for (uint16_t j = 0; j < sc->cfg.n_joints; j++) {
        const roz_can_joint_t *jt = &sc->cfg.joints[j];
        if (f->data[0] == (jt->can_id & 0xFFu) && (f->id == jt->can_id || f->id == sc->cfg.master_id))
            return j;
    }
    return -1;
}

/* Position against velocity, in the actuator's frame; 1 when inconsistent.
 * dt counts the command intervals between the two replies (the actuator
 * answers each frame at once). Host receive times would make a late receive
 * thread look like a jump, and frame counts would make a late writer look
 * like one: the travel allowed for timing is the faster velocity times the
 * larger of one interval and the disagreement of the two clocks. */
static int inconsistent(roz_socketcan_t *sc, size_t j, const roz_mit_reply_t *rep, uint32_t seq,
                        uint64_t t)
{
    roz_socketcan_rx_joint_t *rx = &sc->rx[j];
    const roz_can_joint_t *jt = &sc->cfg.joints[j];
    double margin = sc->cfg.consistency_margin;
    double interval = (double)sc->cfg.joint_interval_us * 1e-6;
    double dt = (double)(uint32_t)(seq - rx->last_seq) * interval;
    double dt_host = (double)(t - rx->last_t) * 1e-9;
    double vbar = 0.5 * (rx->last_v + rep->velocity);
    double vmax = fmax(fabs(rx->last_v), fabs(rep->velocity));
    double slack = margin + vmax * fmax(interval, fabs(dt_host - dt));
    double deadband = DEADBAND_STEPS * roz_mit_codec_step(&jt->ranges.velocity,
                                                          ROZ_MIT_VELOCITY_BITS);

    if (margin <= 0.0 || !rx->have)
        return 0;
    if (fabs((rep->position - rx->last_p) - vbar * dt) > slack) {
        rx->frozen_travel = 0.0;
        return 1;
    }
    /* the same position code while the velocity says it moves one way */
    if (rep->position_code == rx->last_pcode && fabs(rep->velocity) > deadband &&
        fabs(rx->last_v) > deadband && (rep->velocity > 0) == (rx->last_v > 0)) {
        rx->frozen_travel += fabs(vbar) * dt;
        if (rx->frozen_travel > slack) {
            rx->frozen_travel = 0.0;
            return 1;
        }
    } else {
        rx->frozen_travel = 0.0;
    }
    return 0;
}

/* The position a hold sends: the measured one, inside the limits of the
 * joint's position command (a hold has no gains and drives nothing, but no
 * value outside the manifest goes on the bus: an actuator measured past
 * its limit is held at the limit). Where the joint has no position command
 * the measured code itself. */
static uint16_t hold_code_of(const roz_socketcan_t *sc, const roz_can_joint_t *jt,
                             const roz_mit_reply_t *rep)
{
    if (jt->pos_cmd < 0)
        return rep->position_code;
    double p = (double)jt->direction * rep->position + jt->zero_offset;
    double q = roz_channel_clamp(&sc->m->commands[jt->pos_cmd], p);
    if (q == p)
        return rep->position_code;
    uint16_t code = rep->position_code;
    (void)roz_mit_codec_encode((double)jt->direction * (q - jt->zero_offset), &jt->ranges.position,
                               ROZ_MIT_POSITION_BITS, &code);
    return code;
}

static void on_reply(roz_socketcan_t *sc, size_t j, const roz__can_frame_t *f, uint64_t t)
{
    const roz_can_joint_t *jt = &sc->cfg.joints[j];
    roz_socketcan_rx_joint_t *rx = &sc->rx[j];
    roz_socketcan_shared_t *sh = &sc->shared[j];
    roz_mit_reply_t rep;

    if (roz_mit_codec_unpack(&jt->ranges, jt->reply, f->data, f->len, &rep) != ROZ_OK) {
        bump(sc, C(short_frames), 1);
        return;
    }
    if (roz_mit_codec_special_of(f->data, f->len) != 0) {
        bump(sc, C(unknown), 1); /* a special frame to an id that answers with 0xFF */
        return;
    }
    /* a reply answers a frame: the count of frames sent is its sequence */
    uint32_t seq = atomic_load_explicit(&sh->sent, memory_order_acquire);
    uint64_t missing = rx->link.missing;
    if (seq == 0 || roz_link_check(&rx->link, 1, seq, t) == ROZ_LINK_REPLAY) {
        if (seq == 0)
            rx->link.replays++; /* nothing was sent to it: unasked */
        link_bump(sc, L_REPLAYS, 1);
        return;
    }
    link_bump(sc, L_MISSING, rx->link.missing - missing);

    uint32_t replies = atomic_load_explicit(&sh->replies, memory_order_relaxed);
    uint32_t session = atomic_load_explicit(&sh->session, memory_order_relaxed);
    int returned = session != 0 &&
                   atomic_load_explicit(&sh->lost, memory_order_acquire) == replies + 1u;
    if (session == 0 || returned) {
        session++;
        rx->have = 0; /* a new session: no consistency across the silence */
        rx->frozen_travel = 0.0;
        if (returned)
            link_bump(sc, L_RETURNS, 1);
    }
    if (inconsistent(sc, j, &rep, seq, t)) {
        rx->inconsistent++;
        bump(sc, C(inconsistent), 1);
    }
    rx->last_pcode = rep.position_code;
    rx->last_p = rep.position;
    rx->last_v = rep.velocity;
    rx->last_seq = seq;
    rx->last_t = t;
    rx->have = 1;
    rx->error = rep.error;
    if (rep.error != 0)
        bump(sc, C(error_replies), 1);

    double dir = (double)jt->direction;
    if (jt->pos_state >= 0)
        sc->rx_image[jt->pos_state] = dir * rep.position + jt->zero_offset;
    if (jt->vel_state >= 0)
        sc->rx_image[jt->vel_state] = dir * rep.velocity;
    if (jt->eff_state >= 0)
        sc->rx_image[jt->eff_state] = dir * rep.torque;
    sc->rx_image[meta(sc, j, META_SESSION)] = (double)session;
    sc->rx_image[meta(sc, j, META_ERROR)] = (double)rep.error;
    sc->rx_image[meta(sc, j, META_INCONSISTENT)] = (double)rx->inconsistent;

    atomic_store_explicit(&sh->hold_code, hold_code_of(sc, jt, &rep), memory_order_relaxed);
    atomic_store_explicit(&sh->session, session, memory_order_release);
    atomic_store_explicit(&sh->answered, seq, memory_order_release);
    atomic_store_explicit(&sh->replies, replies + 1u, memory_order_release);
    roz_buffer_write(&sc->state_buf, sc->rx_image, t);
    /* counted once published, with release (roz_socketcan_counters() loads
     * with acquire): whoever sees the count can read the frame */
    link_bump(sc, L_ACCEPTED, 1);
    atomic_fetch_add_explicit(&sc->n[C(replies)], 1u, memory_order_release);
}

static void on_frame(roz_socketcan_t *sc, const roz__can_frame_t *f, uint64_t t)
{
    if (f->len > 8) {
        bump(sc, C(unknown), 1); /* not a classic CAN frame */
    } else if (f->flags & ROZ__CAN_ERR) {
        bump(sc, C(bus_errors), 1);
        if (f->err & ROZ__CAN_ERR_CRC)
            link_bump(sc, L_CRC, 1);
        if (f->err & ROZ__CAN_ERR_BUSOFF)
            bump(sc, C(bus_off), 1);
    } else if (f->flags & (ROZ__CAN_EFF | ROZ__CAN_RTR)) {
        bump(sc, C(unknown), 1);
    } else {
        int j = joint_of(sc, f);
        if (j < 0)
            bump(sc, C(unknown), 1);
        else
            on_reply(sc, (size_t)j, f, t);
    }
}

static void *rx_main(void *arg)
{
    roz_socketcan_t *sc = arg;
    roz__can_frame_t f;

    while (!atomic_load_explicit(&sc->stop_rx, memory_order_acquire)) {
        int rc = roz__can_recv(sc->fd, &f, RX_POLL_MS);
        if (rc == 0)
            continue;
        if (rc < 0) {
            bump(sc, C(rx_errors), 1);
            sleep_ns(RX_POLL_MS * 1000000ull); /* a closed or broken socket: do not spin */
            continue;
        }
        uint64_t t0 = now_ns();
        bump(sc, C(frames_received), 1);
        on_frame(sc, &f, t0);
        uint64_t t1 = now_ns();
        roz_monitor_record(&sc->monitor, ROZ_MON_STATE_HANDLER, t1 - t0, t1);
    }
    return NULL;
}

/* ---- writer -------------------------------------------------------------------- */

/* Count the frame, then send it: a reply that comes back at once finds it. */
static void send_to(roz_socketcan_t *sc, size_t j, const uint8_t data[8], size_t counter,
                    uint64_t t)
{
    roz__can_frame_t f;
    memset(&f, 0, sizeof f);
    f.id = sc->cfg.joints[j].can_id;
    f.len = 8;
    memcpy(f.data, data, 8);
    /* the writer alone counts frames while it runs: this one will be k */
    uint32_t k = atomic_load_explicit(&sc->shared[j].sent, memory_order_relaxed) + 1u;
    sc->tx[j].sent_ns[k % ROZ_SOCKETCAN_SENT_RING] = t;
    if (sc->tx[j].oldest_ns == 0)
        sc->tx[j].oldest_ns = t;
    atomic_store_explicit(&sc->shared[j].sent, k, memory_order_release);
    if (roz__can_send(sc->fd, &f) == ROZ_OK) {
        bump(sc, C(frames_sent), 1);
        bump(sc, counter, 1);
    } else {
        bump(sc, C(send_errors), 1);
    }
}

static void special_to(roz_socketcan_t *sc, size_t j, roz_mit_special_t which, size_t counter,
                       uint64_t t)
{
    uint8_t data[8];
    roz_mit_codec_special(which, data);
    send_to(sc, j, data, counter, t);
}

/* The measured position, velocity 0, no gains, no torque. */
/* The start-up hold: the measured position, no gains, no torque. */
static void hold_to(roz_socketcan_t *sc, size_t j, uint64_t t)
{
    roz_mit_codes_t codes = sc->zero_codes[j];
    uint8_t data[8];
    codes.position = (uint16_t)atomic_load_explicit(&sc->shared[j].hold_code, memory_order_relaxed);
    (void)roz_mit_codec_pack_codes(&codes, data);
    send_to(sc, j, data, C(holds_sent), t);
}

/* The measured position the holds use (inside the position command's
 * limits: hold_code_of()), in the joint's frame. */
static double held_position(const roz_socketcan_t *sc, size_t j)
{
    const roz_can_joint_t *jt = &sc->cfg.joints[j];
    uint16_t code = (uint16_t)atomic_load_explicit(&sc->shared[j].hold_code, memory_order_relaxed);
    double p = roz_mit_codec_decode(code, &jt->ranges.position, ROZ_MIT_POSITION_BITS);
    return (double)jt->direction * p + jt->zero_offset;
}

/* The hold after a trip, until every group got one: the start-up hold,
 * with the watchdog hold's damping kept (no frame of kd 0 between two of
 * the watchdog's: test_socketcan_watchdog_on_write). */
static void damped_hold_to(roz_socketcan_t *sc, size_t j, uint64_t t)
{
    const roz_can_joint_t *jt = &sc->cfg.joints[j];
    roz_mit_codes_t codes = sc->zero_codes[j];
    roz_mit_command_t c = { 0.0, 0.0, 0.0, roz_can_hold_damping(sc->m, jt), 0.0 };
    roz_mit_codes_t damped;
    uint8_t data[8];
    (void)roz_mit_codec_quantize(&jt->ranges, &c, &damped);
    codes.kd = damped.kd;
    codes.position = (uint16_t)atomic_load_explicit(&sc->shared[j].hold_code, memory_order_relaxed);
    (void)roz_mit_codec_pack_codes(&codes, data);
    send_to(sc, j, data, C(holds_sent), t);
}

/* The tick is silent: the watchdog's hold (roz/port/can_hold.h), each
 * joint at its hold gains keeping the torque of its last command. */
static void pack_watchdog_hold(roz_socketcan_t *sc, size_t j, uint8_t data[8])
{
    const roz_can_joint_t *jt = &sc->cfg.joints[j];
    roz_mit_command_t c;
    roz_can_watchdog_hold(sc->m, jt, &sc->tx[j].last, held_position(sc, j), &c);
    uint32_t what = roz_mit_codec_pack(&jt->ranges, &c, data);
    if ((what & (ROZ_MIT_SAT_ANY | ROZ_MIT_NONFINITE_ANY)) != 0)
        bump(sc, C(saturated), (uint64_t)__builtin_popcount(what & (ROZ_MIT_SAT_ANY |
                                                                    ROZ_MIT_NONFINITE_ANY)));
}

static void watchdog_to(roz_socketcan_t *sc, size_t j, uint64_t t)
{
    uint8_t data[8];
    pack_watchdog_hold(sc, j, data);
    send_to(sc, j, data, C(holds_sent), t);
}

static void command_to(roz_socketcan_t *sc, size_t j, uint64_t t)
{
    const roz_can_joint_t *jt = &sc->cfg.joints[j];
    const double *cmd = sc->tx_cmd;
    double dir = (double)jt->direction;
    roz_mit_command_t c;
    uint8_t data[8];

    if (jt->pos_cmd >= 0) {
        c.position = dir * (cmd[jt->pos_cmd] - jt->zero_offset);
    } else {
        uint16_t code = (uint16_t)atomic_load_explicit(&sc->shared[j].hold_code,
                                                       memory_order_relaxed);
        c.position = roz_mit_codec_decode(code, &jt->ranges.position, ROZ_MIT_POSITION_BITS);
    }
    c.velocity = jt->vel_cmd >= 0 ? dir * cmd[jt->vel_cmd] : 0.0;
    c.kp = jt->kp_cmd >= 0 ? cmd[jt->kp_cmd] : 0.0;
    c.kd = jt->kd_cmd >= 0 ? cmd[jt->kd_cmd] : 0.0;
    c.torque = jt->eff_cmd >= 0 ? dir * cmd[jt->eff_cmd] : 0.0;
    uint32_t what = roz_mit_codec_pack(&jt->ranges, &c, data);
    uint32_t fields = what & (ROZ_MIT_SAT_ANY | ROZ_MIT_NONFINITE_ANY);
    if (fields != 0)
        bump(sc, C(saturated), (uint64_t)__builtin_popcount(fields));
    roz_can_last_t *last = &sc->tx[j].last;
    last->sent = 1;
    last->position = dir * c.position + jt->zero_offset;
    last->stiffness = c.kp;
    last->measured = held_position(sc, j);
    send_to(sc, j, data, C(commands_sent), t);
}

/* An actuator whose oldest unanswered frame is older than the timeout is
 * lost (every joint, every round: a group's joints wait their turn). When a
 * reply comes, the frames after the one it found counted are unanswered,
 * the oldest of them sent at sent_ns (when more went out since than the
 * ring holds, the oldest it holds: a silence judged no sooner than it is);
 * a frame sent with none unanswered is the oldest itself (send_to()). */
static void watch_losses(roz_socketcan_t *sc, uint64_t t)
{
    uint64_t timeout = (uint64_t)sc->cfg.reply_timeout_us * NS_PER_US;
    for (size_t j = 0; j < sc->cfg.n_joints; j++) {
        roz_socketcan_tx_joint_t *tx = &sc->tx[j];
        roz_socketcan_shared_t *sh = &sc->shared[j];
        uint32_t r = atomic_load_explicit(&sh->replies, memory_order_acquire);
        uint32_t a = atomic_load_explicit(&sh->answered, memory_order_acquire);
        uint32_t s = atomic_load_explicit(&sh->sent, memory_order_relaxed);
        if (a != tx->answered_seen) {
            tx->answered_seen = a;
            uint32_t oldest = s - a > ROZ_SOCKETCAN_SENT_RING ? s - ROZ_SOCKETCAN_SENT_RING + 1u
                                                              : a + 1u;
            tx->oldest_ns = s == a ? 0 : tx->sent_ns[oldest % ROZ_SOCKETCAN_SENT_RING];
        }
        if (tx->oldest_ns != 0 && t - tx->oldest_ns > timeout &&
            atomic_load_explicit(&sh->lost, memory_order_relaxed) != r + 1u) {
            atomic_store_explicit(&sh->lost, r + 1u, memory_order_release);
            bump(sc, C(lost), 1);
        }
    }
}

/* The command watchdog's verdict on the latest command for this round. A
 * hold frame (the tick's first writes after a trip) counts as sent once
 * every round-robin group got it. */
static roz_cmd_verdict_t judge_round(roz_socketcan_t *sc, uint64_t t)
{
    if (sc->tx_cmd_seq == 0)
        return ROZ_CMD_SEND; /* nothing written yet: the start-up layers decide */
    int held = sc->tx_hold && sc->hold_rounds + 1u >= sc->cfg.groups;
    roz_cmd_verdict_t v = roz_cmd_watchdog_judge(&sc->watchdog, sc->tx_epoch, held,
                                                 sc->tx_stamp, t);
    if (v == ROZ_CMD_SEND && sc->tx_hold)
        sc->hold_rounds++;
    else
        sc->hold_rounds = 0;
    return v;
}

/* One round: each joint of this round's group gets one frame. */
static void round_pass(roz_socketcan_t *sc, uint64_t t)
{
    roz_buffer_frame_t fr;
    int all = 1;
    uint64_t before = sc->tx_cmd_seq; /* the commands the tick wrote before this round */
    uint16_t n = sc->m->n_commands;

    if (roz_buffer_read(&sc->cmd_buf, &fr) >= 0 && fr.seq != 0 && fr.seq != sc->tx_cmd_seq) {
        memcpy(sc->tx_cmd, fr.values, (size_t)n * sizeof sc->tx_cmd[0]);
        sc->tx_cmd_seq = fr.seq;
        sc->tx_epoch = (uint32_t)fr.values[n];
        sc->tx_hold = fr.values[n + 1u] != 0.0;
        sc->tx_stamp = fr.stamp_ns;
    }
    roz_cmd_verdict_t verdict = judge_round(sc, t);
    sc->last_round_ns = t;
    watch_losses(sc, t);
    for (size_t j = 0; j < sc->cfg.n_joints; j++)
        all &= atomic_load_explicit(&sc->shared[j].session, memory_order_acquire) != 0;

    for (size_t j = sc->round % sc->cfg.groups; j < sc->cfg.n_joints; j += sc->cfg.groups) {
        roz_socketcan_tx_joint_t *tx = &sc->tx[j];
        uint32_t session = atomic_load_explicit(&sc->shared[j].session, memory_order_acquire);
        if (session == 0) {
            /* layer 1: nothing but "enter motor mode" (which asks for a reply) */
            special_to(sc, j, ROZ_MIT_ENTER_MOTOR_MODE, C(enter_sent), t);
            continue;
        }
        if (session != tx->session_seen) {
            tx->session_seen = session;
            tx->enter_pending = session > 1; /* back after a silence: maybe rebooted */
            tx->ready_seq = UINT64_MAX;
            tx->hold_seq = 0;
            tx->last.sent = 0; /* a new session: nothing of it was commanded */
        }
        if (tx->enter_pending) {
            tx->enter_pending = 0;
            special_to(sc, j, ROZ_MIT_ENTER_MOTOR_MODE, C(enter_sent), t);
            continue;
        }
        if (!all) { /* layer 2: holds until every actuator has answered */
            hold_to(sc, j, t);
            continue;
        }
        if (tx->ready_seq == UINT64_MAX)
            tx->ready_seq = before; /* those came before it was ready */
        if (sc->tx_cmd_seq <= tx->ready_seq) {
            hold_to(sc, j, t);
        } else if (tx->hold_seq == 0 || sc->tx_cmd_seq == tx->hold_seq) {
            tx->hold_seq = sc->tx_cmd_seq; /* layer 3: the first command after is a hold */
            hold_to(sc, j, t);
        } else if (verdict == ROZ_CMD_SAFE) {
            watchdog_to(sc, j, t); /* the tick went silent: the hold until it is back */
            bump(sc, C(watchdog_holds), 1);
        } else if (sc->tx_hold) {
            /* back after a trip: the stop's hold first, never a frame
             * without stiffness (test_socketcan_watchdog_on_write) */
            if (tx->last.sent)
                watchdog_to(sc, j, t);
            else
                damped_hold_to(sc, j, t);
        } else {
            command_to(sc, j, t);
        }
    }
    sc->round++;
    bump(sc, C(rounds), 1);
}

static void timed_round(roz_socketcan_t *sc)
{
    uint64_t t0 = now_ns();
    round_pass(sc, t0);
    uint64_t t1 = now_ns();
    roz_monitor_record(&sc->monitor, ROZ_MON_COMMAND_WRITER, t1 - t0, t1);
}

static void run_periodic(roz_socketcan_t *sc)
{
    uint64_t period = (uint64_t)sc->cfg.command_writer_period_us * NS_PER_US;
    uint64_t next = now_ns();

    while (!atomic_load_explicit(&sc->stop_tx, memory_order_acquire)) {
        struct timespec ts = to_timespec(next);
        if (sem_clockwait(wake_sem(sc), CLOCK_MONOTONIC, &ts) == 0 || errno == EINTR)
            continue; /* stop (or a stray post): look at the flag */
        roz_monitor_periodic(&sc->monitor, now_ns());
        timed_round(sc);
        next += period;
        uint64_t done = now_ns();
        if (done > next + period) {
            bump(sc, C(writer_missed), 1); /* far behind: go on from now, no burst */
            next = done + period;
        }
    }
}

/* When the command watchdog wants a round without a post: the expiry of
 * the last command sent; while tripped, a control period after the last
 * round (the hold, repeated); UINT64_MAX: not before a post. */
static uint64_t watchdog_due(const roz_socketcan_t *sc)
{
    uint64_t due = roz_cmd_watchdog_next_ns(&sc->watchdog);
    return due != 0 ? due : sc->last_round_ns + (uint64_t)sc->cfg.round_us * NS_PER_US;
}

/* A round per post; posts that piled up meanwhile are one round (it sends
 * the latest command). Between posts, losses are still watched, and the
 * command watchdog sends its rounds when it is due. */
static void run_on_write(roz_socketcan_t *sc)
{
    while (!atomic_load_explicit(&sc->stop_tx, memory_order_acquire)) {
        uint64_t t = now_ns(), due = watchdog_due(sc);
        struct timespec ts = to_timespec(due < t + IDLE_WAKE_NS ? due : t + IDLE_WAKE_NS);
        if (sem_clockwait(wake_sem(sc), CLOCK_MONOTONIC, &ts) != 0) {
            if (errno == ETIMEDOUT && now_ns() >= due)
                timed_round(sc);
            else if (errno == ETIMEDOUT)
                watch_losses(sc, now_ns());
            continue;
        }
        while (sem_trywait(wake_sem(sc)) == 0)
            ;
        if (atomic_load_explicit(&sc->stop_tx, memory_order_acquire))
            break;
        uint64_t asked = atomic_load_explicit(&sc->n[C(wakes)], memory_order_acquire);
        timed_round(sc);
        atomic_store_explicit(&sc->n[C(wakes_served)], asked, memory_order_release);
    }
}

static void *tx_main(void *arg)
{
    roz_socketcan_t *sc = arg;
    if (sc->cfg.command_writer_period_us != 0)
        run_periodic(sc);
    else
        run_on_write(sc);
    return NULL;
}

/* ---- shutdown ------------------------------------------------------------------- */

static void send_patiently(roz_socketcan_t *sc, size_t j, const uint8_t data[8], size_t counter)
{
    roz__can_frame_t f;
    memset(&f, 0, sizeof f);
    f.id = sc->cfg.joints[j].can_id;
    f.len = 8;
    memcpy(f.data, data, 8);
    atomic_fetch_add_explicit(&sc->shared[j].sent, 1u, memory_order_acq_rel);
    for (int attempt = 0; attempt < 3; attempt++) {
        int rc = roz__can_send(sc->fd, &f);
        if (rc == ROZ_OK) {
            bump(sc, C(frames_sent), 1);
            bump(sc, counter, 1);
            return;
        }
        if (rc != ROZ_ENOSPC)
            break;
        roz__can_wait_writable(sc->fd, 10);
    }
    bump(sc, C(send_errors), 1);
}

/* Every actuator that answered: the exit is a stop like the others
 * (roz/hold.h): the watchdog's hold from the last command that went out
 * (roz/port/can_hold.h: the hold gains, the torque kept within the band),
 * and the actuators stay in motor mode, holding, as under the watchdog; an
 * actuator never commanded keeps the start-up hold it had (no gains).
 * "Exit motor mode" would leave a standing robot limp
 * (test_socketcan_shutdown, test_socketcan_stops_keep_the_torque). */
static void shutdown_frames(roz_socketcan_t *sc)
{
    for (size_t j = 0; j < sc->cfg.n_joints; j++) {
        if (atomic_load_explicit(&sc->shared[j].session, memory_order_acquire) == 0)
            continue;
        uint8_t data[8];
        if (sc->tx[j].last.sent) {
            pack_watchdog_hold(sc, j, data);
        } else {
            roz_mit_codes_t codes = sc->zero_codes[j];
            codes.position = (uint16_t)atomic_load_explicit(&sc->shared[j].hold_code,
                                                            memory_order_relaxed);
            (void)roz_mit_codec_pack_codes(&codes, data);
        }
        send_patiently(sc, j, data, C(holds_sent));
    }
}

/* ---- ops ------------------------------------------------------------------------ */

typedef struct {
    char  *err;
    size_t errlen;
    int    said;
} first_problem_t;

static void keep_first(void *ctx, const char *rule, const char *what)
{
    first_problem_t *fp = ctx;
    (void)rule;
    if (fp->said++ == 0)
        snprintf(fp->err, fp->errlen, "socketcan: %s", what[0] == ':' ? what + 2 : what);
}

static int sc_open(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                   size_t errlen)
{
    roz_socketcan_t *sc = self;
    int given = sc->given_fd;
    roz_log_fn log = sc->log;
    void *log_ctx = sc->log_ctx;
    first_problem_t fp = { err, errlen, 0 };

    if (sc->opened)
        return ROZ_ESTATE;
    memset(sc, 0, sizeof *sc);
    sc->given_fd = given;
    sc->fd = -1;
    sc->log = log;
    sc->log_ctx = log_ctx;
    sc->fault_joint = -1;
    if (m == NULL || roz_manifest_validate(m, NULL) != ROZ_OK) {
        snprintf(err, errlen, "socketcan: invalid manifest");
        return ROZ_EINVAL;
    }
    if (roz_can_config_load(&sc->cfg, m, p, keep_first, &fp) != ROZ_OK)
        return ROZ_EINVAL;
    sc->m = m;

    for (size_t j = 0; j < sc->cfg.n_joints; j++) {
        const roz_can_joint_t *jt = &sc->cfg.joints[j];
        roz_mit_command_t zero = { 0.0, 0.0, 0.0, 0.0, 0.0 };
        (void)roz_mit_codec_quantize(&jt->ranges, &zero, &sc->zero_codes[j]);
        roz_link_init(&sc->rx[j].link, 0, 0);
        snprintf(sc->stale_text[j], sizeof sc->stale_text[j],
                 "its actuator (CAN id %u) stopped answering (no reply in %u us)",
                 (unsigned)jt->can_id, (unsigned)sc->cfg.reply_timeout_us);
        snprintf(sc->jump_text[j], sizeof sc->jump_text[j],
                 "position does not follow velocity (CAN id %u): stuck, or replies replayed",
                 (unsigned)jt->can_id);
    }
    /* states of no reply yet read as the manifest's defaults */
    for (uint16_t i = 0; i < m->n_states; i++)
        sc->rx_image[i] = m->states[i].default_value;
    roz_buffer_init(&sc->state_buf, sc->state_slots, (uint32_t)image_len(sc));
    roz_buffer_init(&sc->cmd_buf, sc->cmd_slots, (uint32_t)m->n_commands + 2u);
    roz_cmd_watchdog_init(&sc->watchdog, sc->cfg.command_timeout_us);
    roz_monitor_init(&sc->monitor, "socketcan",
                     (uint64_t)(sc->cfg.command_writer_period_us != 0
                                    ? sc->cfg.command_writer_period_us
                                    : sc->cfg.round_us) * NS_PER_US,
                     log, log_ctx);
    if (!sc->cfg.enable_monitor) {
        for (int k = 0; k < ROZ_MON_KIND_COUNT_; k++)
            roz_monitor_set_threshold(&sc->monitor, (roz_monitor_kind_t)k, 0);
    }
    if (sem_init(wake_sem(sc), 0, 0) != 0) {
        snprintf(err, errlen, "socketcan: no semaphore for the writer");
        return ROZ_EIO;
    }
    sc->wake_ready = 1;
    if (given >= 0) {
        sc->fd = given;
    } else {
        char why[200];
        int fd = roz__can_open(sc->cfg.network_interface, why, sizeof why);
        if (fd < 0) {
            snprintf(err, errlen, "socketcan: %s", why);
            sem_destroy(wake_sem(sc));
            sc->wake_ready = 0;
            return fd;
        }
        sc->fd = fd;
        sc->own_fd = 1;
    }
    sc->opened = 1;
    return ROZ_OK;
}

static int sc_activate(void *self)
{
    roz_socketcan_t *sc = self;

    if (!sc->opened)
        return ROZ_ESTATE;
    if (sc->active)
        return ROZ_OK;
    atomic_store(&sc->stop_rx, 0);
    atomic_store(&sc->stop_tx, 0);
    char err[200];
    int rc = roz_thread_start(&sc->rx_thread, &sc->cfg.receive_thread, "receive_thread", rx_main,
                              sc, err, sizeof err);
    if (rc != ROZ_OK) {
        if (sc->log != NULL)
            sc->log(sc->log_ctx, ROZ_LOG_ERROR, err);
        return rc;
    }
    sc->rx_started = 1;
    rc = roz_thread_start(&sc->tx_thread, &sc->cfg.writer_thread, "command_writer", tx_main, sc,
                          err, sizeof err);
    if (rc != ROZ_OK) {
        if (sc->log != NULL)
            sc->log(sc->log_ctx, ROZ_LOG_ERROR, err);
        atomic_store(&sc->stop_rx, 1);
        roz_thread_join(sc->rx_thread);
        sc->rx_started = 0;
        return rc;
    }
    sc->tx_started = 1;
    sc->active = 1;
    return ROZ_OK;
}

static int read_frame(roz_socketcan_t *sc, double *state, size_t n)
{
    roz_buffer_frame_t fr;
    int returned = 0, stale = -1;

    sc->fault_joint = -1;
    int rc = roz_buffer_read(&sc->state_buf, &fr);
    if (rc == ROZ_ENOENT)
        return ROZ_ENOENT;
    const double *img = fr.values;
    for (size_t j = 0; j < sc->cfg.n_joints; j++) {
        if (img[meta(sc, j, META_SESSION)] == 0.0)
            return ROZ_ENOENT; /* a whole state needs every actuator */
    }
    for (size_t j = 0; j < sc->cfg.n_joints; j++) {
        uint32_t session = (uint32_t)img[meta(sc, j, META_SESSION)];
        if (session != sc->tick_session[j]) {
            returned |= sc->tick_session[j] != 0;
            sc->tick_session[j] = session;
        }
        uint32_t r = atomic_load_explicit(&sc->shared[j].replies, memory_order_acquire);
        if (stale < 0 && atomic_load_explicit(&sc->shared[j].lost, memory_order_acquire) == r + 1u)
            stale = (int)j;
    }
    if (returned)
        return ROZ_ELINK;
    if (stale >= 0) {
        sc->fault_joint = stale;
        sc->fault_kind = FAULT_SILENT;
        sc->fault_code = sc->cfg.joints[stale].can_id;
        return 0; /* state holds the frame read last */
    }
    memcpy(state, img, n * sizeof state[0]);
    if (!fr.fresh)
        return 0;
    for (size_t j = 0; j < sc->cfg.n_joints; j++) {
        uint32_t code = (uint32_t)img[meta(sc, j, META_ERROR)];
        uint32_t count = (uint32_t)img[meta(sc, j, META_INCONSISTENT)];
        if (code != 0 && sc->fault_joint < 0) {
            sc->fault_joint = (int)j;
            sc->fault_kind = FAULT_CODE;
            sc->fault_code = code;
        }
        if (count != sc->tick_inconsistent[j]) {
            sc->tick_inconsistent[j] = count;
            if (sc->fault_joint < 0) {
                sc->fault_joint = (int)j;
                sc->fault_kind = FAULT_CONSISTENCY;
                sc->fault_code = sc->cfg.joints[j].can_id;
            }
        }
    }
    return sc->fault_joint >= 0 ? ROZ_EROBOT : 1;
}

static int sc_read(void *self, double *state, size_t n)
{
    roz_socketcan_t *sc = self;

    if (!sc->opened || n != sc->m->n_states)
        return ROZ_EINVAL;
    int rc = read_frame(sc, state, n);
    /* a trip of the watchdog in place of a plain frame; after a link or
     * robot fault, at the next read */
    if ((rc == 0 || rc == 1) &&
        roz_cmd_watchdog_report(&sc->watchdog, now_ns(), &sc->fault_code)) {
        sc->fault_joint = 0;
        sc->fault_kind = FAULT_WATCHDOG;
        return ROZ_EWATCHDOG;
    }
    return rc;
}

static int sc_write(void *self, const double *cmd, size_t n)
{
    roz_socketcan_t *sc = self;
    uint32_t epoch;

    if (!sc->opened || n != sc->m->n_commands)
        return ROZ_EINVAL;
    bump(sc, C(writes), 1);
    uint64_t t = now_ns();
    int hold = roz_cmd_watchdog_write(&sc->watchdog, t, &epoch);
    double *f = roz_buffer_write_begin(&sc->cmd_buf);
    memcpy(f, cmd, n * sizeof cmd[0]);
    f[n] = epoch;
    f[n + 1u] = hold; /* back after a trip: a hold until every group got one */
    roz_buffer_write_commit(&sc->cmd_buf, t); /* the watchdog judges its age */
    if (sc->cfg.command_writer_period_us == 0)
        roz_socketcan_send_round(sc);
    return ROZ_OK;
}

static int sc_fault(void *self, roz_port_fault_t *out)
{
    roz_socketcan_t *sc = self;
    if (sc->fault_joint < 0)
        return ROZ_ENOENT;
    if (sc->fault_kind == FAULT_WATCHDOG) {
        out->what = ROZ_CMD_WATCHDOG_KEY;
        out->kind = "the tick wrote no command for (us)";
        out->code = sc->fault_code;
        out->limit = sc->cfg.command_timeout_us;
        return ROZ_OK;
    }
    out->limit = 0;
    out->what = sc->cfg.joints[sc->fault_joint].name;
    out->code = sc->fault_code;
    out->kind = sc->fault_kind == FAULT_CODE          ? "actuator error code"
                : sc->fault_kind == FAULT_CONSISTENCY ? sc->jump_text[sc->fault_joint]
                                                      : sc->stale_text[sc->fault_joint];
    return ROZ_OK;
}

static int sc_deactivate(void *self)
{
    roz_socketcan_t *sc = self;
    if (!sc->active)
        return ROZ_OK;
    if (sc->tx_started) {
        atomic_store_explicit(&sc->stop_tx, 1, memory_order_release);
        (void)sem_post(wake_sem(sc));
        pthread_join((pthread_t)sc->tx_thread, NULL);
        sc->tx_started = 0;
    }
    shutdown_frames(sc);
    if (sc->rx_started) {
        atomic_store_explicit(&sc->stop_rx, 1, memory_order_release);
        pthread_join((pthread_t)sc->rx_thread, NULL);
        sc->rx_started = 0;
    }
    sc->active = 0;
    return ROZ_OK;
}

static void sc_close(void *self)
{
    roz_socketcan_t *sc = self;
    if (!sc->opened)
        return;
    (void)sc_deactivate(sc);
    if (sc->own_fd)
        roz__can_close(sc->fd);
    sc->fd = -1;
    sc->own_fd = 0;
    if (sc->wake_ready)
        sem_destroy(wake_sem(sc));
    sc->wake_ready = 0;
    sc->opened = 0;
}

static int sc_link_counters(const void *self, roz_port_link_counters_t *out)
{
    roz_link_t l;
    roz_socketcan_link(self, &l);
    roz_link_port_counters(&l, 0, out);
    return ROZ_OK;
}

/* Opened: the bus the configuration gives; the summary: what went over it.
 * Start-up and shut-down only: this formats text. */
static int sc_report(const void *self, roz_port_report_when_t when, char *buf, size_t len)
{
    const roz_socketcan_t *sc = self;
    roz_socketcan_info_t info;
    roz_socketcan_info(sc, &info);
    if (when == ROZ_PORT_REPORT_OPENED)
        return snprintf(buf, len,
                        "socketcan: %u actuators on %s at %u kbit/s; rounds of %u us, %u group%s "
                        "(each actuator every %u us); worst-case bus load %.1f %%; an actuator "
                        "silent for %u us is stale; a tick silent for %u us, every actuator "
                        "held without gains",
                        (unsigned)info.n_joints, info.network_interface,
                        (unsigned)(info.bitrate / 1000u), (unsigned)info.round_us,
                        (unsigned)info.groups, info.groups == 1 ? "" : "s",
                        (unsigned)info.joint_interval_us, 100.0 * info.bus_load,
                        (unsigned)info.reply_timeout_us, (unsigned)info.command_timeout_us);
    roz_socketcan_counters_t c;
    roz_socketcan_counters(sc, &c);
    return snprintf(buf, len,
                    "CAN bus                %s, %u group%s, worst-case load %.1f %%; %llu frames "
                    "sent (%llu commands, %llu holds, %llu enter, %llu exit), %llu refused by "
                    "the socket\n"
                    "CAN replies            %llu taken, %llu with an error code, %llu "
                    "inconsistent; %llu unknown, %llu short, %llu bus errors (%llu bus-off); "
                    "actuators lost %llu times; %llu fields saturated",
                    info.network_interface, (unsigned)info.groups, info.groups == 1 ? "" : "s",
                    100.0 * info.bus_load, (unsigned long long)c.frames_sent,
                    (unsigned long long)c.commands_sent, (unsigned long long)c.holds_sent,
                    (unsigned long long)c.enter_sent, (unsigned long long)c.exit_sent,
                    (unsigned long long)c.send_errors, (unsigned long long)c.replies,
                    (unsigned long long)c.error_replies, (unsigned long long)c.inconsistent,
                    (unsigned long long)c.unknown, (unsigned long long)c.short_frames,
                    (unsigned long long)c.bus_errors, (unsigned long long)c.bus_off,
                    (unsigned long long)c.lost, (unsigned long long)c.saturated);
}

/* roz/port/can_config.h's table, one row a key. */
static const roz_port_param_info_t sc_params[] = {
    ROZ_PORT_PARAM_TEXT_ROW("can_id", "1..2047 per joint", "required",
                            "each actuator's 11-bit CAN id"),
    ROZ_PORT_PARAM_TEXT_ROW("reply", "basic|temperature_error", "required",
                            "the reply layout (roz/port/mit_codec.h)"),
    ROZ_PORT_PARAM_TEXT_ROW("position_range", "MIN:MAX", "required",
                            "the actuators' position range, rad"),
    ROZ_PORT_PARAM_TEXT_ROW("velocity_range", "MIN:MAX", "required",
                            "the actuators' velocity range, rad/s"),
    ROZ_PORT_PARAM_TEXT_ROW("stiffness_range", "MIN:MAX", "required",
                            "the actuators' kp range, N.m/rad"),
    ROZ_PORT_PARAM_TEXT_ROW("damping_range", "MIN:MAX", "required",
                            "the actuators' kd range, N.m.s/rad"),
    ROZ_PORT_PARAM_TEXT_ROW("effort_range", "MIN:MAX", "required",
                            "the actuators' torque range, N.m"),
    ROZ_PORT_PARAM_TEXT_ROW("direction", "1|-1 per joint", "1",
                            "-1: the actuator turns against the joint"),
    ROZ_PORT_PARAM_TEXT_ROW("zero_offset", "rad per joint", "0",
                            "the joint's position when the actuator reads 0"),
    ROZ_PORT_PARAM_TEXT_ROW("network_interface", "at most 15 bytes", "can0", "the CAN interface"),
    ROZ_PORT_PARAM_TEXT_ROW("bitrate", "10000..1000000", "1000000",
                            "the bus's bit rate as set on the interface"),
    ROZ_PORT_PARAM_TEXT_ROW("command_writer_period_us", "0, 100..1000000", "2000",
                            "the command writer's period; 0: a round when the tick writes"),
    ROZ_PORT_PARAM_TEXT_ROW("max_bus_load_percent", "10..100", "80",
                            "the share of the bus a period may take"),
    ROZ_PORT_PARAM_TEXT_ROW("reply_timeout_us", "1000..10000000", "20000 or three intervals",
                            "a command unanswered this long makes its joint stale"),
    ROZ_PORT_PARAM_TEXT_ROW("command_timeout_us", "1000..60000000",
                            "50000 or five intervals or ticks",
                            "the command watchdog: the tick silent this long, every actuator "
                            "held without gains"),
    ROZ_PORT_PARAM_TEXT_ROW("master_id", "0..2047", "0",
                            "the CAN id replies may come from besides the actuator's"),
    ROZ_PORT_PARAM_TEXT_ROW("consistency_margin", "rad, 0 = off", "0.2",
                            "a position that moves this much more than its velocity says is "
                            "a fault"),
    ROZ_PORT_PARAM_TEXT_ROW("enable_monitor", "true|false", "true", "jitter warnings"),
    ROZ_THREAD_PARAM_INFO("receive_thread", "the CAN receive thread"),
    ROZ_THREAD_PARAM_INFO("command_writer", "the CAN command writer thread"),
    ROZ_PORT_PARAM_TEXT_ROW("state_decimation", "1", "1", "every reply is converted"),
};

static const roz_port_info_t sc_info = {
    .summary = "CAN actuators speaking the MIT-mode frame, over Linux SocketCAN",
    .header = "roz/port/can_config.h",
    ROZ_PORT_INFO_PARAMS(sc_params),
    .no_sequence = "MIT-mode frames carry no sequence number: a rebooted actuator is seen only "
                   "as a silence longer than reply_timeout_us (the vanish case)",
};

/* The receive and send threads' warnings, said here (roz/port.h drain). */
static size_t sc_drain(void *self)
{
    roz_socketcan_t *sc = self;
    return roz_monitor_drain(&sc->monitor);
}

const roz_port_ops_t roz_socketcan_ops = {
    .name = "socketcan",
    .open = sc_open,
    .activate = sc_activate,
    .read = sc_read,
    .write = sc_write,
    .deactivate = sc_deactivate,
    .close = sc_close,
    .fault = sc_fault,
    .caps = ROZ_PORT_CAP_CRC | ROZ_PORT_CAP_WATCHDOG | ROZ_PORT_CAP_START_HOLD |
            ROZ_PORT_CAP_ROBOT | ROZ_PORT_CAP_NEEDS_NETNS,
    .info = &sc_info,
    .link_counters = sc_link_counters,
    .report = sc_report,
    .drain = sc_drain,
};

/* ---- public ---------------------------------------------------------------------- */

roz_port_t roz__socketcan_port(roz_socketcan_t *sc, const roz_port_layout_t *caller,
                               size_t bytes, roz_log_fn log, void *log_ctx)
{
    roz_port_t p = roz_port_make(&roz_socketcan_ops, sc, caller, bytes, sizeof *sc);
    if (p.self == NULL)
        return p; /* misbuilt: nothing written to *sc */
    if (!sc->opened)
        sc->given_fd = -1;
    sc->log = log;
    sc->log_ctx = log_ctx;
    return p;
}

void roz_socketcan_set_fd(roz_socketcan_t *sc, int fd)
{
    if (!sc->opened)
        sc->given_fd = fd;
}

void roz_socketcan_counters(const roz_socketcan_t *sc, roz_socketcan_counters_t *out)
{
    uint64_t v[sizeof *out / sizeof(uint64_t)];
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
        v[i] = atomic_load_explicit(&sc->n[i], memory_order_acquire);
    memcpy(out, v, sizeof *out);
    out->command_timeouts = roz_cmd_watchdog_trips(&sc->watchdog);
}

void roz_socketcan_link(const roz_socketcan_t *sc, roz_link_t *out)
{
    const roz_socketcan_t *s = sc;
    memset(out, 0, sizeof *out);
    roz_link_init(out, (uint64_t)sc->cfg.reply_timeout_us * NS_PER_US, 0);
    out->accepted = atomic_load_explicit(&s->link_n[L_ACCEPTED], memory_order_acquire);
    out->crc_errors = atomic_load_explicit(&s->link_n[L_CRC], memory_order_acquire);
    out->replays = atomic_load_explicit(&s->link_n[L_REPLAYS], memory_order_acquire);
    out->restarts = atomic_load_explicit(&s->link_n[L_RESTARTS], memory_order_acquire);
    out->returns = atomic_load_explicit(&s->link_n[L_RETURNS], memory_order_acquire);
    out->missing = atomic_load_explicit(&s->link_n[L_MISSING], memory_order_acquire);
    out->alive = out->accepted != 0;
}

void roz_socketcan_info(const roz_socketcan_t *sc, roz_socketcan_info_t *out)
{
    out->network_interface = sc->given_fd >= 0 ? "" : sc->cfg.network_interface;
    out->bitrate = sc->cfg.bitrate;
    out->round_us = sc->cfg.round_us;
    out->groups = sc->cfg.groups;
    out->joint_interval_us = sc->cfg.joint_interval_us;
    out->reply_timeout_us = sc->cfg.reply_timeout_us;
    out->command_timeout_us = sc->cfg.command_timeout_us;
    out->bus_load = sc->cfg.bus_load;
    out->n_joints = sc->cfg.n_joints;
}

void roz_socketcan_send_round(roz_socketcan_t *sc)
{
    if (sc->cfg.command_writer_period_us != 0 || !sc->wake_ready)
        return;
    atomic_fetch_add_explicit(&sc->n[C(wakes)], 1, memory_order_acq_rel);
    (void)sem_post(wake_sem(sc));
}

const roz_monitor_t *roz_socketcan_monitor(const roz_socketcan_t *sc)
{
    return &sc->monitor;
}
