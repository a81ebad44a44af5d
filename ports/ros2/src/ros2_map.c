/* SPDX-License-Identifier: Apache-2.0 */
/* The manifest's joints and IMU bound to a robot's joint slots, and the
 * conversions between channel values and joint commands. Binding runs at
 * open; the rest on the tick and the writer thread: no heap, no I/O. */
#include "ros2_map.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- binding ------------------------------------------------------------------ */

/* The channels served per joint, with their interface type. */
static const struct {
    const char     *suffix;
    roz_interface_t type;
} joint_states[3] = { { "position", ROZ_IF_POSITION },
                      { "velocity", ROZ_IF_VELOCITY },
                      { "effort", ROZ_IF_EFFORT } },
  joint_cmds[5] = { { "position", ROZ_IF_POSITION },
                    { "velocity", ROZ_IF_VELOCITY },
                    { "effort", ROZ_IF_EFFORT },
                    { "stiffness", ROZ_IF_STIFFNESS },
                    { "damping", ROZ_IF_DAMPING } };

/* The IMU's states, in the order of roz_ros2_bridge_t.imu. */
static const struct {
    const char     *name;
    roz_interface_t type;
} imu_states[ROZ_ROS2_IMU_VALUES] = {
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
 * when absent; ROZ_EINVAL (err said) when its type is not @p type. */
static int find(const roz_ros2_bridge_t *b, int is_state, const char *joint, const char *suffix,
                roz_interface_t type, uint8_t *bound, int *out, char *err, size_t errlen)
{
    const roz_manifest_t *m = b->m;
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
        snprintf(err, errlen, "%s: %s %d \"%s\" is a %s channel; the port serves it as %s",
                 b->robot->port, is_state ? "state" : "command", i, name,
                 roz_interface_name(c->type), roz_interface_name(type));
        return ROZ_EINVAL;
    }
    bound[i] = 1;
    *out = i;
    return ROZ_OK;
}

/* The robot's slot of manifest joint @p j, found by its name among the
 * robot's joints (a joint listed under another name, or in another order
 * than the robot's, would otherwise drive the wrong actuator). */
static int place(roz_ros2_bridge_t *b, uint16_t j, const char *joint, char *err, size_t errlen)
{
    const roz_ros2_robot_t *r = b->robot;

    for (uint16_t g = 0; g < r->n_groups; g++) {
        for (uint16_t s = 0; s < r->groups[g].n_slots; s++) {
            if (strcmp(r->groups[g].slots[s], joint) == 0) {
                b->joint[j].group = g;
                b->joint[j].slot = s;
                return ROZ_OK;
            }
        }
    }
    snprintf(err, errlen,
             "%s: [hardware] joints[%u] \"%s\" is not one of the robot's joints (the port's "
             "header lists them%s)",
             r->port, (unsigned)j, joint, r->n_groups > 1 ? " by group" : "");
    return ROZ_EINVAL;
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
        return ROZ_EINVAL;
    }
    if (hw->n_joints > b->n_slots) {
        snprintf(err, errlen, "%s: manifest %s: [hardware] joints lists %u joints; the robot has %u",
                 r->port, m->robot_id, (unsigned)hw->n_joints, (unsigned)b->n_slots);
        return ROZ_EINVAL;
    }
    b->n_joints = hw->n_joints;
    for (uint16_t j = 0; j < hw->n_joints; j++) {
        const char *joint = hw->joints[j];
        roz_ros2_joint_t *jt = &b->joint[j];
        int idx[8];
        if (place(b, j, joint, err, errlen) != ROZ_OK)
            return ROZ_EINVAL;
        uint16_t rs = (uint16_t)(b->group_base[jt->group] + jt->slot);
        if (b->slot_joint[rs] >= 0) {
            snprintf(err, errlen, "%s: [hardware] joints[%u] \"%s\" is listed twice", r->port,
                     (unsigned)j, joint);
            return ROZ_EINVAL;
        }
        b->slot_joint[rs] = (int16_t)j;
        for (int k = 0; k < 3; k++) {
            if (find(b, 1, joint, joint_states[k].suffix, joint_states[k].type, state_bound,
                     &idx[k], err, errlen) != ROZ_OK)
                return ROZ_EINVAL;
        }
        for (int k = 0; k < 5; k++) {
            if (find(b, 0, joint, joint_cmds[k].suffix, joint_cmds[k].type, cmd_bound,
                     &idx[3 + k], err, errlen) != ROZ_OK)
                return ROZ_EINVAL;
        }
        jt->q_state = (int16_t)idx[0];
        jt->dq_state = (int16_t)idx[1];
        jt->tau_state = (int16_t)idx[2];
        jt->q_cmd = (int16_t)idx[3];
        jt->dq_cmd = (int16_t)idx[4];
        jt->tau_cmd = (int16_t)idx[5];
        jt->kp_cmd = (int16_t)idx[6];
        jt->kd_cmd = (int16_t)idx[7];
        int any = 0;
        for (int k = 0; k < 8; k++)
            any |= idx[k] >= 0;
        if (!any) {
            snprintf(err, errlen,
                     "%s: [hardware] joints[%u] \"%s\" has no channel in manifest %s (expected "
                     "%s/position, /velocity, /effort, /stiffness, /damping)",
                     r->port, (unsigned)j, joint, m->robot_id, joint);
            return ROZ_EINVAL;
        }
    }
    for (int k = 0; k < ROZ_ROS2_IMU_VALUES; k++) {
        int i = r->imu_topic != NULL ? roz_manifest_find_state(m, imu_states[k].name) : -1;
        if (i >= 0 && m->states[i].type != imu_states[k].type) {
            snprintf(err, errlen, "%s: state %d \"%s\" is a %s channel; expected %s", r->port, i,
                     imu_states[k].name, roz_interface_name(m->states[i].type),
                     roz_interface_name(imu_states[k].type));
            return ROZ_EINVAL;
        }
        if (i >= 0)
            state_bound[i] = 1;
        b->imu[k] = (int16_t)(i >= 0 ? i : -1);
    }
    /* every channel has its place, or the port cannot serve the manifest */
    for (uint16_t i = 0; i < m->n_states; i++) {
        if (!state_bound[i]) {
            snprintf(err, errlen,
                     "%s: state %u \"%s\" has no source on this robot (joint states are "
                     "<joint>/position, /velocity, /effort of a [hardware] joint%s)",
                     r->port, (unsigned)i, m->states[i].name,
                     r->imu_topic != NULL ? "; the IMU is base_imu/orientation.x..w, "
                                            "angular_velocity.x..z, linear_acceleration.x..z"
                                          : "");
            return ROZ_EINVAL;
        }
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (!cmd_bound[i]) {
            snprintf(err, errlen,
                     "%s: command %u \"%s\" has no place on this robot (commands are "
                     "<joint>/position, /velocity, /effort, /stiffness, /damping of a [hardware] "
                     "joint)",
                     r->port, (unsigned)i, m->commands[i].name);
            return ROZ_EINVAL;
        }
    }
    return ROZ_OK;
}

