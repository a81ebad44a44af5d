/* SPDX-License-Identifier: Apache-2.0 */
/* fake_g1: a stand-in Unitree G1 on Cyclone DDS for roz's tests, written
 * from the robot's wire description alone (README.md). It publishes
 * LowState_ on rt/lowstate when told to (or every --period-us), receives
 * LowCmd_ on rt/lowcmd, checks each command's CRC as the robot does and
 * keeps the last good one; a test drives it over stdin/stdout, one request
 * line in, one reply line out. With --unitree-mujoco it behaves as Unitree's
 * simulator does on the same topics (README.md, "As unitree_mujoco").
 *
 * Threads: main (requests, publishing), the command reader (a waitset on
 * rt/lowcmd), the periodic publisher (with --period-us). Lock order:
 * pub_lock before lock; dds_write is never called under lock, which the
 * command reader takes. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <inttypes.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <dds/dds.h>

#include "fake_reply.h"
#include "g1_dds.h"
#include "g1_frame.h"
#include "g1_request.h"

#define STATE_TOPIC "rt/lowstate"
#define CMD_TOPIC "rt/lowcmd"
#define RX_BATCH 16
#define DEFAULT_MODE_MACHINE 5u /* 29-DoF rev 1.0 */
#define MIN_PERIOD_US 100u /* 10 kHz, 20 times the robot's rate */
#define MAX_PERIOD_US 1000000u
/* After a restart, how long the new state writer may take to meet the
 * readers the old one had (polled every millisecond). */
#define REMATCH_POLLS 5000

/* Good commands kept for command_at: 4 s of a 500 Hz stream. */
#define HISTORY 2048

typedef struct fake {
    dds_entity_t participant, state_topic, cmd_topic, cmd_reader;
    dds_entity_t waitset, stop_guard;
    dds_qos_t *state_qos;
    uint32_t period_us;
    int sim; /* --unitree-mujoco */
    struct timespec pause_until; /* the periodic publisher is silent until then; lock */

    /* publishing; pub_lock */
    pthread_mutex_t pub_lock;
    dds_entity_t state_writer;
    uint32_t next_tick;
    int have_sent;
    g1_lowstate_t last_sent; /* the last good frame, byte for byte */
    g1_lowstate_t frame;

    /* the robot's model and what it received; lock */
    pthread_mutex_t lock;
    pthread_cond_t changed; /* a command counted, or stopping */
    g1_lowstate_t model;
    uint64_t good, bad_crc;
    int have_cmd;
    g1_lowcmd_t last_cmd;
    g1_lowcmd_t history[HISTORY]; /* good command K at (K - 1) % HISTORY */
    int flip_next;
    int stopping;

    pthread_t reader_thread, period_thread;
    int reader_running, period_running;
    g1_lowcmd_t rx[RX_BATCH]; /* the reader thread's */
} fake_t;

static fake_t fake;

/* ---- time ---------------------------------------------------------------- */

static void deadline_after(struct timespec *t, uint64_t us)
{
    t->tv_sec += (time_t)(us / 1000000u);
    t->tv_nsec += (long)(us % 1000000u) * 1000L;
    if (t->tv_nsec >= 1000000000L) {
        t->tv_sec++;
        t->tv_nsec -= 1000000000L;
    }
}

static int before(const struct timespec *a, const struct timespec *b)
{
    return a->tv_sec < b->tv_sec || (a->tv_sec == b->tv_sec && a->tv_nsec < b->tv_nsec);
}

/* ---- state frames -------------------------------------------------------- */

typedef enum { FRAME_GOOD, FRAME_CORRUPT } frame_kind_t;

/* One bit flipped after the CRC, as in transit: the lowest bit of motor 0's
 * position, a change a receiver without the CRC would take silently. */
static void flip_one_bit(g1_lowstate_t *frame)
{
    uint32_t bits;
    memcpy(&bits, &frame->motor_state[0].q, sizeof bits);
    bits ^= 1u;
    memcpy(&frame->motor_state[0].q, &bits, sizeof bits);
}

