/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/loopback.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/hal/params.h"

/* ---- private ------------------------------------------------------------- */

enum { M_DEFAULT = 0, M_JOINT_POS, M_JOINT_VEL, M_JOINT_EFF, M_BASE };

#define INERTIA 0.05  /* kg*m^2 of every simulated joint */
#define FRICTION 0.05 /* N*m*s/rad viscous friction */
#define HIST (ROZ_LOOPBACK_MAX_DELAY + 1)

static const char *suffix_of(const char *name)
{
    const char *slash = strrchr(name, '/');
    return slash != NULL ? slash + 1 : name;
}

static size_t prefix_len(const char *name)
{
    const char *slash = strrchr(name, '/');
    return slash != NULL ? (size_t)(slash - name) : 0;
}

static int same_prefix(const char *a, const char *b)
{
    size_t la = prefix_len(a);
    return la != 0 && la == prefix_len(b) && strncmp(a, b, la) == 0;
}

/* Joint whose states share this name's prefix; created for position states. */
static int joint_for(roz_loopback_t *lb, const char *name, int create)
{
    const roz_manifest_t *m = lb->m;
    for (uint16_t j = 0; j < lb->n_joints; j++) {
        const roz_loopback_joint_t *jt = &lb->joints[j];
        int32_t any = jt->pos_state >= 0 ? jt->pos_state
                                         : (jt->vel_state >= 0 ? jt->vel_state : jt->eff_state);
        if (any >= 0 && same_prefix(m->states[any].name, name))
            return j;
    }
    if (!create || prefix_len(name) == 0 || lb->n_joints >= (uint16_t)(sizeof lb->joints / sizeof lb->joints[0]))
        return -1;
    roz_loopback_joint_t *jt = &lb->joints[lb->n_joints];
    memset(jt, 0, sizeof *jt);
    jt->pos_state = jt->vel_state = jt->eff_state = -1;
    jt->pos_cmd = jt->vel_cmd = jt->kp_cmd = jt->kd_cmd = jt->eff_cmd = -1;
    return lb->n_joints++;
}

static int base_axis_state(const char *suffix)
{
    if (!strcmp(suffix, "position.x") || !strcmp(suffix, "odom.x")) return 0;
    if (!strcmp(suffix, "position.y") || !strcmp(suffix, "odom.y")) return 1;
    if (!strcmp(suffix, "position.z")) return 2;
    if (!strcmp(suffix, "yaw") || !strcmp(suffix, "odom.yaw")) return 3;
    return -1;
}

static int base_axis_cmd(const char *suffix)
{
    if (!strcmp(suffix, "velocity.x") || !strcmp(suffix, "linear.x")) return 0;
    if (!strcmp(suffix, "velocity.y") || !strcmp(suffix, "linear.y")) return 1;
    if (!strcmp(suffix, "velocity.z") || !strcmp(suffix, "linear.z")) return 2;
    if (!strcmp(suffix, "yaw_rate") || !strcmp(suffix, "angular.z")) return 3;
    return -1;
}

static void bind_channels(roz_loopback_t *lb)
{
    const roz_manifest_t *m = lb->m;

    lb->n_joints = 0;
    for (int a = 0; a < 4; a++)
        lb->base_cmd[a] = lb->base_state[a] = -1;
    /* states: joints first (a position state creates its joint) */
    for (uint16_t s = 0; s < m->n_states; s++) {
        const roz_channel_t *c = &m->states[s];
        const char *suf = suffix_of(c->name);
        int axis = base_axis_state(suf);
        lb->bind[s] = (roz_loopback_binding_t){ M_DEFAULT, 0, -1 };
        if (axis >= 0 && c->type == ROZ_IF_POSITION) {
            lb->base_state[axis] = s;
            lb->bind[s] = (roz_loopback_binding_t){ M_BASE, (uint8_t)axis, -1 };
        } else if (c->type == ROZ_IF_POSITION && !strcmp(suf, "position")) {
            int j = joint_for(lb, c->name, 1);
            if (j >= 0) {
                lb->joints[j].pos_state = s;
                lb->bind[s] = (roz_loopback_binding_t){ M_JOINT_POS, 0, (int16_t)j };
            }
        }
    }
    for (uint16_t s = 0; s < m->n_states; s++) {
        const roz_channel_t *c = &m->states[s];
        const char *suf = suffix_of(c->name);
        int j;
        if (lb->bind[s].model != M_DEFAULT)
            continue;
        if (c->type == ROZ_IF_VELOCITY && !strcmp(suf, "velocity") &&
            (j = joint_for(lb, c->name, 0)) >= 0) {
            lb->joints[j].vel_state = s;
            lb->bind[s] = (roz_loopback_binding_t){ M_JOINT_VEL, 0, (int16_t)j };
        } else if (c->type == ROZ_IF_EFFORT && !strcmp(suf, "effort") &&
                   (j = joint_for(lb, c->name, 0)) >= 0) {
            lb->joints[j].eff_state = s;
            lb->bind[s] = (roz_loopback_binding_t){ M_JOINT_EFF, 0, (int16_t)j };
        }
    }
    /* commands: by joint prefix, or through the position pairing */
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        const char *suf = suffix_of(c->name);
        int axis = base_axis_cmd(suf);
        int j = joint_for(lb, c->name, 0);
        if (j < 0 && c->position_state >= 0 && lb->bind[c->position_state].model == M_JOINT_POS)
            j = lb->bind[c->position_state].joint;
        if (j < 0) {
            if (axis >= 0 && c->type == ROZ_IF_VELOCITY)
                lb->base_cmd[axis] = i;
            continue;
        }
        roz_loopback_joint_t *jt = &lb->joints[j];
        switch (c->type) {
        case ROZ_IF_POSITION:  jt->pos_cmd = i; break;
        case ROZ_IF_VELOCITY:  jt->vel_cmd = i; break;
        case ROZ_IF_STIFFNESS: jt->kp_cmd = i; break;
        case ROZ_IF_DAMPING:   jt->kd_cmd = i; break;
        case ROZ_IF_EFFORT:    jt->eff_cmd = i; break;
        default: break;
        }
    }
}

