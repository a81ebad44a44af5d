/* SPDX-License-Identifier: Apache-2.0 */
/* The loopback port: the wire between the port and the simulated robot
 * (sim.c), its faults, and the port's end with the link checks every
 * hardware port runs. */
#include "roz/port/loopback.h"

#include <math.h>
#include <string.h>

#include "roz/format.h"
#include "roz/hal/crc32.h"
#include "roz/hal/inject.h"
#include "roz/hal/params.h"
#include "sim.h"

#define DEPTH (ROZ_LOOPBACK_MAX_DELAY + 1)
#define NEVER UINT64_MAX

/* ---- faults --------------------------------------------------------------- */

static int fault_active(const roz_loopback_fault_t *f, uint64_t t)
{
    return t >= f->from && (f->to == 0 || t < f->to);
}

/* Any fault of @p kind active at tick @p t. */
static const roz_loopback_fault_t *active(const roz_loopback_t *lb, roz_inject_kind_t kind,
                                          uint64_t t)
{
    for (uint32_t k = 0; k < lb->n_faults; k++) {
        if (lb->faults[k].kind == kind && fault_active(&lb->faults[k], t))
            return &lb->faults[k];
    }
    return NULL;
}

/* ---- parameters ------------------------------------------------------------
 * The fault injections' grammar is the simulators' (roz/hal/inject.h); the
 * port reads the CHANNEL of nan= and range= and injects each entry. */

enum { BAD = ROZ_INJECT_BAD };

/* The state channel of nan= and range=: an index or a name. */
static int parse_channel(const roz_loopback_t *lb, const char *head, roz_inject_kind_t kind,
                         int32_t *out, char *why, size_t whylen)
{
    const roz_manifest_t *m = lb->m;
    long ch;

    if (head[strspn(head, "0123456789")] == '\0') {
        /* an index; a number too large for 32 bits is out of range too */
        uint32_t k = 0;
        int ok = roz_params_parse_u32(roz_params_span(head), 0, 0, UINT32_MAX, &k) == ROZ_OK;
        ch = (long)k;
        if (!ok || k >= m->n_states) {
            roz_format(why, whylen, "state %s does not exist (%u states)", head,
                       (unsigned)m->n_states);
            return BAD;
        }
    } else {
        ch = roz_manifest_find_state(m, head);
        if (ch < 0) {
            roz_format(why, whylen, "no state named \"%s\"", head);
            return BAD;
        }
    }
    if (kind == ROZ_INJECT_RANGE && m->states[ch].type != ROZ_IF_POSITION) {
        roz_format(why, whylen, "state %ld (%s) is not a position state", ch, m->states[ch].name);
        return BAD;
    }
    *out = (int32_t)ch;
    return 0;
}