/* Publish the next frame (it takes the next tick, a corrupt one too: the
 * robot sent it, the wire spoiled it). */
static int publish(fake_t *f, frame_kind_t kind, uint32_t *tick, char *err, size_t errlen)
{
    int rc = 0;
    pthread_mutex_lock(&f->pub_lock);
    pthread_mutex_lock(&f->lock);
    if (f->sim) /* the simulator sets none of tick, crc, mode_machine */
        g1_lowstate_copy(&f->frame, &f->model);
    else
        g1_state_frame(&f->frame, &f->model, f->next_tick);
    pthread_mutex_unlock(&f->lock);
    if (kind == FRAME_CORRUPT)
        flip_one_bit(&f->frame);
    dds_return_t r = dds_write(f->state_writer, &f->frame);
    if (r < 0) {
        snprintf(err, errlen, "write on %s: %s", STATE_TOPIC, dds_strretcode(r));
        rc = -1;
    } else {
        *tick = f->next_tick++;
        if (kind == FRAME_GOOD) {
            memcpy(&f->last_sent, &f->frame, sizeof f->last_sent);
            f->have_sent = 1;
        }
    }
    pthread_mutex_unlock(&f->pub_lock);
    return rc;
}

static int replay(fake_t *f, uint32_t *tick, char *err, size_t errlen)
{
    int rc = 0;
    pthread_mutex_lock(&f->pub_lock);
    if (!f->have_sent) {
        snprintf(err, errlen, "nothing sent yet");
        rc = -1;
    } else {
        dds_return_t r = dds_write(f->state_writer, &f->last_sent);
        if (r < 0) {
            snprintf(err, errlen, "write on %s: %s", STATE_TOPIC, dds_strretcode(r));
            rc = -1;
        }
        *tick = f->last_sent.tick;
    }
    pthread_mutex_unlock(&f->pub_lock);
    return rc;
}

static uint32_t readers_matched(dds_entity_t writer)
{
    dds_publication_matched_status_t st;
    return dds_get_publication_matched_status(writer, &st) < 0 ? 0u : st.current_count;
}

static uint32_t writers_matched(dds_entity_t reader)
{
    dds_subscription_matched_status_t st;
    return dds_get_subscription_matched_status(reader, &st) < 0 ? 0u : st.current_count;
}

/* The robot restarts: a new state writer (a new DDS identity, as after a
 * boot), the tick from 0, the last command forgotten; the counters stay. */
static int restart(fake_t *f, char *err, size_t errlen)
{
    int rc = 0;
    pthread_mutex_lock(&f->pub_lock);
    uint32_t had = readers_matched(f->state_writer);
    (void)dds_delete(f->state_writer);
    f->state_writer = dds_create_writer(f->participant, f->state_topic, f->state_qos, NULL);
    if (f->state_writer < 0) {
        snprintf(err, errlen, "new writer on %s: %s", STATE_TOPIC,
                 dds_strretcode(f->state_writer));
        rc = -1;
    } else {
        /* its first frame should reach the readers the old writer had */
        const struct timespec ms = { 0, 1000000L };
        for (int i = 0; i < REMATCH_POLLS && readers_matched(f->state_writer) < had; i++)
            nanosleep(&ms, NULL);
        if (readers_matched(f->state_writer) < had)
            fprintf(stderr, "fake_g1: restart: the new writer met %u of %u readers\n",
                    readers_matched(f->state_writer), had);
    }
    f->next_tick = 0;
    pthread_mutex_lock(&f->lock);
    f->have_cmd = 0;
    pthread_mutex_unlock(&f->lock);
    pthread_mutex_unlock(&f->pub_lock);
    return rc;
}

/* ---- as unitree_mujoco ---------------------------------------------------- */

