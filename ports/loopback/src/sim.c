/* SPDX-License-Identifier: Apache-2.0 */
/* The simulated robot of the loopback port: channel binding by name and the
 * joint and base models (roz/port/loopback.h lists them). */
#include "sim.h"

#include <math.h>
#include <string.h>

#include "roz/abi.h"

/* Not the C library's math: the simulator computes the same bits on every
 * target (glibc and newlib differ in the last bit now and then), so a
 * firmware image and the host agree (test/firmware/). sin and cos are the
 * core's (the controller ABI's, one copy in the image); exp and atan2 the
 * controller SDK's roz_math.h. */
#include "roz_math.h"

enum { M_DEFAULT = 0, M_JOINT_POS, M_JOINT_VEL, M_JOINT_EFF, M_BASE };

#define INERTIA 0.05  /* kg*m^2 of every simulated joint */
#define FRICTION 0.05 /* N*m*s/rad viscous friction */

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
        jt->q += (target - jt->q) * (1.0 - roz_math_exp(-dt / ROZ_LOOPBACK_TAU_S));
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
    lb->base[0] += (v[0] * roz_abi_math_cos(yaw) - v[1] * roz_abi_math_sin(yaw)) * lb->dt;
    lb->base[1] += (v[0] * roz_abi_math_sin(yaw) + v[1] * roz_abi_math_cos(yaw)) * lb->dt;
    lb->base[2] += v[2] * lb->dt;
    yaw += v[3] * lb->dt;
    /* wrap to [-pi, pi] */
    lb->base[3] = roz_math_atan2(roz_abi_math_sin(yaw), roz_abi_math_cos(yaw));
}

void roz_lbsim_compose(const roz_loopback_t *lb, double *state)
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

void roz_lbsim_open(roz_loopback_t *lb)
{
    const roz_manifest_t *m = lb->m;

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
}

void roz_lbsim_step(roz_loopback_t *lb)
{
    for (uint16_t j = 0; j < lb->n_joints; j++)
        step_joint(lb, &lb->joints[j]);
    step_base(lb);
}
