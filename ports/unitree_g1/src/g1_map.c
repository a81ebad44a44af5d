/* SPDX-License-Identifier: Apache-2.0 */
/* The G1's joints and IMU bound to the manifest's channels, and the
 * conversions between LowState_/LowCmd_ and channel values. Runs at open
 * (binding) and on the port's threads (the rest): no heap, no I/O. */
#include "g1_map.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "roz/hal/crc32.h"

/* ---- binding --------------------------------------------------------------- */

/* The channel names the port serves per joint, with their interface type. */
static const struct {
    const char     *suffix;
    roz_interface_t type;
} joint_states[] = { { "position", ROZ_IF_POSITION },
                     { "velocity", ROZ_IF_VELOCITY },
                     { "effort", ROZ_IF_EFFORT } },
  joint_cmds[] = { { "position", ROZ_IF_POSITION },
                   { "velocity", ROZ_IF_VELOCITY },
                   { "effort", ROZ_IF_EFFORT },
                   { "stiffness", ROZ_IF_STIFFNESS },
                   { "damping", ROZ_IF_DAMPING } };

/* The IMU: manifest state name, its type (g1->imu[] order). */
static const struct {
    const char     *name;
    roz_interface_t type;
} imu_states[10] = {
    { "base_imu/orientation.x", ROZ_IF_ORIENTATION },
    { "base_imu/orientation.y", ROZ_IF_ORIENTATION },
    { "base_imu/orientation.z", ROZ_IF_ORIENTATION },
    { "base_imu/orientation.w", ROZ_IF_ORIENTATION },
    { "base_imu/angular_velocity.x", ROZ_IF_VELOCITY },
    { "base_imu/angular_velocity.y", ROZ_IF_VELOCITY },
    { "base_imu/angular_velocity.z", ROZ_IF_VELOCITY },
    { "base_imu/linear_acceleration.x", ROZ_IF_ACCELERATION },
    { "base_imu/linear_acceleration.y", ROZ_IF_ACCELERATION },
    { "base_imu/linear_acceleration.z", ROZ_IF_ACCELERATION },
};

/* Finds "<joint>/<suffix>" among states or commands: *out its index, -1
 * if absent; ROZ_EINVAL (err said) if its type is not @p type. */
static int find(const roz_manifest_t *m, int is_state, const char *joint, const char *suffix,
                roz_interface_t type, uint8_t *bound, int *out, char *err, size_t errlen)
{
    char name[160];
    int n = snprintf(name, sizeof name, "%s/%s", joint, suffix);
    *out = -1;
    if (n < 0 || (size_t)n >= sizeof name)
        return ROZ_OK; /* longer than any channel name can be: absent */
    int i = is_state ? roz_manifest_find_state(m, name) : roz_manifest_find_command(m, name);
    if (i < 0)
        return ROZ_OK;
    const roz_channel_t *c = is_state ? &m->states[i] : &m->commands[i];
    if (c->type != type) {
        snprintf(err, errlen,
                 "unitree/G1: %s %d \"%s\" is a %s channel; the G1 port serves \"%s\" as %s",
                 is_state ? "state" : "command", i, name, roz_interface_name(c->type), name,
                 roz_interface_name(type));
        return ROZ_EINVAL;
    }
    bound[i] = 1;
    *out = i;
    return ROZ_OK;
}

