/* SPDX-License-Identifier: Apache-2.0 */
/* The loopback port: the wire between the port and the simulated robot
 * (sim.c), its faults, and the port's end with the link checks every
 * hardware port runs. */
#include "roz/loopback.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/hal/crc32.h"
#include "roz/hal/params.h"
#include "sim.h"

#define DEPTH (ROZ_LOOPBACK_MAX_DELAY + 1)
#define NEVER UINT64_MAX

/* ---- faults --------------------------------------------------------------- */

static int fault_active(const roz_loopback_fault_t *f, uint64_t t)
{
    return t >= f->from && (f->to == 0 || t < f->to);
}

/* Parses "FROM:TO", "FROM:" or "FROM" (freeze); TO empty = forever. */
static int parse_range(const char *s, uint64_t *from, uint64_t *to)
{
    char *end;
    if (*s < '0' || *s > '9')
        return ROZ_EINVAL;
    *from = strtoull(s, &end, 10);
    *to = 0;
    if (*end == '\0')
        return ROZ_OK;
    if (*end != ':')
        return ROZ_EINVAL;
    s = end + 1;
    if (*s == '\0')
        return ROZ_OK;
    if (*s < '0' || *s > '9')
        return ROZ_EINVAL;
    *to = strtoull(s, &end, 10);
    return *end == '\0' && *to > *from ? ROZ_OK : ROZ_EINVAL;
}

static int parse_fault_param(roz_loopback_t *lb, const char *key, const char *value,
                             roz_loopback_fault_kind_t kind, char *err, size_t errlen)
{
    roz_loopback_fault_t f = { kind, 0, 0, -1, 0 };
    char head[96];
    const char *range = value;
    const char *at = strchr(value, '@');

    if (kind == ROZ_LOOPBACK_DELAY || kind == ROZ_LOOPBACK_NAN || kind == ROZ_LOOPBACK_RANGE) {
        size_t n = at != NULL ? (size_t)(at - value) : 0;
        if (at == NULL || n == 0 || n >= sizeof head)
            goto bad;
        memcpy(head, value, n);
        head[n] = '\0';
        range = at + 1;
        if (kind == ROZ_LOOPBACK_DELAY) {
            char *end;
            unsigned long k = strtoul(head, &end, 10);
            if (*end != '\0' || k < 1 || k > ROZ_LOOPBACK_MAX_DELAY)
                goto bad;
            f.arg = (uint32_t)k;
        } else {
            char *end;
            long ch = strtol(head, &end, 10);
            if (*end != '\0' || head[0] < '0' || head[0] > '9')
                ch = roz_manifest_find_state(lb->m, head);
            if (ch < 0 || ch >= (long)lb->m->n_states)
                goto bad;
            f.channel = (int32_t)ch;
        }
    }
    if (parse_range(range, &f.from, &f.to) != ROZ_OK)
        goto bad;
    if (roz_loopback_inject(lb, &f) == ROZ_OK)
        return ROZ_OK;
bad:
    snprintf(err, errlen,
             "parameter %s = \"%s\": expected %s (ticks FROM:TO, TO empty = forever; at most %d faults)",
             key, value,
             kind == ROZ_LOOPBACK_DELAY ? "K@FROM:TO with K in 1..15"
             : (kind == ROZ_LOOPBACK_NAN || kind == ROZ_LOOPBACK_RANGE) ? "CHANNEL@FROM:TO"
                                                                        : "FROM:TO",
             ROZ_LOOPBACK_MAX_FAULTS);
    return ROZ_EINVAL;
}

/* Any fault of @p kind active at tick @p t. */
static const roz_loopback_fault_t *active(const roz_loopback_t *lb, roz_loopback_fault_kind_t kind,
                                          uint64_t t)
{
    for (uint32_t k = 0; k < lb->n_faults; k++) {
        if (lb->faults[k].kind == kind && fault_active(&lb->faults[k], t))
            return &lb->faults[k];
    }
    return NULL;
}