/* One entry of a fault parameter (roz_inject_parse()'s callback). */
static int inject_entry(void *ctx, const roz_inject_entry_t *e, char *why, size_t whylen)
{
    roz_loopback_t *lb = ctx;
    roz_loopback_fault_t f = { e->kind, e->from, e->to, -1, e->arg };
    int rc;

    if ((e->kind == ROZ_INJECT_NAN || e->kind == ROZ_INJECT_RANGE) &&
        (rc = parse_channel(lb, e->head, e->kind, &f.channel, why, whylen)) != 0)
        return rc;
    if (roz_loopback_inject(lb, &f) != ROZ_OK) {
        roz_format(why, whylen, "more than %d fault injections", ROZ_LOOPBACK_MAX_FAULTS);
        return BAD;
    }
    return ROZ_OK;
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
    int dead = active(lb, ROZ_INJECT_RESTART, t) != NULL;
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
    if (active(lb, ROZ_INJECT_FREEZE, t) != NULL)
        return;

    roz_lbsim_compose(lb, v);
    for (uint32_t k = 0; k < lb->n_faults; k++) {
        const roz_loopback_fault_t *f = &lb->faults[k];
        if (!fault_active(f, t))
            continue;
        if (f->kind == ROZ_INJECT_NAN)
            v[f->channel] = NAN;
        else if (f->kind == ROZ_INJECT_RANGE)
            v[f->channel] = m->states[f->channel].max + 0.5;
    }
    roz_loopback_frame_t *fr = &lb->flight[t % DEPTH];
    encode(fr->image, lb->peer_seq++, v, m->n_states);
    lb->frames_sent++;

    /* the transport */
    const roz_loopback_fault_t *delay = active(lb, ROZ_INJECT_DELAY, t);
    fr->sent = t;
    fr->arrives = t + (delay != NULL ? delay->arg : 0u);
    if (active(lb, ROZ_INJECT_DROP, t) != NULL) {
        fr->arrives = NEVER;
        lb->frames_dropped++;
    }
    if (active(lb, ROZ_INJECT_CORRUPT, t) != NULL) {
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
    /* its parameters: the fault injections ROZ_INJECT_DROP .. _RESTART */
    enum { N_KEYS = ROZ_INJECT_RESTART - ROZ_INJECT_DROP + 1 };
    const char *known[N_KEYS + 1];
    roz_loopback_t *lb = self;
    int rc;

    if (m == NULL || roz_manifest_validate(m, NULL) != ROZ_OK) {
        roz_format(err, errlen, "loopback: invalid manifest");
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
        known[k] = roz_inject_key((roz_inject_kind_t)(ROZ_INJECT_DROP + (int)k));
    known[N_KEYS] = NULL;
    rc = roz_params_check_known(p, known, "loopback", err, errlen);
    if (rc != ROZ_OK)
        return rc;
    for (size_t i = 0; p != NULL && i < p->n; i++) {
        roz_inject_kind_t kind = roz_inject_find(p->items[i].key);
        if (kind >= ROZ_INJECT_DROP && kind <= ROZ_INJECT_RESTART) {
            rc = roz_inject_parse(kind, p->items[i].value, inject_entry, lb, err, errlen);
            if (rc != ROZ_OK)
                return rc;
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

    if (active(lb, ROZ_INJECT_DUPLICATE, t) != NULL && lb->link.alive) {
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
    if (active(lb, ROZ_INJECT_CORRUPT_CMD, t) != NULL) {
        flip_bit(lb->cmd_image, frame_words(n), t);
        lb->cmds_corrupted++;
    }
    peer_receive(lb, lb->cmd_image, t * lb->period_ns);
    return ROZ_OK;
}

static int lb_link_counters(const void *self, roz_port_link_counters_t *out)
{
    const roz_loopback_t *lb = self;
    roz_link_port_counters(&lb->link, 0, out);
    return ROZ_OK;
}

/* Every fault runs over ticks [FROM, TO); TO may be empty: forever. */
static const roz_port_param_info_t lb_params[] = {
    ROZ_PORT_PARAM_TEXT_ROW("drop", "FROM:TO", "", "frames sent are lost in transit"),
    ROZ_PORT_PARAM_TEXT_ROW("freeze", "FROM[:TO]", "", "the peer sends nothing"),
    ROZ_PORT_PARAM_TEXT_ROW("delay", "K@FROM:TO", "", "frames arrive K ticks late"),
    ROZ_PORT_PARAM_TEXT_ROW("nan", "CH@FROM:TO", "",
                            "the peer sends NaN in state CH (an index or a name)"),
    ROZ_PORT_PARAM_TEXT_ROW("range", "CH@FROM:TO", "",
                            "the peer sends 0.5 beyond state CH's upper limit"),
    ROZ_PORT_PARAM_TEXT_ROW("duplicate", "FROM:TO", "", "the frame delivered before, again"),
    ROZ_PORT_PARAM_TEXT_ROW("corrupt", "FROM:TO", "", "one bit of every state frame flips"),
    ROZ_PORT_PARAM_TEXT_ROW("corrupt_cmd", "FROM:TO", "", "one bit of every command frame flips"),
    ROZ_PORT_PARAM_TEXT_ROW("restart", "FROM:TO", "", "the peer dies at FROM, boots again at TO"),
};

static const roz_port_info_t lb_info = {
    .summary = "a deterministic simulator for any manifest, with fault injection",
    .header = "roz/port/loopback.h",
    ROZ_PORT_INFO_PARAMS(lb_params),
};

const roz_port_ops_t roz_loopback_ops = {
    .name = "loopback",
    .open = lb_open,
    .activate = NULL,
    .read = lb_read,
    .write = lb_write,
    .deactivate = NULL,
    .close = NULL,
    .caps = ROZ_PORT_CAP_CRC | ROZ_PORT_CAP_SEQUENCE | ROZ_PORT_CAP_RESTART |
            ROZ_PORT_CAP_SIMULATOR,
    .info = &lb_info,
    .link_counters = lb_link_counters,
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
    if (f->kind < ROZ_INJECT_DROP || f->kind > ROZ_INJECT_RESTART)
        return ROZ_EINVAL;
    if ((f->kind == ROZ_INJECT_NAN || f->kind == ROZ_INJECT_RANGE) &&
        (f->channel < 0 || f->channel >= (int32_t)lb->m->n_states))
        return ROZ_EINVAL;
    if (f->kind == ROZ_INJECT_RANGE && lb->m->states[f->channel].type != ROZ_IF_POSITION)
        return ROZ_EINVAL;
    if (f->kind == ROZ_INJECT_DELAY && (f->arg < 1 || f->arg > ROZ_LOOPBACK_MAX_DELAY))
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

roz_loopback_counters_t roz_loopback_counters(const roz_loopback_t *lb)
{
    roz_loopback_counters_t c;
    c.tick = lb->tick;
    c.faults = lb->n_faults;
    c.frames_sent = lb->frames_sent;
    c.frames_delivered = lb->frames_delivered;
    c.frames_dropped = lb->frames_dropped;
    c.frames_duplicated = lb->frames_duplicated;
    c.frames_corrupted = lb->frames_corrupted;
    c.link_events = lb->link_events;
    c.writes = lb->writes;
    c.writes_withheld = lb->writes_withheld;
    c.cmds_corrupted = lb->cmds_corrupted;
    c.cmds_lost = lb->cmds_lost;
    c.violations = lb->violations;
    c.first_write_tick = lb->first_write_tick;
    return c;
}

roz_link_t roz_loopback_link(const roz_loopback_t *lb)
{
    return lb->link;
}

roz_link_t roz_loopback_peer_link(const roz_loopback_t *lb)
{
    return lb->peer_link;
}

void roz_loopback_clear_faults(roz_loopback_t *lb)
{
    lb->n_faults = 0;
}