int roz__g1_bind(roz_unitree_g1_t *g1, const roz_manifest_t *m, char *err, size_t errlen)
{
    uint8_t state_bound[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    uint8_t cmd_bound[ROZ_CFG_MAX_COMMANDS];
    const roz_hardware_t *hw = m->hardware;

    memset(state_bound, 0, sizeof state_bound);
    memset(cmd_bound, 0, sizeof cmd_bound);
    if (hw == NULL || hw->n_joints == 0 || hw->n_joints > ROZ_UNITREE_G1_BODY) {
        snprintf(err, errlen,
                 "unitree/G1: manifest %s: [hardware] joints must list 1..%d joints in the SDK's "
                 "motor order (motor_cmd/motor_state index), it lists %u",
                 m->robot_id, ROZ_UNITREE_G1_BODY, hw != NULL ? (unsigned)hw->n_joints : 0u);
        return ROZ_EINVAL;
    }
    for (size_t s = 0; s < ROZ_UNITREE_G1_SLOTS; s++) {
        roz_unitree_g1_joint_t *j = &g1->joint[s];
        j->q_state = j->dq_state = j->tau_state = -1;
        j->q_cmd = j->dq_cmd = j->tau_cmd = j->kp_cmd = j->kd_cmd = -1;
    }
    g1->n_joints = hw->n_joints;
    for (uint16_t s = 0; s < hw->n_joints; s++) {
        const char *joint = hw->joints[s];
        roz_unitree_g1_joint_t *j = &g1->joint[s];
        int idx[8];
        for (int k = 0; k < 3; k++) {
            if (find(m, 1, joint, joint_states[k].suffix, joint_states[k].type, state_bound,
                     &idx[k], err, errlen) != ROZ_OK)
                return ROZ_EINVAL;
        }
        for (int k = 0; k < 5; k++) {
            if (find(m, 0, joint, joint_cmds[k].suffix, joint_cmds[k].type, cmd_bound,
                     &idx[3 + k], err, errlen) != ROZ_OK)
                return ROZ_EINVAL;
        }
        j->q_state = (int16_t)idx[0];
        j->dq_state = (int16_t)idx[1];
        j->tau_state = (int16_t)idx[2];
        j->q_cmd = (int16_t)idx[3];
        j->dq_cmd = (int16_t)idx[4];
        j->tau_cmd = (int16_t)idx[5];
        j->kp_cmd = (int16_t)idx[6];
        j->kd_cmd = (int16_t)idx[7];
        int any = 0;
        for (int k = 0; k < 8; k++)
            any |= idx[k] >= 0;
        if (!any) {
            snprintf(err, errlen,
                     "unitree/G1: [hardware] joints[%u] \"%s\" has no channel in manifest %s "
                     "(expected %s/position, /velocity, /effort, /stiffness, /damping)",
                     (unsigned)s, joint, m->robot_id, joint);
            return ROZ_EINVAL;
        }
    }
    for (int k = 0; k < 10; k++) {
        int i = roz_manifest_find_state(m, imu_states[k].name);
        if (i >= 0 && m->states[i].type != imu_states[k].type) {
            snprintf(err, errlen, "unitree/G1: state %d \"%s\" is a %s channel; expected %s", i,
                     imu_states[k].name, roz_interface_name(m->states[i].type),
                     roz_interface_name(imu_states[k].type));
            return ROZ_EINVAL;
        }
        if (i >= 0)
            state_bound[i] = 1;
        g1->imu[k] = (int16_t)(i >= 0 ? i : -1);
    }
    /* every channel has its place, or the port cannot serve the manifest */
    for (uint16_t i = 0; i < m->n_states; i++) {
        if (!state_bound[i]) {
            snprintf(err, errlen,
                     "unitree/G1: state %u \"%s\" has no source on the G1 (joint states are "
                     "<joint>/position, /velocity, /effort of a [hardware] joint; the IMU is "
                     "base_imu/orientation.x..w, angular_velocity.x..z, linear_acceleration.x..z)",
                     (unsigned)i, m->states[i].name);
            return ROZ_EINVAL;
        }
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (!cmd_bound[i]) {
            snprintf(err, errlen,
                     "unitree/G1: command %u \"%s\" has no place on the G1 (commands are "
                     "<joint>/position, /velocity, /effort, /stiffness, /damping of a [hardware] "
                     "joint)",
                     (unsigned)i, m->commands[i].name);
            return ROZ_EINVAL;
        }
    }
    return ROZ_OK;
}

int roz__g1_damping_range(const roz_unitree_g1_t *g1, double *lo, double *hi)
{
    int n = 0;
    *lo = 0.0;
    *hi = 0.0;
    for (uint16_t s = 0; s < g1->n_joints; s++) {
        int16_t c = g1->joint[s].kd_cmd;
        if (c < 0)
            continue;
        const roz_channel_t *ch = &g1->m->commands[c];
        *lo = n == 0 ? ch->min : fmax(*lo, ch->min);
        *hi = n == 0 ? ch->max : fmin(*hi, ch->max);
        n++;
    }
    return n;
}

/* ---- state ----------------------------------------------------------------- */

int roz__g1_state_crc_ok(const g1_state_t *s)
{
    return roz_crc32_words((const uint32_t *)(const void *)s, G1_STATE_CRC_WORDS) == s->crc;
}

void roz__g1_convert(const roz_unitree_g1_t *g1, const g1_state_t *s, double *values, int full)
{
    for (uint16_t k = 0; k < g1->n_joints; k++) {
        const roz_unitree_g1_joint_t *j = &g1->joint[k];
        const unitree_hg_msg_dds__MotorState_ *ms = &s->motor_state[k];
        if (j->q_state >= 0)
            values[j->q_state] = ms->q;
        if (!full)
            continue;
        if (j->dq_state >= 0)
            values[j->dq_state] = ms->dq;
        if (j->tau_state >= 0)
            values[j->tau_state] = ms->tau_est;
    }
    if (!full)
        return;
    /* Unitree's quaternion is w, x, y, z; the manifest's x, y, z, w */
    const float raw[10] = { s->imu_state.quaternion[1],    s->imu_state.quaternion[2],
                            s->imu_state.quaternion[3],    s->imu_state.quaternion[0],
                            s->imu_state.gyroscope[0],     s->imu_state.gyroscope[1],
                            s->imu_state.gyroscope[2],     s->imu_state.accelerometer[0],
                            s->imu_state.accelerometer[1], s->imu_state.accelerometer[2] };
    for (int k = 0; k < 10; k++) {
        if (g1->imu[k] >= 0)
            values[g1->imu[k]] = raw[k];
    }
}

int roz__g1_motor_fault(const roz_unitree_g1_t *g1, const g1_state_t *s, uint32_t *code)
{
    for (uint16_t k = 0; k < g1->n_joints; k++) {
        if (s->motor_state[k].motorstate != 0u) {
            *code = s->motor_state[k].motorstate;
            return (int)k;
        }
    }
    *code = 0;
    return -1;
}

/* ---- commands ------------------------------------------------------------------ */

static double clamp_to(const roz_channel_t *c, double v)
{
    if (!(v == v))
        return c->default_value;
    return v < c->min ? c->min : v > c->max ? c->max : v;
}

void roz__g1_hold(const roz_unitree_g1_t *g1, const double *q, double kd, double *cmd)
{
    const roz_manifest_t *m = g1->m;
    for (uint16_t i = 0; i < m->n_commands; i++)
        cmd[i] = clamp_to(&m->commands[i], 0.0);
    for (uint16_t k = 0; k < g1->n_joints; k++) {
        const roz_unitree_g1_joint_t *j = &g1->joint[k];
        if (j->q_cmd >= 0)
            cmd[j->q_cmd] = clamp_to(&m->commands[j->q_cmd], q[k]);
        if (j->kd_cmd >= 0)
            cmd[j->kd_cmd] = clamp_to(&m->commands[j->kd_cmd], kd);
    }
}

uint32_t roz__g1_clamp(const roz_unitree_g1_t *g1, const double *in, double *out)
{
    const roz_manifest_t *m = g1->m;
    uint32_t changed = 0;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        double v = in[i];
        if (!(v >= c->min && v <= c->max)) {
            v = clamp_to(c, v);
            changed++;
        }
        out[i] = v;
    }
    return changed;
}