/* ---- frames ----------------------------------------------------------------
 * A frame image: [0] sequence, [1] value count, [2 .. 2+2n) the values as
 * host doubles, [2+2n] the CRC of the words before it. */

static size_t frame_words(size_t n)
{
    return 3 + 2 * n;
}

static void encode(uint32_t *image, uint32_t seq, const double *v, size_t n)
{
    image[0] = seq;
    image[1] = (uint32_t)n;
    memcpy(&image[2], v, n * sizeof v[0]);
    image[2 + 2 * n] = roz_crc32_words(image, 2 + 2 * n);
}

/* Whether the image is intact: the count it claims and its CRC. */
static int intact(const uint32_t *image, size_t n)
{
    return image[1] == (uint32_t)n && image[2 + 2 * n] == roz_crc32_words(image, 2 + 2 * n);
}

static void decode(const uint32_t *image, double *v, size_t n)
{
    memcpy(v, &image[2], n * sizeof v[0]);
}

/* One bit, chosen by the tick, flips in transit. */
static void flip_bit(uint32_t *image, size_t words, uint64_t t)
{
    uint64_t bit = (t * 2654435761u) % (words * 32u);
    image[bit / 32u] ^= 1u << (bit % 32u);
}

/* ---- the robot's end ------------------------------------------------------ */

/* Tick t of the robot: live or die, move, send a state frame. */
static void peer_tick(roz_loopback_t *lb, uint64_t t)
{
    const roz_manifest_t *m = lb->m;
    int dead = active(lb, ROZ_LOOPBACK_RESTART, t) != NULL;
    double v[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];

    if (dead) {
        /* died (or still dead): it forgets its command, its joints stop */
        lb->peer_dead = 1;
        lb->have_cmd = 0;
        for (uint16_t j = 0; j < lb->n_joints; j++)
            lb->joints[j].dq = lb->joints[j].tau = 0.0;
        return;
    }
    if (lb->peer_dead) {
        /* boots again: a new process, sequence from 0, no command */
        lb->peer_dead = 0;
        lb->peer_seq = 0;
        roz_link_init(&lb->peer_link, 0, 0);
    }
    if (lb->have_cmd)
        roz_lbsim_step(lb);
    if (active(lb, ROZ_LOOPBACK_FREEZE, t) != NULL)
        return;

    roz_lbsim_compose(lb, v);
    for (uint32_t k = 0; k < lb->n_faults; k++) {
        const roz_loopback_fault_t *f = &lb->faults[k];
        if (!fault_active(f, t))
            continue;
        if (f->kind == ROZ_LOOPBACK_NAN)
            v[f->channel] = NAN;
        else if (f->kind == ROZ_LOOPBACK_RANGE)
            v[f->channel] = m->states[f->channel].max + 0.5;
    }
    roz_loopback_frame_t *fr = &lb->flight[t % DEPTH];
    encode(fr->image, lb->peer_seq++, v, m->n_states);
    lb->frames_sent++;

    /* the transport */
    const roz_loopback_fault_t *delay = active(lb, ROZ_LOOPBACK_DELAY, t);
    fr->sent = t;
    fr->arrives = t + (delay != NULL ? delay->arg : 0u);
    if (active(lb, ROZ_LOOPBACK_DROP, t) != NULL) {
        fr->arrives = NEVER;
        lb->frames_dropped++;
    }
    if (active(lb, ROZ_LOOPBACK_CORRUPT, t) != NULL) {
        flip_bit(fr->image, frame_words(m->n_states), t);
        lb->frames_corrupted++;
    }
}

/* A command frame reaches the robot. */
static void peer_receive(roz_loopback_t *lb, const uint32_t *image, uint64_t now_ns)
{
    const roz_manifest_t *m = lb->m;
    if (lb->peer_dead) {
        lb->cmds_lost++;
        return;
    }
    roz_link_verdict_t v = roz_link_check(&lb->peer_link, intact(image, m->n_commands), image[0],
                                          now_ns);
    if (v == ROZ_LINK_BAD_CRC || v == ROZ_LINK_REPLAY)
        return; /* dropped and counted by peer_link; the last good command stays */
    decode(image, lb->cmd, m->n_commands);
    if (lb->first_write_tick == 0)
        lb->first_write_tick = lb->tick;
    lb->have_cmd = 1;
}