int roz__ros2_damping_range(const roz_ros2_bridge_t *b, double *lo, double *hi)
{
    int n = 0;
    *lo = 0.0;
    *hi = 0.0;
    for (uint16_t j = 0; j < b->n_joints; j++) {
        int16_t c = b->joint[j].kd_cmd;
        if (c < 0)
            continue;
        const roz_channel_t *ch = &b->m->commands[c];
        *lo = n == 0 ? ch->min : fmax(*lo, ch->min);
        *hi = n == 0 ? ch->max : fmin(*hi, ch->max);
        n++;
    }
    return n;
}

/* ---- commands ------------------------------------------------------------------- */

static double clamp_to(const roz_channel_t *c, double v)
{
    if (!(v == v))
        return c->default_value;
    return v < c->min ? c->min : v > c->max ? c->max : v;
}

static uint16_t robot_slot(const roz_ros2_bridge_t *b, const roz_ros2_joint_t *j)
{
    return (uint16_t)(b->group_base[j->group] + j->slot);
}

void roz__ros2_hold(const roz_ros2_bridge_t *b, const double *q, double kd, double *cmd)
{
    const roz_manifest_t *m = b->m;
    for (uint16_t i = 0; i < m->n_commands; i++)
        cmd[i] = clamp_to(&m->commands[i], 0.0);
    for (uint16_t k = 0; k < b->n_joints; k++) {
        const roz_ros2_joint_t *j = &b->joint[k];
        if (j->q_cmd >= 0)
            cmd[j->q_cmd] = clamp_to(&m->commands[j->q_cmd], q[robot_slot(b, j)]);
        if (j->kd_cmd >= 0)
            cmd[j->kd_cmd] = clamp_to(&m->commands[j->kd_cmd], kd);
    }
}

uint32_t roz__ros2_clamp(const roz_ros2_bridge_t *b, const double *in, double *out)
{
    const roz_manifest_t *m = b->m;
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

static double value(const double *cmd, int16_t ch)
{
    return ch >= 0 ? cmd[ch] : 0.0;
}

void roz__ros2_joints(const roz_ros2_bridge_t *b, const double *cmd, const double *q,
                      roz_ros2_joint_cmd_t *out)
{
    for (uint16_t s = 0; s < b->n_slots; s++) {
        roz_ros2_joint_cmd_t *o = &out[s];
        int16_t k = b->slot_joint[s];
        memset(o, 0, sizeof *o);
        o->q = q[s];
        if (k < 0)
            continue; /* no joint of the manifest: no gains, no torque */
        const roz_ros2_joint_t *j = &b->joint[k];
        if (j->q_cmd >= 0)
            o->q = cmd[j->q_cmd];
        o->dq = value(cmd, j->dq_cmd);
        o->tau = value(cmd, j->tau_cmd);
        o->kp = value(cmd, j->kp_cmd);
        o->kd = value(cmd, j->kd_cmd);
    }
}

void roz__ros2_damping(const roz_ros2_bridge_t *b, const double *q, double kd,
                       roz_ros2_joint_cmd_t *out)
{
    const roz_manifest_t *m = b->m;
    for (uint16_t s = 0; s < b->n_slots; s++) {
        roz_ros2_joint_cmd_t *o = &out[s];
        int16_t k = b->slot_joint[s];
        memset(o, 0, sizeof *o);
        o->q = q[s];
        if (k < 0)
            continue;
        const roz_ros2_joint_t *j = &b->joint[k];
        if (j->q_cmd >= 0)
            o->q = clamp_to(&m->commands[j->q_cmd], q[s]);
        if (j->kd_cmd >= 0) {
            const roz_channel_t *c = &m->commands[j->kd_cmd];
            o->kd = clamp_to(c, kd == kd ? kd : c->default_value);
        }
    }
}