/* One step of @p dt s, as the simulator applies a command: each motor's
 * torque tau + kp (q_cmd - q) + kd (dq_cmd - dq) from the last command
 * received, kept while no new one comes, whatever its mode; here on a unit
 * inertia per joint, no gravity, no contact. Under lock. */
static void sim_step(fake_t *f, double dt)
{
    if (!f->have_cmd)
        return;
    for (size_t i = 0; i < G1_MOTORS; i++) {
        const g1_motorcmd_t *c = &f->last_cmd.motor_cmd[i];
        g1_motorstate_t *m = &f->model.motor_state[i];
        double q = m->q, dq = m->dq;
        double tau = (double)c->tau + (double)c->kp * ((double)c->q - q) +
                     (double)c->kd * ((double)c->dq - dq);
        dq += tau * dt; /* semi-implicit Euler */
        q += dq * dt;
        m->q = (float)q;
        m->dq = (float)dq;
        m->tau_est = (float)tau;
    }
}

/* ---- the periodic publisher ---------------------------------------------- */

static void *period_main(void *arg)
{
    fake_t *f = arg;
    struct timespec next;
    char err[160];
    clock_gettime(CLOCK_MONOTONIC, &next);
    pthread_mutex_lock(&f->lock);
    while (!f->stopping) {
        deadline_after(&next, f->period_us);
        int r = 0;
        while (!f->stopping && r != ETIMEDOUT)
            r = pthread_cond_timedwait(&f->changed, &f->lock, &next);
        if (f->stopping)
            break;
        if (f->sim)
            sim_step(f, f->period_us * 1e-6);
        struct timespec at;
        clock_gettime(CLOCK_MONOTONIC, &at);
        int paused = before(&at, &f->pause_until);
        pthread_mutex_unlock(&f->lock);
        uint32_t tick;
        if (!paused && publish(f, FRAME_GOOD, &tick, err, sizeof err) != 0)
            fprintf(stderr, "fake_g1: periodic frame: %s\n", err);
        struct timespec now;
        clock_gettime(CLOCK_MONOTONIC, &now);
        if (before(&next, &now)) /* late: go on from now, no burst */
            next = now;
        pthread_mutex_lock(&f->lock);
    }
    pthread_mutex_unlock(&f->lock);
    return NULL;
}

/* ---- the command reader -------------------------------------------------- */

static void take_commands(fake_t *f)
{
    void *ptrs[RX_BATCH];
    dds_sample_info_t info[RX_BATCH];
    for (;;) {
        for (size_t i = 0; i < RX_BATCH; i++)
            ptrs[i] = &f->rx[i];
        dds_return_t n = dds_take(f->cmd_reader, ptrs, info, RX_BATCH, RX_BATCH);
        if (n <= 0)
            return;
        pthread_mutex_lock(&f->lock);
        for (dds_return_t i = 0; i < n; i++) {
            if (!info[i].valid_data)
                continue;
            /* a flipped bit fails the CRC, whichever bit it is; the
             * simulator looks at no CRC */
            int ok = !f->flip_next && (f->sim || g1_lowcmd_crc_ok(&f->rx[i]));
            f->flip_next = 0;
            if (ok) {
                f->good++;
                memcpy(&f->last_cmd, &f->rx[i], sizeof f->last_cmd);
                memcpy(&f->history[(f->good - 1u) % HISTORY], &f->rx[i], sizeof f->last_cmd);
                f->have_cmd = 1;
            } else {
                f->bad_crc++; /* the robot drops it without a word */
            }
        }
        pthread_cond_broadcast(&f->changed);
        pthread_mutex_unlock(&f->lock);
    }
}

static void *reader_main(void *arg)
{
    fake_t *f = arg;
    for (;;) {
        dds_return_t r = dds_waitset_wait(f->waitset, NULL, 0, DDS_INFINITY);
        pthread_mutex_lock(&f->lock);
        int stop = f->stopping;
        pthread_mutex_unlock(&f->lock);
        if (stop)
            break;
        if (r < 0) {
            fprintf(stderr, "fake_g1: waiting for commands: %s\n", dds_strretcode(r));
            break;
        }
        take_commands(f);
    }
    return NULL;
}