/* ---- the port's end --------------------------------------------------------- */

/* A state frame reaches the port. Returns the verdict. */
static roz_link_verdict_t port_receive(roz_loopback_t *lb, const uint32_t *image, uint64_t now_ns)
{
    size_t n = lb->m->n_states;
    roz_link_verdict_t v = roz_link_check(&lb->link, intact(image, n), image[0], now_ns);

    if (v == ROZ_LINK_BAD_CRC || v == ROZ_LINK_REPLAY)
        return v;
    decode(image, lb->rx, n);
    memcpy(lb->last_image, image, frame_words(n) * sizeof image[0]);
    lb->frames_delivered++;
    return v;
}

/* ---- ops ----------------------------------------------------------------- */

static int lb_open(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                   size_t errlen)
{
    static const struct { const char *key; roz_loopback_fault_kind_t kind; } fault_keys[] = {
        { "drop", ROZ_LOOPBACK_DROP },     { "freeze", ROZ_LOOPBACK_FREEZE },
        { "delay", ROZ_LOOPBACK_DELAY },   { "nan", ROZ_LOOPBACK_NAN },
        { "range", ROZ_LOOPBACK_RANGE },   { "duplicate", ROZ_LOOPBACK_DUPLICATE },
        { "corrupt", ROZ_LOOPBACK_CORRUPT }, { "corrupt_cmd", ROZ_LOOPBACK_CORRUPT_CMD },
        { "restart", ROZ_LOOPBACK_RESTART },
    };
    enum { N_KEYS = sizeof fault_keys / sizeof fault_keys[0] };
    const char *known[N_KEYS + 1];
    roz_loopback_t *lb = self;
    int rc;

    if (m == NULL || roz_manifest_validate(m, NULL) != ROZ_OK) {
        snprintf(err, errlen, "loopback: invalid manifest");
        return ROZ_EINVAL;
    }
    memset(lb, 0, sizeof *lb);
    lb->m = m;
    lb->dt = 1.0 / (double)m->control_rate_hz;
    lb->period_ns = 1000000000u / m->control_rate_hz;
    for (size_t k = 0; k < DEPTH; k++)
        lb->flight[k].arrives = NEVER;
    roz_link_init(&lb->link, ROZ_LOOPBACK_PEER_TIMEOUT_NS, 0);
    roz_link_init(&lb->peer_link, 0, 0);
    roz_lbsim_open(lb);

    for (size_t k = 0; k < N_KEYS; k++)
        known[k] = fault_keys[k].key;
    known[N_KEYS] = NULL;
    rc = roz_params_check_known(p, known, "loopback", err, errlen);
    if (rc != ROZ_OK)
        return rc;
    for (size_t i = 0; p != NULL && i < p->n; i++) {
        for (size_t k = 0; k < N_KEYS; k++) {
            if (strcmp(p->items[i].key, fault_keys[k].key) == 0) {
                rc = parse_fault_param(lb, p->items[i].key, p->items[i].value,
                                       fault_keys[k].kind, err, errlen);
                if (rc != ROZ_OK)
                    return rc;
            }
        }
    }
    return ROZ_OK;
}

