/* SPDX-License-Identifier: Apache-2.0 */
/* MIT-mode actuators on a bus, for tests (fake_can.h, README.md). */
#define _DEFAULT_SOURCE
#include "fake_can.h"

#include <errno.h>
#include <math.h>
#include <net/if.h>
#include <poll.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/raw.h>

static const unsigned widths[FAKE_FIELDS] = { 16, 12, 12, 12, 12 };

/* ---- the protocol, from its description ---------------------------------------- */

/* value -> code: nearest step, halves away from min; saturated at the ends */
static uint16_t to_code(double x, const double r[2], unsigned bits)
{
    double top = (double)((1u << bits) - 1u);
    if (!(x > r[0]))
        return 0;
    if (x >= r[1])
        return (uint16_t)top;
    return (uint16_t)floor((x - r[0]) / (r[1] - r[0]) * top + 0.5);
}

static double from_code(uint16_t c, const double r[2], unsigned bits)
{
    double top = (double)((1u << bits) - 1u);
    return r[0] + (double)c / top * (r[1] - r[0]);
}

/* Bits [at, at+width) of the frame, most significant first. */
static uint16_t bits_of(const uint8_t *d, unsigned at, unsigned width)
{
    uint32_t v = 0;
    for (unsigned i = 0; i < width; i++) {
        unsigned b = at + i;
        v = (v << 1) | ((d[b / 8] >> (7 - b % 8)) & 1u);
    }
    return (uint16_t)v;
}

static void put_bits(uint8_t *d, unsigned at, unsigned width, uint16_t v)
{
    for (unsigned i = 0; i < width; i++) {
        unsigned b = at + i;
        uint8_t bit = (uint8_t)((v >> (width - 1 - i)) & 1u);
        d[b / 8] = (uint8_t)((d[b / 8] & ~(1u << (7 - b % 8))) | (bit << (7 - b % 8)));
    }
}

int fake_can_pack_reply(const fake_actuator_cfg_t *c, double q, double dq, double tau,
                        uint8_t error, uint8_t out[8])
{
    memset(out, 0, 8);
    out[0] = (uint8_t)(c->can_id & 0xFFu);
    put_bits(out, 8, 16, to_code(q, c->range[FAKE_P], 16));
    put_bits(out, 24, 12, to_code(dq, c->range[FAKE_V], 12));
    put_bits(out, 36, 12, to_code(tau, c->range[FAKE_T], 12));
    if (c->layout == FAKE_TEMP_ERROR) {
        out[6] = 40; /* a warm actuator, in whatever scale */
        out[7] = error;
        return 8;
    }
    return 6;
}

static int send_frame(int fd, uint32_t id, const uint8_t *data, uint8_t len)
{
    struct can_frame f;
    memset(&f, 0, sizeof f);
    f.can_id = id;
    f.can_dlc = len;
    memcpy(f.data, data, len);
    return send(fd, &f, sizeof f, MSG_NOSIGNAL) == (ssize_t)sizeof f ? 0 : -1;
}

/* ---- the actuators (under the lock) --------------------------------------------- */

static int all_replied(const fake_can_t *bus)
{
    for (unsigned j = 0; j < bus->n; j++) {
        if (bus->act[j].replies == 0)
            return 0;
    }
    return 1;
}

static void log_kind(fake_can_t *bus, unsigned j, char kind)
{
    if (bus->n_log < FAKE_CAN_LOG) {
        bus->log[bus->n_log][0] = (char)('0' + j);
        bus->log[bus->n_log][1] = kind;
        bus->n_log++;
    }
}

static void reply(fake_can_t *bus, unsigned j)
{
    fake_actuator_t *a = &bus->act[j];
    uint8_t d[8];
    int len;
    if (a->frozen && a->last_reply_len > 0) {
        memcpy(d, a->last_reply, 8);
        len = a->last_reply_len;
    } else {
        len = fake_can_pack_reply(&a->cfg, a->q + a->jump, a->dq, a->tau, a->error, d);
    }
    if (send_frame(bus->fd, a->cfg.reply_id, d, (uint8_t)len) == 0) {
        memcpy(a->last_reply, d, 8);
        a->last_reply_len = len;
        a->replies++;
    }
}