static double cmd_or(const roz_loopback_t *lb, int32_t i, double fallback)
{
    return i >= 0 ? lb->cmd[i] : fallback;
}

static void step_joint(roz_loopback_t *lb, roz_loopback_joint_t *jt)
{
    const roz_manifest_t *m = lb->m;
    double dt = lb->dt;

    if (jt->kp_cmd >= 0 || jt->kd_cmd >= 0 || (jt->eff_cmd >= 0 && jt->pos_cmd < 0 && jt->vel_cmd < 0)) {
        double kp = cmd_or(lb, jt->kp_cmd, 0.0), kd = cmd_or(lb, jt->kd_cmd, 0.0);
        double tau = kp * (cmd_or(lb, jt->pos_cmd, jt->q) - jt->q) +
                     kd * (cmd_or(lb, jt->vel_cmd, 0.0) - jt->dq) + cmd_or(lb, jt->eff_cmd, 0.0);
        if (jt->eff_cmd >= 0) {
            const roz_channel_t *e = &m->commands[jt->eff_cmd];
            tau = fmin(fmax(tau, e->min), e->max);
        }
        jt->tau = tau;
        jt->dq += (tau - FRICTION * jt->dq) / INERTIA * dt;
        jt->q += jt->dq * dt;
    } else if (jt->pos_cmd >= 0) {
        double target = lb->cmd[jt->pos_cmd];
        double q0 = jt->q;
        jt->q += (target - jt->q) * (1.0 - exp(-dt / ROZ_LOOPBACK_TAU_S));
        jt->dq = (jt->q - q0) / dt;
        jt->tau = 0.0;
    } else if (jt->vel_cmd >= 0) {
        jt->dq = lb->cmd[jt->vel_cmd];
        jt->q += jt->dq * dt;
        jt->tau = 0.0;
    }
}

static void step_base(roz_loopback_t *lb)
{
    double v[4];
    for (int a = 0; a < 4; a++)
        v[a] = cmd_or(lb, lb->base_cmd[a], 0.0);
    double yaw = lb->base[3];
    lb->base[0] += (v[0] * cos(yaw) - v[1] * sin(yaw)) * lb->dt;
    lb->base[1] += (v[0] * sin(yaw) + v[1] * cos(yaw)) * lb->dt;
    lb->base[2] += v[2] * lb->dt;
    yaw += v[3] * lb->dt;
    lb->base[3] = atan2(sin(yaw), cos(yaw)); /* wrap to [-pi, pi] */
}

static void compose(const roz_loopback_t *lb, double *state)
{
    const roz_manifest_t *m = lb->m;
    for (uint16_t s = 0; s < m->n_states; s++) {
        const roz_loopback_binding_t *b = &lb->bind[s];
        switch (b->model) {
        case M_JOINT_POS: state[s] = lb->joints[b->joint].q; break;
        case M_JOINT_VEL: state[s] = lb->joints[b->joint].dq; break;
        case M_JOINT_EFF: state[s] = lb->joints[b->joint].tau; break;
        case M_BASE:      state[s] = lb->base[b->axis]; break;
        default:          state[s] = m->states[s].default_value; break;
        }
    }
}

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

/* ---- ops ----------------------------------------------------------------- */