static int lb_read(void *self, double *state, size_t n)
{
    roz_loopback_t *lb = self;
    int fresh = 0, restarted = 0;

    if (n != lb->m->n_states)
        return ROZ_EINVAL; /* refused before time moves on */
    uint64_t t = lb->tick++;
    uint64_t now_ns = t * lb->period_ns;
    peer_tick(lb, t);

    if (active(lb, ROZ_LOOPBACK_DUPLICATE, t) != NULL && lb->link.alive) {
        /* the last frame again, in place of whatever arrives now */
        for (size_t k = 0; k < DEPTH; k++) {
            if (lb->flight[k].arrives == t)
                lb->flight[k].arrives = NEVER;
        }
        lb->frames_duplicated++;
        (void)port_receive(lb, lb->last_image, now_ns);
    }
    /* frames arriving now, oldest sent first */
    for (uint64_t back = DEPTH; back-- > 0;) {
        if (back > t)
            continue;
        roz_loopback_frame_t *fr = &lb->flight[(t - back) % DEPTH];
        if (fr->sent != t - back || fr->arrives != t)
            continue;
        fr->arrives = NEVER;
        roz_link_verdict_t v = port_receive(lb, fr->image, now_ns);
        fresh |= v == ROZ_LINK_FIRST || v == ROZ_LINK_FRESH || v == ROZ_LINK_RESTART;
        restarted |= v == ROZ_LINK_RESTART;
    }
    if (restarted) {
        lb->link_events++;
        return ROZ_ELINK;
    }
    if (!lb->link.alive)
        return ROZ_ENOENT;
    memcpy(state, lb->rx, n * sizeof state[0]);
    return fresh;
}

static int lb_write(void *self, const double *cmd, size_t n)
{
    roz_loopback_t *lb = self;
    const roz_manifest_t *m = lb->m;
    uint64_t t = lb->tick > 0 ? lb->tick - 1 : 0; /* the tick of the last read */

    if (n != m->n_commands)
        return ROZ_EINVAL;
    lb->writes++;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (!(cmd[i] >= m->commands[i].min && cmd[i] <= m->commands[i].max))
            lb->violations++;
    }
    if (!lb->link.alive) {
        lb->writes_withheld++; /* nothing before the peer's first state frame */
        return ROZ_OK;
    }
    encode(lb->cmd_image, lb->cmd_seq++, cmd, n);
    if (active(lb, ROZ_LOOPBACK_CORRUPT_CMD, t) != NULL) {
        flip_bit(lb->cmd_image, frame_words(n), t);
        lb->cmds_corrupted++;
    }
    peer_receive(lb, lb->cmd_image, t * lb->period_ns);
    return ROZ_OK;
}

const roz_port_ops_t roz_loopback_ops = {
    .name = "loopback",
    .open = lb_open,
    .activate = NULL,
    .read = lb_read,
    .write = lb_write,
    .deactivate = NULL,
    .close = NULL,
};

/* ---- public -------------------------------------------------------------- */

int roz_loopback_inject(roz_loopback_t *lb, const roz_loopback_fault_t *f)
{
    if (lb->n_faults >= ROZ_LOOPBACK_MAX_FAULTS) {
        /* make room: forget the injections that are over */
        uint32_t kept = 0;
        for (uint32_t k = 0; k < lb->n_faults; k++) {
            if (lb->faults[k].to == 0 || lb->faults[k].to > lb->tick)
                lb->faults[kept++] = lb->faults[k];
        }
        lb->n_faults = kept;
    }
    if (lb->n_faults >= ROZ_LOOPBACK_MAX_FAULTS)
        return ROZ_ENOSPC;
    if (f->kind < ROZ_LOOPBACK_DROP || f->kind > ROZ_LOOPBACK_RESTART)
        return ROZ_EINVAL;
    if ((f->kind == ROZ_LOOPBACK_NAN || f->kind == ROZ_LOOPBACK_RANGE) &&
        (f->channel < 0 || f->channel >= (int32_t)lb->m->n_states))
        return ROZ_EINVAL;
    if (f->kind == ROZ_LOOPBACK_RANGE && lb->m->states[f->channel].type != ROZ_IF_POSITION)
        return ROZ_EINVAL;
    if (f->kind == ROZ_LOOPBACK_DELAY && (f->arg < 1 || f->arg > ROZ_LOOPBACK_MAX_DELAY))
        return ROZ_EINVAL;
    lb->faults[lb->n_faults++] = *f;
    return ROZ_OK;
}

void roz_loopback_true_state(const roz_loopback_t *lb, double *state)
{
    roz_lbsim_compose(lb, state);
}

const double *roz_loopback_last_command(const roz_loopback_t *lb)
{
    return lb->have_cmd ? lb->cmd : NULL;
}