/* One simulated step of the joint under the command (unit-ish inertia,
 * light friction); the torque is the actuator's, clamped to its range. */
static void step(fake_actuator_t *a, double dt)
{
    const double inertia = 0.05, friction = 0.2;
    if (a->motor_mode && a->have_cmd) {
        double tau = a->cmd[FAKE_KP] * (a->cmd[FAKE_P] - a->q) +
                     a->cmd[FAKE_KD] * (a->cmd[FAKE_V] - a->dq) + a->cmd[FAKE_T];
        a->tau = fmin(fmax(tau, a->cfg.range[FAKE_T][0]), a->cfg.range[FAKE_T][1]);
    } else {
        a->tau = 0.0;
    }
    a->dq += (a->tau - friction * a->dq) / inertia * dt;
    a->q += a->dq * dt;
}

static void on_frame(fake_can_t *bus, const struct can_frame *f)
{
    bus->received++;
    if (f->can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG))
        goto stray;
    for (unsigned j = 0; j < bus->n; j++) {
        fake_actuator_t *a = &bus->act[j];
        if (f->can_id != a->cfg.can_id)
            continue;
        a->frames++;
        if (a->drop_next) { /* refused by the controller: as if never sent */
            a->drop_next = 0;
            a->dropped++;
            return;
        }
        int special = f->can_dlc == 8;
        for (int i = 0; i < 7 && special; i++)
            special = f->data[i] == 0xFF;
        special = special && f->data[7] >= 0xFC && f->data[7] <= 0xFE;
        if (special) {
            char kind = f->data[7] == 0xFC ? FAKE_ENTER : f->data[7] == 0xFD ? FAKE_EXIT : FAKE_ZERO;
            log_kind(bus, j, kind);
            if (kind == FAKE_ENTER) {
                a->enters++;
                a->motor_mode = 1;
            } else if (kind == FAKE_EXIT) {
                a->exits++;
                a->motor_mode = 0;
                a->have_cmd = 0;
            } else {
                a->zeros++;
                a->q = 0.0;
            }
            if (a->replies == 0 && kind != FAKE_ENTER)
                a->before_first_reply++;
        } else if (f->can_dlc == 8) {
            if (a->replies == 0)
                a->before_first_reply++;
            a->code[FAKE_P] = bits_of(f->data, 0, 16);
            a->code[FAKE_V] = bits_of(f->data, 16, 12);
            a->code[FAKE_KP] = bits_of(f->data, 28, 12);
            a->code[FAKE_KD] = bits_of(f->data, 40, 12);
            a->code[FAKE_T] = bits_of(f->data, 52, 12);
            int gains = a->code[FAKE_KP] != 0 || a->code[FAKE_KD] != 0;
            if (gains && !all_replied(bus))
                a->gains_before_all++;
            if (!a->motor_mode) {
                a->outside_motor_mode++;
            } else {
                for (int k = 0; k < FAKE_FIELDS; k++)
                    a->cmd[k] = from_code(a->code[k], a->cfg.range[k], widths[k]);
                a->have_cmd = 1;
            }
            if (a->code[FAKE_KP] != 0) { /* stiffness: it drives toward a position */
                a->commands++;
                log_kind(bus, j, FAKE_COMMAND);
            } else {
                a->holds++;
                log_kind(bus, j, FAKE_HOLD);
            }
        } else {
            goto stray;
        }
        step(a, bus->dt);
        if (bus->manual)
            a->pending++;
        else if (!a->mute)
            reply(bus, j);
        return;
    }
stray:
    bus->strays++;
}

static void *bus_main(void *arg)
{
    fake_can_t *bus = arg;
    while (!atomic_load(&bus->stop)) {
        struct pollfd p = { bus->fd, POLLIN, 0 };
        struct can_frame f;
        if (poll(&p, 1, 10) <= 0)
            continue;
        ssize_t got = read(bus->fd, &f, sizeof f);
        if (got != (ssize_t)sizeof f) {
            if (got == 0)
                break; /* the port's end closed */
            continue;
        }
        pthread_mutex_lock(&bus->lock);
        on_frame(bus, &f);
        pthread_mutex_unlock(&bus->lock);
    }
    return NULL;
}