/* ---- requests ------------------------------------------------------------ */

static int wait_commands(fake_t *f, uint64_t n, uint64_t timeout_ms, uint64_t *good)
{
    struct timespec until;
    clock_gettime(CLOCK_MONOTONIC, &until);
    deadline_after(&until, timeout_ms * 1000u);
    pthread_mutex_lock(&f->lock);
    int r = 0;
    while (f->good < n && r != ETIMEDOUT)
        r = pthread_cond_timedwait(&f->changed, &f->lock, &until);
    *good = f->good;
    pthread_mutex_unlock(&f->lock);
    return *good >= n ? 0 : -1;
}

/* The last good command (k = 0), or good command number k (1, 2, ...)
 * while it is among the last HISTORY. */
static int reply_command(fake_t *f, uint64_t k)
{
    g1_lowcmd_t c;
    pthread_mutex_lock(&f->lock);
    int have = k == 0 ? f->have_cmd : k <= f->good && f->good - k < HISTORY;
    uint64_t good = f->good;
    memcpy(&c, k == 0 ? &f->last_cmd : &f->history[(k - 1u) % HISTORY], sizeof c);
    pthread_mutex_unlock(&f->lock);
    if (!have && k == 0)
        return reply("err none");
    if (!have)
        return reply("err command_at %" PRIu64 ": not kept (good commands: %" PRIu64
                     ", the last %u kept)",
                     k, good, (unsigned)HISTORY);
    /* 35 groups of at most 4 + 5 * 25 characters */
    char out[8192];
    size_t len = (size_t)snprintf(out, sizeof out, "ok %u %u", (unsigned)c.mode_pr,
                                  (unsigned)c.mode_machine);
    for (size_t i = 0; i < G1_MOTORS && len < sizeof out; i++) {
        const g1_motorcmd_t *m = &c.motor_cmd[i];
        len += (size_t)snprintf(out + len, sizeof out - len, " %u %.17g %.17g %.17g %.17g %.17g",
                                (unsigned)m->mode, (double)m->q, (double)m->dq, (double)m->tau,
                                (double)m->kp, (double)m->kd);
    }
    return reply("%s", out);
}

/* The remote's data as Unitree's SDK declares it (its rocker-and-button
 * struct, the first 24 of LowState_.wireless_remote's 40 bytes): two
 * header bytes, the key union of sixteen one-bit fields in the SDK's order
 * and with its names, five floats, the rest unused. The robot copies its
 * memory image (little-endian, checked in g1_frame.h). A key is set by
 * its name, as the SDK's users set it: where its bit lands is the
 * compiler's bit-field layout, as on the robot, never roz's numbering. */
typedef struct fake_remote {
    uint8_t head[2];
    union {
        struct {
            uint8_t R1 : 1;
            uint8_t L1 : 1;
            uint8_t start : 1;
            uint8_t select : 1;
            uint8_t R2 : 1;
            uint8_t L2 : 1;
            uint8_t F1 : 1;
            uint8_t F2 : 1;
            uint8_t A : 1;
            uint8_t B : 1;
            uint8_t X : 1;
            uint8_t Y : 1;
            uint8_t up : 1;
            uint8_t right : 1;
            uint8_t down : 1;
            uint8_t left : 1;
        } components;
        uint16_t value;
    } btn;
    float lx, rx, ry, l2, ly;
    uint8_t idle[16];
} fake_remote_t;
_Static_assert(sizeof(fake_remote_t) == 40 && offsetof(fake_remote_t, btn) == 2 &&
                   offsetof(fake_remote_t, lx) == 4 && offsetof(fake_remote_t, ly) == 20,
               "the SDK's remote layout");