static int lb_open(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                   size_t errlen)
{
    static const char *const known[] = { "drop", "freeze", "delay", "nan", "range",
                                         "duplicate", NULL };
    static const struct { const char *key; roz_loopback_fault_kind_t kind; } fault_keys[] = {
        { "drop", ROZ_LOOPBACK_DROP },   { "freeze", ROZ_LOOPBACK_FREEZE },
        { "delay", ROZ_LOOPBACK_DELAY }, { "nan", ROZ_LOOPBACK_NAN },
        { "range", ROZ_LOOPBACK_RANGE }, { "duplicate", ROZ_LOOPBACK_DUPLICATE },
    };
    roz_loopback_t *lb = self;
    int rc;

    if (m == NULL || roz_manifest_validate(m, NULL) != ROZ_OK) {
        snprintf(err, errlen, "loopback: invalid manifest");
        return ROZ_EINVAL;
    }
    memset(lb, 0, sizeof *lb);
    lb->m = m;
    lb->dt = 1.0 / (double)m->control_rate_hz;
    bind_channels(lb);
    for (uint16_t j = 0; j < lb->n_joints; j++) {
        roz_loopback_joint_t *jt = &lb->joints[j];
        if (jt->pos_state >= 0)
            jt->q = m->states[jt->pos_state].default_value;
    }
    for (int a = 0; a < 4; a++) {
        if (lb->base_state[a] >= 0)
            lb->base[a] = m->states[lb->base_state[a]].default_value;
    }
    rc = roz_params_check_known(p, known, "loopback", err, errlen);
    if (rc != ROZ_OK)
        return rc;
    for (size_t i = 0; p != NULL && i < p->n; i++) {
        for (size_t k = 0; k < sizeof fault_keys / sizeof fault_keys[0]; k++) {
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
    const roz_manifest_t *m = lb->m;
    uint64_t t = lb->tick++;
    double *now_frame = lb->hist[t % HIST];
    const double *frame = now_frame;
    int deliver = 1, duplicate = 0;

    if (n != m->n_states)
        return ROZ_EINVAL;
    if (lb->have_cmd) {
        for (uint16_t j = 0; j < lb->n_joints; j++)
            step_joint(lb, &lb->joints[j]);
        step_base(lb);
    }
    compose(lb, now_frame);

    for (uint32_t k = 0; k < lb->n_faults; k++) {
        const roz_loopback_fault_t *f = &lb->faults[k];
        if (!fault_active(f, t))
            continue;
        if (f->kind == ROZ_LOOPBACK_DROP || f->kind == ROZ_LOOPBACK_FREEZE)
            deliver = 0;
        else if (f->kind == ROZ_LOOPBACK_DELAY)
            frame = t >= f->arg ? lb->hist[(t - f->arg) % HIST] : NULL;
        else if (f->kind == ROZ_LOOPBACK_DUPLICATE)
            duplicate = 1;
    }
    if (frame == NULL)
        deliver = 0;
    if (!deliver) {
        lb->frames_dropped++;
        if (!lb->delivered_any)
            return ROZ_ENOENT;
        memcpy(state, lb->last_out, n * sizeof state[0]);
        return 0;
    }
    if (duplicate && lb->delivered_any) {
        /* the frame before, again, claimed fresh */
        memcpy(state, lb->last_out, n * sizeof state[0]);
        lb->frames_duplicated++;
        lb->frames_delivered++;
        return 1;
    }
    memcpy(state, frame, n * sizeof state[0]);
    for (uint32_t k = 0; k < lb->n_faults; k++) {
        const roz_loopback_fault_t *f = &lb->faults[k];
        if (!fault_active(f, t))
            continue;
        if (f->kind == ROZ_LOOPBACK_NAN)
            state[f->channel] = NAN;
        else if (f->kind == ROZ_LOOPBACK_RANGE)
            state[f->channel] = m->states[f->channel].max + 0.5;
    }
    memcpy(lb->last_out, state, n * sizeof state[0]);
    lb->delivered_any = 1;
    lb->frames_delivered++;
    return 1;
}

static int lb_write(void *self, const double *cmd, size_t n)
{
    roz_loopback_t *lb = self;
    const roz_manifest_t *m = lb->m;

    if (n != m->n_commands)
        return ROZ_EINVAL;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (!(cmd[i] >= m->commands[i].min && cmd[i] <= m->commands[i].max))
            lb->violations++;
    }
    memcpy(lb->cmd, cmd, n * sizeof cmd[0]);
    if (!lb->have_cmd)
        lb->first_write_tick = lb->tick;
    lb->have_cmd = 1;
    lb->writes++;
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
    if (lb->n_faults >= ROZ_LOOPBACK_MAX_FAULTS)
        return ROZ_ENOSPC;
    if (f->kind < ROZ_LOOPBACK_DROP || f->kind > ROZ_LOOPBACK_DUPLICATE)
        return ROZ_EINVAL;
    if ((f->kind == ROZ_LOOPBACK_NAN || f->kind == ROZ_LOOPBACK_RANGE) &&
        (f->channel < 0 || f->channel >= (int32_t)lb->m->n_states))
        return ROZ_EINVAL;
    if (f->kind == ROZ_LOOPBACK_DELAY && (f->arg < 1 || f->arg > ROZ_LOOPBACK_MAX_DELAY))
        return ROZ_EINVAL;
    lb->faults[lb->n_faults++] = *f;
    return ROZ_OK;
}

void roz_loopback_true_state(const roz_loopback_t *lb, double *state)
{
    compose(lb, state);
}

const double *roz_loopback_last_command(const roz_loopback_t *lb)
{
    return lb->have_cmd ? lb->cmd : NULL;
}
