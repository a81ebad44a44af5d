/* SPDX-License-Identifier: Apache-2.0 */
/* The G1's joints and IMU bound to the manifest's channels, and the
 * conversions between LowState_/LowCmd_ and channel values. Runs at open
 * (binding) and on the port's threads (the rest): no heap, no I/O. */
#include "g1_map.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "roz/hal/crc32.h"
#include "roz/hal/joints.h"

/* ---- binding --------------------------------------------------------------- */

/* Motor slots each hardware variant lacks (mode_machine, reference: the
 * SDK's 23-DoF enum and the locked-waist variants). */
#define G1_SLOTS_23DOF ((1u << 13) | (1u << 14) | (1u << 20) | (1u << 21) | (1u << 27) | (1u << 28))
#define G1_SLOTS_WAIST ((1u << 13) | (1u << 14))

int roz__g1_variant_refuses(const roz_unitree_g1_t *g1, uint32_t mode_machine, const char **why)
{
    uint32_t absent;

    switch (mode_machine) {
    case 4:
    case 10:
        absent = G1_SLOTS_23DOF;
        *why = "has no motor on a 23-DoF G1 (nothing is sent), mode_machine";
        break;
    case 6:
    case 12:
    case 14:
    case 16:
        absent = G1_SLOTS_WAIST;
        *why = "has no motor on a G1 with a locked waist (nothing is sent), mode_machine";
        break;
    default: /* 0 (simulation), and every other variant: the whole body */
        *why = NULL;
        return -1;
    }
    if ((g1->listed & absent) == 0u) {
        *why = NULL;
        return -1;
    }
    for (uint16_t k = 0; k < g1->n_joints; k++) {
        if ((absent >> g1->slot[k]) & 1u)
            return (int)k;
    }
    return -1; /* not reached: listed says one is */
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
        const unitree_hg_msg_dds__MotorState_ *ms = &s->motor_state[g1->slot[k]];
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
        uint32_t c = s->motor_state[g1->slot[k]].motorstate;
        if (c != 0u) {
            *code = c;
            return (int)k;
        }
    }
    *code = 0;
    return -1;
}

/* ---- the wireless remote ---------------------------------------------------------- */

/* The little-endian float at @p b, whatever the host's byte order. */
static float le_float(const uint8_t *b)
{
    uint32_t w = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 |
                 (uint32_t)b[3] << 24;
    float f;
    memcpy(&f, &w, sizeof f);
    return f;
}

int roz__g1_remote(const uint8_t raw[40], roz_operator_remote_t *out)
{
    out->buttons = (uint16_t)(raw[2] | raw[3] << 8);
    out->lx = le_float(raw + 4);
    out->rx = le_float(raw + 8);
    out->ry = le_float(raw + 12);
    out->l2 = le_float(raw + 16);
    out->ly = le_float(raw + 20);
    out->r2 = (out->buttons & ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_R2)) != 0u ? 1.0f : 0.0f;
    return !isfinite(out->lx) + !isfinite(out->rx) + !isfinite(out->ry) + !isfinite(out->l2) +
           !isfinite(out->ly);
}

/* ---- commands ------------------------------------------------------------------ */

void roz__g1_hold(const roz_unitree_g1_t *g1, const double *q, const double *last, double kd,
                  double *cmd)
{
    double jq[ROZ_UNITREE_G1_BODY];
    for (uint16_t k = 0; k < g1->n_joints; k++)
        jq[k] = q[g1->slot[k]];
    if (last != NULL)
        roz_joints_hold_keep(g1->m, g1->joint, g1->n_joints, last, jq, kd, cmd);
    else
        roz_joints_hold(g1->m, g1->joint, g1->n_joints, jq, kd, cmd);
}

/* Channel @p ch's command as a float inside its limits (0 without one):
 * the robot compares floats (test_g1_wire_inside_the_manifest). */
static float value(const roz_manifest_t *m, const double *cmd, int16_t ch)
{
    return ch >= 0 ? roz_channel_clamp_float(&m->commands[ch], cmd[ch]) : 0.0f;
}

