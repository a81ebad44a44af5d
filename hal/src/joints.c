/* SPDX-License-Identifier: Apache-2.0 */
/* A robot's joints and IMU bound to a manifest's channels, and the command
 * frames built from them. roz/hal/joints.h says what; here is how. */
#include "roz/hal/joints.h"

#include <math.h>
#include <string.h>

#include "roz/error.h"
#include "roz/hold.h"
#include "roz/format.h"

/* ---- binding ------------------------------------------------------------------ */

/* The channels served per joint, with their interface type, in the order of
 * roz_joint_channels_t's fields. */
static const struct {
    const char     *suffix;
    roz_interface_t type;
    int             is_state;
} joint_channels[8] = {
    { "position", ROZ_IF_POSITION, 1 },  { "velocity", ROZ_IF_VELOCITY, 1 },
    { "effort", ROZ_IF_EFFORT, 1 },      { "position", ROZ_IF_POSITION, 0 },
    { "velocity", ROZ_IF_VELOCITY, 0 },  { "effort", ROZ_IF_EFFORT, 0 },
    { "stiffness", ROZ_IF_STIFFNESS, 0 }, { "damping", ROZ_IF_DAMPING, 0 },
};

/* The IMU's states, in the order of the imu[] a port gets. */
static const struct {
    const char     *name;
    roz_interface_t type;
} imu_states[ROZ_IMU_VALUES] = {
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

/* Which channels found their place. */
typedef struct {
    uint8_t state[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    uint8_t command[ROZ_CFG_MAX_COMMANDS];
} bound_t;

/* Finds "<joint>/<suffix>" among states or commands: *out its index, -1
 * when absent; ROZ_EINVAL (err said) when its type is not @p type. */
static int find(const roz_manifest_t *m, const char *port, int is_state, const char *joint,
                const char *suffix, roz_interface_t type, bound_t *bound, int16_t *out,
                char *err, size_t errlen)
{
    char name[160];
    int n = roz_format(name, sizeof name, "%s/%s", joint, suffix);
    *out = -1;
    if (n < 0 || (size_t)n >= sizeof name)
        return ROZ_OK; /* longer than any channel name can be: absent */
    int i = is_state ? roz_manifest_find_state(m, name) : roz_manifest_find_command(m, name);
    if (i < 0)
        return ROZ_OK;
    const roz_channel_t *c = is_state ? &m->states[i] : &m->commands[i];
    if (c->type != type) {
        roz_format(err, errlen, "%s: %s %d \"%s\" has interface_type %s; the port serves it as %s", port,
                   is_state ? "state" : "command", i, name, roz_interface_name(c->type),
                   roz_interface_name(type));
        return ROZ_EINVAL;
    }
    if (is_state)
        bound->state[i] = 1;
    else
        bound->command[i] = 1;
    *out = (int16_t)i;
    return ROZ_OK;
}

static int bind_joint(const roz_manifest_t *m, const char *port, uint16_t index,
                      const char *joint, roz_joint_channels_t *out, bound_t *bound, char *err,
                      size_t errlen)
{
    int16_t *field[8] = { &out->q_state, &out->dq_state, &out->tau_state, &out->q_cmd,
                          &out->dq_cmd,  &out->tau_cmd,  &out->kp_cmd,    &out->kd_cmd };
    int any = 0;
    for (int k = 0; k < 8; k++) {
        if (find(m, port, joint_channels[k].is_state, joint, joint_channels[k].suffix,
                 joint_channels[k].type, bound, field[k], err, errlen) != ROZ_OK)
            return ROZ_EINVAL;
        any |= *field[k] >= 0;
    }
    if (!any) {
        roz_format(err, errlen,
                   "%s: [hardware] joints[%u] \"%s\" has no channel in manifest %s (expected "
                   "%s/position, /velocity, /effort, /stiffness, /damping)",
                   port, (unsigned)index, joint, m->robot_id, joint);
        return ROZ_ENOENT;
    }
    return ROZ_OK;
}

int roz_joints_bind(const roz_manifest_t *m, const char *port, const char *robot,
                    const char *const *names, uint16_t n, roz_joint_channels_t *out,
                    int16_t *imu, char *err, size_t errlen)
{
    bound_t bound;

    memset(&bound, 0, sizeof bound);
    for (uint16_t j = 0; j < n; j++) {
        int rc = bind_joint(m, port, j, names[j], &out[j], &bound, err, errlen);
        if (rc != ROZ_OK)
            return rc;
    }
    for (int k = 0; imu != NULL && k < ROZ_IMU_VALUES; k++) {
        int i = roz_manifest_find_state(m, imu_states[k].name);
        if (i >= 0 && m->states[i].type != imu_states[k].type) {
            roz_format(err, errlen, "%s: state %d \"%s\" has interface_type %s; expected %s", port, i,
                       imu_states[k].name, roz_interface_name(m->states[i].type),
                       roz_interface_name(imu_states[k].type));
            return ROZ_EINVAL;
        }
        if (i >= 0)
            bound.state[i] = 1;
        imu[k] = (int16_t)(i >= 0 ? i : -1);
    }
    /* every channel has its place, or the port cannot serve the manifest */
    for (uint16_t i = 0; i < m->n_states; i++) {
        if (!bound.state[i]) {
            roz_format(err, errlen,
                       "%s: state %u \"%s\" has no source on %s (joint states are "
                       "<joint>/position, /velocity, /effort of a [hardware] joint%s)",
                       port, (unsigned)i, m->states[i].name, robot,
                       imu != NULL ? "; the IMU is base_imu/orientation.x..w, "
                                   "angular_velocity.x..z, linear_acceleration.x..z"
                                 : "");
            return ROZ_EINVAL;
        }
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (!bound.command[i]) {
            roz_format(err, errlen,
                       "%s: command %u \"%s\" has no place on %s (commands are <joint>/position, "
                       "/velocity, /effort, /stiffness, /damping of a [hardware] joint)",
                       port, (unsigned)i, m->commands[i].name, robot);
            return ROZ_EINVAL;
        }
    }
    return ROZ_OK;
}

int roz_joints_damping_range(const roz_manifest_t *m, const roz_joint_channels_t *j, uint16_t n,
                             double *lo, double *hi)
{
    int found = 0;
    *lo = 0.0;
    *hi = 0.0;
    for (uint16_t k = 0; k < n; k++) {
        if (j[k].kd_cmd < 0)
            continue;
        const roz_channel_t *c = &m->commands[j[k].kd_cmd];
        *lo = found == 0 ? c->min : fmax(*lo, c->min);
        *hi = found == 0 ? c->max : fmin(*hi, c->max);
        found++;
    }
    return found;
}

/* ---- command frames ------------------------------------------------------------- */

double roz_channel_clamp(const roz_channel_t *c, double v)
{
    if (!(v == v))
        return c->default_value;
    return v < c->min ? c->min : v > c->max ? c->max : v;
}

float roz_channel_clamp_float(const roz_channel_t *c, double v)
{
    double d = roz_channel_clamp(c, v);
    float f = (float)d;
    if ((double)f > c->max)
        f = nextafterf(f, -INFINITY);
    else if ((double)f < c->min)
        f = nextafterf(f, INFINITY);
    return f;
}

void roz_joints_hold(const roz_manifest_t *m, const roz_joint_channels_t *j, uint16_t n,
                     const double *q, double kd, double *cmd)
{
    for (uint16_t i = 0; i < m->n_commands; i++)
        cmd[i] = roz_channel_clamp(&m->commands[i], 0.0);
    for (uint16_t k = 0; k < n; k++) {
        if (j[k].q_cmd >= 0)
            cmd[j[k].q_cmd] = roz_channel_clamp(&m->commands[j[k].q_cmd], q[k]);
        if (j[k].kd_cmd >= 0)
            cmd[j[k].kd_cmd] = roz_channel_clamp(&m->commands[j[k].kd_cmd], kd);
    }
}

double roz_joints_hold_setpoint(const roz_manifest_t *m, const roz_joint_channels_t *j,
                                double last_q, double last_kp, double measured)
{
    roz_hold_from_t from = { j->q_cmd >= 0 ? last_q : NAN, j->kp_cmd >= 0 ? last_kp : NAN,
                             measured };
    double kp_hold = j->kp_cmd >= 0 ? m->commands[j->kp_cmd].default_value : NAN;
    double band = j->q_cmd >= 0 ? roz_hold_band(&m->commands[j->q_cmd]) : 0.0;
    double v = roz_hold_setpoint(&from, kp_hold, band);
    if (!(v == v))
        return NAN;
    if (j->q_cmd >= 0)
        return roz_channel_clamp(&m->commands[j->q_cmd], v);
    return j->q_state >= 0 ? roz_channel_clamp(&m->states[j->q_state], v) : v;
}

void roz_joints_hold_keep(const roz_manifest_t *m, const roz_joint_channels_t *j, uint16_t n,
                          const double *last, const double *q, double kd, double *cmd)
{
    roz_joints_hold(m, j, n, q, kd, cmd);
    for (uint16_t k = 0; k < n; k++) {
        if (j[k].kp_cmd >= 0)
            cmd[j[k].kp_cmd] = roz_channel_clamp(&m->commands[j[k].kp_cmd],
                                                 m->commands[j[k].kp_cmd].default_value);
        if (j[k].q_cmd >= 0)
            cmd[j[k].q_cmd] = roz_joints_hold_setpoint(
                m, &j[k], last[j[k].q_cmd], j[k].kp_cmd >= 0 ? last[j[k].kp_cmd] : NAN, q[k]);
    }
}

uint32_t roz_commands_clamp(const roz_manifest_t *m, const double *in, double *out)
{
    uint32_t changed = 0;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        double v = in[i];
        if (!(v >= c->min && v <= c->max)) {
            v = roz_channel_clamp(c, v);
            changed++;
        }
        out[i] = v;
    }
    return changed;
}

int roz_joints_not_the_robots(const char *port, unsigned k, const char *joint, const char *how,
                              char *err, size_t errlen)
{
    roz_format(err, errlen, "%s: [hardware] joints[%u] \"%s\" is not one of the robot's joints "
               "(the port's header lists them%s)", port, k, joint != NULL ? joint : "", how);
    return ROZ_ENOENT;
}