/* ---- public ------------------------------------------------------------------- */

int fake_can_start(fake_can_t *bus, int fd, const fake_actuator_cfg_t *acts, unsigned n,
                   double dt, int manual)
{
    if (n > FAKE_CAN_MAX)
        return -1;
    memset(bus, 0, sizeof *bus);
    bus->fd = fd;
    bus->n = n;
    bus->dt = dt;
    bus->manual = manual;
    for (unsigned j = 0; j < n; j++)
        bus->act[j].cfg = acts[j];
    pthread_mutex_init(&bus->lock, NULL);
    atomic_init(&bus->stop, 0);
    if (pthread_create(&bus->thread, NULL, bus_main, bus) != 0)
        return -1;
    bus->running = 1;
    return 0;
}

void fake_can_stop(fake_can_t *bus)
{
    if (!bus->running)
        return;
    atomic_store(&bus->stop, 1);
    pthread_join(bus->thread, NULL);
    pthread_mutex_destroy(&bus->lock);
    bus->running = 0;
}

void fake_can_view(fake_can_t *bus, unsigned j, fake_actuator_t *out)
{
    pthread_mutex_lock(&bus->lock);
    *out = bus->act[j];
    pthread_mutex_unlock(&bus->lock);
}

uint64_t fake_can_received(fake_can_t *bus)
{
    pthread_mutex_lock(&bus->lock);
    uint64_t n = bus->received;
    pthread_mutex_unlock(&bus->lock);
    return n;
}

#define UNDER_LOCK(bus, stmt)                 \
    do {                                      \
        pthread_mutex_lock(&(bus)->lock);     \
        stmt;                                 \
        pthread_mutex_unlock(&(bus)->lock);   \
    } while (0)

void fake_can_mute(fake_can_t *bus, unsigned j, int on)
{
    UNDER_LOCK(bus, bus->act[j].mute = on);
}

void fake_can_freeze(fake_can_t *bus, unsigned j, int on)
{
    UNDER_LOCK(bus, bus->act[j].frozen = on);
}

void fake_can_error(fake_can_t *bus, unsigned j, uint8_t code)
{
    UNDER_LOCK(bus, bus->act[j].error = code);
}

void fake_can_jump(fake_can_t *bus, unsigned j, double rad)
{
    UNDER_LOCK(bus, bus->act[j].jump += rad);
}

void fake_can_drop_next(fake_can_t *bus, unsigned j)
{
    UNDER_LOCK(bus, bus->act[j].drop_next = 1);
}

void fake_can_set(fake_can_t *bus, unsigned j, double q, double dq)
{
    UNDER_LOCK(bus, (bus->act[j].q = q, bus->act[j].dq = dq));
}

unsigned fake_can_release(fake_can_t *bus)
{
    unsigned sent = 0;
    pthread_mutex_lock(&bus->lock);
    for (unsigned j = 0; j < bus->n; j++) {
        fake_actuator_t *a = &bus->act[j];
        if (a->pending == 0 || a->mute)
            continue;
        a->pending = 0;
        uint64_t before = a->replies;
        reply(bus, j);
        sent += a->replies != before;
    }
    pthread_mutex_unlock(&bus->lock);
    return sent;
}

int fake_can_replay(fake_can_t *bus, unsigned j)
{
    int rc = -1;
    pthread_mutex_lock(&bus->lock);
    fake_actuator_t *a = &bus->act[j];
    if (a->last_reply_len > 0)
        rc = send_frame(bus->fd, a->cfg.reply_id, a->last_reply, (uint8_t)a->last_reply_len);
    pthread_mutex_unlock(&bus->lock);
    return rc;
}

int fake_can_send_raw(fake_can_t *bus, uint32_t can_id, const uint8_t *data, uint8_t len)
{
    pthread_mutex_lock(&bus->lock);
    int rc = send_frame(bus->fd, can_id, data, len);
    pthread_mutex_unlock(&bus->lock);
    return rc;
}

int fake_can_open_raw(const char *ifname)
{
    struct sockaddr_can addr;
    unsigned idx = if_nametoindex(ifname);
    if (idx == 0)
        return -1;
    int fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0)
        return -1;
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = (int)idx;
    if (bind(fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}
