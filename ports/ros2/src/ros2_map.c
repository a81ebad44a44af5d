/* SPDX-License-Identifier: Apache-2.0 */
/* The manifest's joints and IMU bound to a robot's joint slots, and the
 * conversions between channel values and joint commands. Binding runs at
 * open; the rest on the tick and the writer thread: no heap, no I/O. */
#include "ros2_map.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- binding ------------------------------------------------------------------ */

/* The robot's slot of manifest joint @p j, found by its name among the
 * robot's joints (a joint listed under another name, or in another order
 * than the robot's, would otherwise drive the wrong actuator). */
static int place(roz_ros2_bridge_t *b, uint16_t j, const char *joint, char *err, size_t errlen)
{
    const roz_ros2_robot_t *r = b->robot;

    for (uint16_t g = 0; g < r->n_groups; g++) {
        for (uint16_t s = 0; s < r->groups[g].n_slots; s++) {
            if (strcmp(r->groups[g].slots[s], joint) == 0) {
                b->place[j].group = g;
                b->place[j].slot = s;
                return ROZ_OK;
            }
        }
    }
    return roz_joints_not_the_robots(r->port, j, joint, r->n_groups > 1 ? " by group" : "", err,
                                     errlen);
}

int roz__ros2_bind(roz_ros2_bridge_t *b, const roz_manifest_t *m, char *err, size_t errlen)
{
    uint8_t state_bound[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    uint8_t cmd_bound[ROZ_CFG_MAX_COMMANDS];
    const roz_hardware_t *hw = m->hardware;
    const roz_ros2_robot_t *r = b->robot;

    memset(state_bound, 0, sizeof state_bound);
    memset(cmd_bound, 0, sizeof cmd_bound);
    b->n_slots = 0;
    if (r->n_groups == 0 || r->n_groups > ROZ_ROS2_MAX_GROUPS) {
        snprintf(err, errlen, "%s: %u joint groups; the bridge takes 1..%d", r->port,
                 (unsigned)r->n_groups, ROZ_ROS2_MAX_GROUPS);
        return ROZ_EINVAL;
    }
    for (uint16_t g = 0; g < r->n_groups; g++) {
        if (r->groups[g].n_slots == 0 || r->groups[g].n_slots > ROZ_ROS2_MAX_SLOTS ||
            b->n_slots + r->groups[g].n_slots > ROZ_ROS2_MAX_ROBOT_SLOTS) {
            snprintf(err, errlen, "%s: group %s has %u joints; the bridge takes 1..%d a group, %d "
                     "in all",
                     r->port, r->groups[g].name, (unsigned)r->groups[g].n_slots,
                     ROZ_ROS2_MAX_SLOTS, ROZ_ROS2_MAX_ROBOT_SLOTS);
            return ROZ_EINVAL;
        }
        b->group_base[g] = b->n_slots;
        b->n_slots = (uint16_t)(b->n_slots + r->groups[g].n_slots);
    }
    for (uint16_t s = 0; s < ROZ_ROS2_MAX_ROBOT_SLOTS; s++)
        b->slot_joint[s] = -1;
    if (hw == NULL || hw->n_joints == 0 || hw->n_joints > ROZ_CFG_MAX_JOINTS) {
        snprintf(err, errlen,
                 "%s: manifest %s: [hardware] joints must list the robot's joints (1..%u), it "
                 "lists %u",
                 r->port, m->robot_id, (unsigned)b->n_slots,
                 hw != NULL ? (unsigned)hw->n_joints : 0u);
        return ROZ_ENOENT;
    }
    if (hw->n_joints > b->n_slots) {
        snprintf(err, errlen,
                 "%s: manifest %s: [hardware] joints lists %u joints; the robot has %u", r->port,
                 m->robot_id, (unsigned)hw->n_joints, (unsigned)b->n_slots);
        return ROZ_ENOENT;
    }
    b->n_joints = hw->n_joints;
    for (uint16_t j = 0; j < hw->n_joints; j++) {
        const char *joint = hw->joints[j];
        if (place(b, j, joint, err, errlen) != ROZ_OK)
            return ROZ_ENOENT;
        uint16_t rs = (uint16_t)(b->group_base[b->place[j].group] + b->place[j].slot);
        if (b->slot_joint[rs] >= 0) {
            snprintf(err, errlen, "%s: [hardware] joints[%u] \"%s\" is listed twice", r->port,
                     (unsigned)j, joint);
            return ROZ_ENOENT;
        }
        b->slot_joint[rs] = (int16_t)j;
    }
    for (int k = 0; k < ROZ_IMU_VALUES; k++)
        b->imu[k] = -1;
    return roz_joints_bind(m, r->port, "this robot", hw->joints, hw->n_joints, b->joint,
                           r->imu_topic != NULL ? b->imu : NULL, err, errlen);
}

static uint16_t robot_slot(const roz_ros2_bridge_t *b, uint16_t k)
{
    return (uint16_t)(b->group_base[b->place[k].group] + b->place[k].slot);
}

void roz__ros2_hold(const roz_ros2_bridge_t *b, const double *q, const double *last, double kd,
                    double *cmd)
{
    double qj[ROZ_CFG_MAX_JOINTS];
    for (uint16_t k = 0; k < b->n_joints; k++)
        qj[k] = q[robot_slot(b, k)];
    if (last != NULL)
        roz_joints_hold_keep(b->m, b->joint, b->n_joints, last, qj, kd, cmd);
    else
        roz_joints_hold(b->m, b->joint, b->n_joints, qj, kd, cmd);
}

static double value(const double *cmd, int16_t ch)
{
    return ch >= 0 ? cmd[ch] : 0.0;
}

/* A command the port makes up for a channel (0 where the channel allows
 * it, else its end nearest 0); 0 without a channel. */
static double neutral(const roz_manifest_t *m, int16_t ch)
{
    return ch >= 0 ? roz_channel_clamp(&m->commands[ch], 0.0) : 0.0;
}

/* The position sent to slot @p s of joint @p k (-1: none) that the
 * manifest does not command: the measured one @p q, inside the joint's
 * position state limits; *known 0 when there is none (never measured, or
 * not a number): the slot then gets 0 and no stiffness. Every value on the
 * wire is finite and inside the manifest (test_x2_nonfinite_state_never_on_
 * the_wire, test_pm01_joints_by_name). */
static double measured(const roz_ros2_bridge_t *b, int16_t k, double q, int *known)
{
    *known = isfinite(q);
    if (!*known)
        return 0.0;
    if (k >= 0 && b->joint[k].q_state >= 0) {
        const roz_channel_t *c = &b->m->states[b->joint[k].q_state];
        q = q < c->min ? c->min : q > c->max ? c->max : q;
    }
    return q;
}

/* Slot @p s's command zeroed but for its measured position: the channels
 * of the manifest joint on it, NULL for none (no gains, no torque). */
static const roz_joint_channels_t *begin_slot(const roz_ros2_bridge_t *b, uint16_t s,
                                              const double *q, roz_ros2_joint_cmd_t *o,
                                              int *known)
{
    int16_t k = b->slot_joint[s];
    memset(o, 0, sizeof *o);
    o->q = measured(b, k, q[s], known);
    return k >= 0 ? &b->joint[k] : NULL;
}

void roz__ros2_joints(const roz_ros2_bridge_t *b, const double *cmd, const double *q,
                      roz_ros2_joint_cmd_t *out)
{
    const roz_manifest_t *m = b->m;
    for (uint16_t s = 0; s < b->n_slots; s++) {
        roz_ros2_joint_cmd_t *o = &out[s];
        int known;
        const roz_joint_channels_t *j = begin_slot(b, s, q, o, &known);
        if (j == NULL)
            continue;
        if (j->q_cmd >= 0) {
            o->q = cmd[j->q_cmd];
            known = 1;
        }
        o->dq = value(cmd, j->dq_cmd);
        o->tau = value(cmd, j->tau_cmd);
        o->kp = known ? value(cmd, j->kp_cmd) : neutral(m, j->kp_cmd);
        o->kd = value(cmd, j->kd_cmd);
    }
}

void roz__ros2_damping(const roz_ros2_bridge_t *b, const double *q, double kd, int hold,
                       roz_ros2_joint_cmd_t *out)
{
    const roz_manifest_t *m = b->m;
    for (uint16_t s = 0; s < b->n_slots; s++) {
        roz_ros2_joint_cmd_t *o = &out[s];
        int known;
        const roz_joint_channels_t *j = begin_slot(b, s, q, o, &known);
        if (j == NULL)
            continue;
        /* no stiffness, velocity or torque, as far as the manifest allows */
        if (j->q_cmd >= 0)
            o->q = roz_channel_clamp(&m->commands[j->q_cmd], o->q);
        o->dq = neutral(m, j->dq_cmd);
        o->tau = neutral(m, j->tau_cmd);
        o->kp = neutral(m, j->kp_cmd);
        if (j->kd_cmd >= 0) {
            const roz_channel_t *c = &m->commands[j->kd_cmd];
            o->kd = roz_channel_clamp(c, kd == kd ? kd : c->default_value);
        }
        /* the hold gain only where there is a position to hold: never 0
         * rad under it (test_pm01_watchdog_keeps_the_torque) */
        if (hold && j->kp_cmd >= 0 && known)
            o->kp = m->commands[j->kp_cmd].default_value; /* within it: a valid manifest */
    }
}