/* Presses the key the SDK names @p name. */
static void press_key(fake_remote_t *r, const char *name)
{
#define KEY(n)                                                                          \
    if (strcmp(name, #n) == 0)                                                          \
        r->btn.components.n = 1;
    KEY(R1) KEY(L1) KEY(start) KEY(select) KEY(R2) KEY(L2) KEY(F1) KEY(F2)
    KEY(A) KEY(B) KEY(X) KEY(Y) KEY(up) KEY(right) KEY(down) KEY(left)
#undef KEY
}

/* Carry out one request and reply; 1 when the fake should stop, -1 when
 * stdout is gone. */
static int handle(fake_t *f, const g1_request_t *q)
{
    char err[200];
    uint32_t tick = 0;
    switch (q->kind) {
    case G1_REQ_MOTOR: {
        pthread_mutex_lock(&f->lock);
        g1_motorstate_t *m = &f->model.motor_state[q->u[0]];
        m->q = (float)q->f[0];
        m->dq = (float)q->f[1];
        m->tau_est = (float)q->f[2];
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    case G1_REQ_MOTORSTATE:
        pthread_mutex_lock(&f->lock);
        f->model.motor_state[q->u[0]].motorstate = (uint32_t)q->u[1];
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    case G1_REQ_IMU: {
        pthread_mutex_lock(&f->lock);
        g1_imustate_t *imu = &f->model.imu_state;
        for (size_t i = 0; i < 4; i++)
            imu->quaternion[i] = (float)q->f[i];
        for (size_t i = 0; i < 3; i++) {
            imu->gyroscope[i] = (float)q->f[4 + i];
            imu->accelerometer[i] = (float)q->f[7 + i];
        }
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    case G1_REQ_REMOTE: {
        /* as Unitree's SDK fills it: its remote struct's memory image */
        fake_remote_t r;
        memset(&r, 0, sizeof r);
        for (int k = 0; k < G1_REMOTE_KEYS; k++)
            if ((q->u[0] >> k & 1u) != 0)
                press_key(&r, g1_remote_key_names[k]);
        r.lx = (float)q->f[0];
        r.rx = (float)q->f[1];
        r.ry = (float)q->f[2];
        r.l2 = (float)q->f[3];
        r.ly = (float)q->f[4];
        pthread_mutex_lock(&f->lock);
        memcpy(f->model.wireless_remote, &r, sizeof r);
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    case G1_REQ_MODE_MACHINE:
        pthread_mutex_lock(&f->lock);
        f->model.mode_machine = (uint8_t)q->u[0];
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    case G1_REQ_MODE_PR:
        pthread_mutex_lock(&f->lock);
        f->model.mode_pr = (uint8_t)q->u[0];
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    case G1_REQ_SEND:
        if (publish(f, FRAME_GOOD, &tick, err, sizeof err) != 0)
            return reply("err send: %s", err);
        return reply("ok %" PRIu32, tick);
    case G1_REQ_CORRUPT:
        if (publish(f, FRAME_CORRUPT, &tick, err, sizeof err) != 0)
            return reply("err corrupt: %s", err);
        return reply("ok %" PRIu32, tick);
    case G1_REQ_REPLAY:
        if (replay(f, &tick, err, sizeof err) != 0)
            return reply("err replay: %s", err);
        return reply("ok %" PRIu32, tick);
    case G1_REQ_RESTART:
        if (restart(f, err, sizeof err) != 0)
            return reply("err restart: %s", err);
        return reply("ok");
    case G1_REQ_SILENT:
        return reply("ok");
    case G1_REQ_COMMANDS: {
        pthread_mutex_lock(&f->lock);
        uint64_t good = f->good, bad = f->bad_crc;
        pthread_mutex_unlock(&f->lock);
        return reply("ok %" PRIu64 " %" PRIu64, good, bad);
    }
    case G1_REQ_WAIT_COMMANDS: {
        uint64_t good;
        if (wait_commands(f, q->u[0], q->u[1], &good) != 0)
            return reply("err timeout %" PRIu64, good);
        return reply("ok %" PRIu64, good);
    }
    case G1_REQ_COMMAND:
        return reply_command(f, 0);
    case G1_REQ_COMMAND_AT:
        return reply_command(f, q->u[0] != 0 ? q->u[0] : UINT64_MAX);
    case G1_REQ_FLIP_NEXT:
        pthread_mutex_lock(&f->lock);
        f->flip_next = 1;
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    case G1_REQ_MATCHED: {
        /* discovery seen from this side: the writers its command reader
         * matched, the readers its state writer matched */
        pthread_mutex_lock(&f->pub_lock);
        uint32_t w = writers_matched(f->cmd_reader), r = readers_matched(f->state_writer);
        pthread_mutex_unlock(&f->pub_lock);
        return reply("ok %" PRIu32 " %" PRIu32, w, r);
    }
    case G1_REQ_PAUSE: {
        struct timespec until;
        clock_gettime(CLOCK_MONOTONIC, &until);
        deadline_after(&until, q->u[0] * 1000u);
        pthread_mutex_lock(&f->lock);
        f->pause_until = until;
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    case G1_REQ_MOTOR_STATE: {
        pthread_mutex_lock(&f->lock);
        g1_motorstate_t m = f->model.motor_state[q->u[0]];
        pthread_mutex_unlock(&f->lock);
        return reply("ok %.17g %.17g %.17g", (double)m.q, (double)m.dq, (double)m.tau_est);
    }
    case G1_REQ_QUIT:
        return reply("ok") != 0 ? -1 : 1;
    }
    return reply("err internal: request kind %d", (int)q->kind);
}

typedef enum { LINE_OK, LINE_LONG, LINE_NUL, LINE_EOF } line_t;

/* One line of stdin into @p buf (without its newline); a line too long or
 * with a NUL byte is read to its end and reported. A last line without a
 * newline counts. */
static line_t read_line(char *buf, size_t cap)
{
    size_t n = 0;
    int c, any = 0, too_long = 0, nul = 0;
    while ((c = getchar()) != EOF) {
        any = 1;
        if (c == '\n')
            break;
        if (c == '\0')
            nul = 1;
        else if (n + 1 < cap)
            buf[n++] = (char)c;
        else
            too_long = 1;
    }
    buf[n] = '\0';
    if (!any)
        return LINE_EOF;
    return nul ? LINE_NUL : too_long ? LINE_LONG : LINE_OK;
}

static int serve(fake_t *f)
{
    char line[G1_REQ_MAX_LINE + 1];
    char err[200];
    g1_request_t q;
    for (;;) {
        line_t got = read_line(line, sizeof line);
        int r;
        if (got == LINE_EOF)
            return 0;
        if (got == LINE_LONG)
            r = reply("err request longer than %d bytes", G1_REQ_MAX_LINE);
        else if (got == LINE_NUL)
            r = reply("err request contains a NUL byte");
        else if (g1_request_parse(line, &q, err, sizeof err) != 0)
            r = reply("err %s", err);
        else
            r = handle(f, &q);
        if (r == 1)
            return 0;
        if (r != 0) {
            fprintf(stderr, "fake_g1: stdout is gone\n");
            return 1;
        }
    }
}

/* ---- set-up and tear-down ------------------------------------------------ */

static void usage(FILE *to)
{
    fprintf(to, "usage: fake_g1 --domain N [--interface lo] [--mode-machine M] [--period-us P]\n"
                "               [--allow-any-interface] [--unitree-mujoco]\n"
                "A fake Unitree G1 on Cyclone DDS; requests on stdin (see README.md).\n");
}

typedef struct options {
    uint32_t domain;
    int have_domain;
    const char *iface;
    uint32_t mode_machine;
    uint32_t period_us;
    int any_iface;
    int sim;
} options_t;

static int number_arg(const char *opt, const char *val, uint32_t max, uint32_t *out)
{
    char *end;
    if (val == NULL || val[0] < '0' || val[0] > '9') {
        fprintf(stderr, "fake_g1: %s wants a number 0..%u\n", opt, max);
        return -1;
    }
    errno = 0;
    unsigned long long v = strtoull(val, &end, 10);
    if (errno != 0 || *end != '\0' || v > max) {
        fprintf(stderr, "fake_g1: %s '%s' is not a number 0..%u\n", opt, val, max);
        return -1;
    }
    *out = (uint32_t)v;
    return 0;
}

static int parse_options(int argc, char **argv, options_t *o)
{
    *o = (options_t){ .iface = "lo", .mode_machine = DEFAULT_MODE_MACHINE };
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int rc = 0;
        if (strcmp(a, "--domain") == 0) {
            rc = number_arg(a, v, G1_DDS_MAX_DOMAIN, &o->domain);
            o->have_domain = 1;
            i++;
        } else if (strcmp(a, "--interface") == 0) {
            if (v == NULL || !g1_dds_iface_valid(v)) {
                fprintf(stderr, "fake_g1: --interface wants an interface name\n");
                rc = -1;
            }
            o->iface = v;
            i++;
        } else if (strcmp(a, "--mode-machine") == 0) {
            rc = number_arg(a, v, 255u, &o->mode_machine);
            i++;
        } else if (strcmp(a, "--period-us") == 0) {
            rc = number_arg(a, v, MAX_PERIOD_US, &o->period_us);
            if (rc == 0 && o->period_us > 0 && o->period_us < MIN_PERIOD_US) {
                fprintf(stderr, "fake_g1: --period-us %u is not 0 (off) or %u..%u\n",
                        o->period_us, MIN_PERIOD_US, MAX_PERIOD_US);
                rc = -1;
            }
            i++;
        } else if (strcmp(a, "--allow-any-interface") == 0) {
            o->any_iface = 1;
        } else if (strcmp(a, "--unitree-mujoco") == 0) {
            o->sim = 1;
        } else if (strcmp(a, "--help") == 0) {
            usage(stdout);
            exit(0);
        } else {
            fprintf(stderr, "fake_g1: unknown option '%s'\n", a);
            rc = -1;
        }
        if (rc != 0)
            return -1;
    }
    if (!o->have_domain) {
        fprintf(stderr, "fake_g1: --domain is required\n");
        return -1;
    }
    if (strcmp(o->iface, "lo") != 0 && !o->any_iface) {
        fprintf(stderr, "fake_g1: --interface %s refused: the fake robot stays on lo unless "
                        "--allow-any-interface is given\n", o->iface);
        return -1;
    }
    return 0;
}

static int dds_fail(const char *what, dds_return_t r)
{
    fprintf(stderr, "fake_g1: %s: %s\n", what, dds_strretcode(r));
    return -1;
}

static int start(fake_t *f, const options_t *o)
{
    char err[200];
    f->participant = g1_dds_participant(o->domain, o->iface, err, sizeof err);
    if (f->participant < 0) {
        fprintf(stderr, "fake_g1: %s\n", err);
        return -1;
    }
    f->state_topic = dds_create_topic(f->participant, &unitree_hg_msg_dds__LowState__desc,
                                      STATE_TOPIC, NULL, NULL);
    if (f->state_topic < 0)
        return dds_fail("topic " STATE_TOPIC, f->state_topic);
    f->cmd_topic = dds_create_topic(f->participant, &unitree_hg_msg_dds__LowCmd__desc, CMD_TOPIC,
                                    NULL, NULL);
    if (f->cmd_topic < 0)
        return dds_fail("topic " CMD_TOPIC, f->cmd_topic);

    /* State: RELIABLE, the latest frame only (unitree_ros2 reads it with
     * ROS 2's default RELIABLE reader and works, so the robot offers it). */
    f->state_qos = dds_create_qos();
    dds_qset_reliability(f->state_qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_history(f->state_qos, DDS_HISTORY_KEEP_LAST, 1);
    dds_qset_durability(f->state_qos, DDS_DURABILITY_VOLATILE);
    f->state_writer = dds_create_writer(f->participant, f->state_topic, f->state_qos, NULL);
    if (f->state_writer < 0)
        return dds_fail("writer on " STATE_TOPIC, f->state_writer);

    /* Commands: BEST_EFFORT matches any writer, reliable or not (the
     * robot's own reader QoS is not published); KEEP_ALL so that every
     * sample is counted. */
    dds_qos_t *rq = dds_create_qos();
    dds_qset_reliability(rq, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(rq, DDS_HISTORY_KEEP_ALL, 0);
    dds_qset_durability(rq, DDS_DURABILITY_VOLATILE);
    f->cmd_reader = dds_create_reader(f->participant, f->cmd_topic, rq, NULL);
    dds_delete_qos(rq);
    if (f->cmd_reader < 0)
        return dds_fail("reader on " CMD_TOPIC, f->cmd_reader);

    f->waitset = dds_create_waitset(f->participant);
    if (f->waitset < 0)
        return dds_fail("waitset", f->waitset);
    dds_entity_t rc = dds_create_readcondition(f->cmd_reader, DDS_ANY_STATE);
    if (rc < 0)
        return dds_fail("read condition", rc);
    f->stop_guard = dds_create_guardcondition(f->participant);
    if (f->stop_guard < 0)
        return dds_fail("guard condition", f->stop_guard);
    dds_return_t r = dds_waitset_attach(f->waitset, rc, 0);
    if (r >= 0)
        r = dds_waitset_attach(f->waitset, f->stop_guard, 1);
    if (r < 0)
        return dds_fail("waitset attach", r);

    if (pthread_create(&f->reader_thread, NULL, reader_main, f) != 0) {
        fprintf(stderr, "fake_g1: cannot start the command reader thread\n");
        return -1;
    }
    f->reader_running = 1;
    if (f->period_us > 0) {
        if (pthread_create(&f->period_thread, NULL, period_main, f) != 0) {
            fprintf(stderr, "fake_g1: cannot start the periodic publisher thread\n");
            return -1;
        }
        f->period_running = 1;
    }
    return 0;
}

static void stop(fake_t *f)
{
    pthread_mutex_lock(&f->lock);
    f->stopping = 1;
    pthread_cond_broadcast(&f->changed);
    pthread_mutex_unlock(&f->lock);
    if (f->stop_guard > 0)
        (void)dds_set_guardcondition(f->stop_guard, true);
    if (f->period_running)
        pthread_join(f->period_thread, NULL);
    if (f->reader_running)
        pthread_join(f->reader_thread, NULL);
    if (f->state_qos != NULL)
        dds_delete_qos(f->state_qos);
    (void)dds_delete(DDS_CYCLONEDDS_HANDLE);
}

int main(int argc, char **argv)
{
    options_t o;
    fake_t *f = &fake;
    signal(SIGPIPE, SIG_IGN); /* a closed stdout is an error reply, not a crash */
    if (parse_options(argc, argv, &o) != 0) {
        usage(stderr);
        return 2;
    }

    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&f->changed, &ca);
    pthread_condattr_destroy(&ca);
    pthread_mutex_init(&f->lock, NULL);
    pthread_mutex_init(&f->pub_lock, NULL);

    /* the robot at rest, upright: an identity attitude, nothing moving */
    memset(&f->model, 0, sizeof f->model);
    f->model.mode_machine = o.sim ? 0u : (uint8_t)o.mode_machine;
    f->model.imu_state.quaternion[0] = 1.0f;
    f->period_us = o.period_us;
    f->sim = o.sim;

    int rc = start(f, &o);
    if (rc == 0 && reply("ready") != 0)
        rc = -1;
    if (rc == 0)
        rc = serve(f);
    stop(f);
    return rc == 0 ? 0 : 1;
}