static float value(const double *cmd, int16_t ch)
{
    return ch >= 0 ? (float)cmd[ch] : 0.0f;
}

static void seal(g1_cmd_t *out)
{
    out->crc = roz_crc32_words((const uint32_t *)(const void *)out, G1_CMD_CRC_WORDS);
}

void roz__g1_fill(const roz_unitree_g1_t *g1, const double *cmd, uint8_t mode_machine,
                  g1_cmd_t *out)
{
    out->mode_pr = g1->mode_pr;
    out->mode_machine = mode_machine;
    /* slots past the manifest's joints stay as zeroed: mode 0, disabled */
    for (uint16_t k = 0; k < g1->n_joints; k++) {
        const roz_unitree_g1_joint_t *j = &g1->joint[k];
        unitree_hg_msg_dds__MotorCmd_ *mc = &out->motor_cmd[k];
        mc->mode = 1;
        mc->q = value(cmd, j->q_cmd);
        mc->dq = value(cmd, j->dq_cmd);
        mc->tau = value(cmd, j->tau_cmd);
        mc->kp = value(cmd, j->kp_cmd);
        mc->kd = value(cmd, j->kd_cmd);
    }
    seal(out);
}

void roz__g1_fill_damping(const roz_unitree_g1_t *g1, const double *q, double kd,
                          uint8_t mode_machine, g1_cmd_t *out)
{
    const roz_manifest_t *m = g1->m;
    out->mode_pr = g1->mode_pr;
    out->mode_machine = mode_machine;
    for (uint16_t k = 0; k < g1->n_joints; k++) {
        const roz_unitree_g1_joint_t *j = &g1->joint[k];
        unitree_hg_msg_dds__MotorCmd_ *mc = &out->motor_cmd[k];
        mc->mode = 1;
        mc->q = j->q_cmd >= 0 ? (float)clamp_to(&m->commands[j->q_cmd], q[k]) : 0.0f;
        if (j->kd_cmd >= 0) {
            const roz_channel_t *c = &m->commands[j->kd_cmd];
            mc->kd = (float)clamp_to(c, kd == kd ? kd : c->default_value);
        }
    }
    seal(out);
}