/* A command the port makes up: 0, or the channel's end nearest 0. */
static float neutral(const roz_manifest_t *m, int16_t ch)
{
    return ch >= 0 ? roz_channel_clamp_float(&m->commands[ch], 0.0) : 0.0f;
}

static void seal(g1_cmd_t *out)
{
    out->crc = roz_crc32_words((const uint32_t *)(const void *)out, G1_CMD_CRC_WORDS);
}

/* A command's header, and its joints' motors enabled (mode 1): slots
 * without a manifest joint stay as zeroed, mode 0, disabled. */
static void begin(const roz_unitree_g1_t *g1, uint8_t mode_machine, g1_cmd_t *out)
{
    out->mode_pr = g1->mode_pr;
    out->mode_machine = mode_machine;
    for (uint16_t k = 0; k < g1->n_joints; k++)
        out->motor_cmd[g1->slot[k]].mode = 1;
}

void roz__g1_fill(const roz_unitree_g1_t *g1, const double *cmd, const double *q,
                  uint8_t mode_machine, g1_cmd_t *out)
{
    const roz_manifest_t *m = g1->m;
    begin(g1, mode_machine, out);
    for (uint16_t k = 0; k < g1->n_joints; k++) {
        const roz_unitree_g1_joint_t *j = &g1->joint[k];
        unitree_hg_msg_dds__MotorCmd_ *mc = &out->motor_cmd[g1->slot[k]];
        mc->q = value(m, cmd, j->q_cmd);
        mc->dq = value(m, cmd, j->dq_cmd);
        mc->tau = value(m, cmd, j->tau_cmd);
        mc->kp = value(m, cmd, j->kp_cmd);
        mc->kd = value(m, cmd, j->kd_cmd);
        if (j->q_cmd < 0) {
            /* no position command: the measured position, inside its
             * state's limits, under the stiffness; never measured (or not
             * a number): 0, and no stiffness the manifest can avoid */
            double qk = q[g1->slot[k]];
            if (isfinite(qk) && j->q_state >= 0)
                qk = roz_channel_clamp_float(&m->states[j->q_state], qk);
            if (fabs(qk) <= FLT_MAX) { /* finite, as a float too */
                mc->q = (float)qk;
            } else {
                mc->q = 0.0f;
                mc->kp = neutral(m, j->kp_cmd);
            }
        }
    }
    seal(out);
}

void roz__g1_fill_damping(const roz_unitree_g1_t *g1, const double *q, double kd, int hold,
                          uint8_t mode_machine, g1_cmd_t *out)
{
    const roz_manifest_t *m = g1->m;
    begin(g1, mode_machine, out);
    for (uint16_t k = 0; k < g1->n_joints; k++) {
        const roz_unitree_g1_joint_t *j = &g1->joint[k];
        unitree_hg_msg_dds__MotorCmd_ *mc = &out->motor_cmd[g1->slot[k]];
        /* no stiffness, velocity or torque, as far as the manifest allows;
         * a joint without a position command at @p q, its measured position
         * (inside its state's limits): never 0 rad under a hold gain, and
         * no stiffness where nothing was measured (test_g1_watchdog_hold_
         * rules) */
        double qk = q[k];
        int known = fabs(qk) <= FLT_MAX; /* finite, as a float too */
        if (j->q_cmd >= 0)
            mc->q = roz_channel_clamp_float(&m->commands[j->q_cmd], qk);
        else if (known && j->q_state >= 0)
            mc->q = roz_channel_clamp_float(&m->states[j->q_state], qk);
        else
            mc->q = known ? (float)qk : 0.0f;
        mc->dq = neutral(m, j->dq_cmd);
        mc->tau = neutral(m, j->tau_cmd);
        mc->kp = neutral(m, j->kp_cmd);
        if (j->kd_cmd >= 0) {
            const roz_channel_t *c = &m->commands[j->kd_cmd];
            mc->kd = roz_channel_clamp_float(c, kd == kd ? kd : c->default_value);
        }
        if (hold && j->kp_cmd >= 0 && (known || j->q_cmd >= 0))
            mc->kp = (float)m->commands[j->kp_cmd].default_value; /* within it: a valid manifest */
    }
    seal(out);
}
