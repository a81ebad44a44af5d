/* SPDX-License-Identifier: Apache-2.0 */
/* The mujoco port's rules that bind a manifest to a model (mj_rules.h):
 * one implementation, which the port's open runs against MuJoCo's compiled
 * model and roz_mujoco_check_model() (roz_manifest_json, and so rozgen)
 * against the MJCF reader's. No MuJoCo here. */
#include "mj_rules.h"

#include <math.h>
#include <string.h>

#include "mjcf_scan.h"
#include "roz/format.h"

#include "builtin_ids.h" /* ROZ_MUJOCO_BUILTIN_IDS: generated from models/ */

#define PORT "mujoco"

/* ---- the joints -------------------------------------------------------------------- */

/* Looks @p name up in a "A=B, C=D" list: the B of A = @p name (into
 * @p buf), or @p name itself. */
static const char *map_name(const char *list, const char *name, char *buf, size_t cap)
{
    size_t nl = strlen(name);
    for (const char *p = list; p != NULL && *p != '\0';) {
        while (*p == ' ' || *p == ',')
            p++;
        const char *eq = strchr(p, '=');
        const char *end = strchr(p, ',');
        if (end == NULL)
            end = p + strlen(p);
        if (eq != NULL && eq < end) {
            const char *k = p, *ke = eq;
            while (ke > k && ke[-1] == ' ')
                ke--;
            if ((size_t)(ke - k) == nl && strncmp(k, name, nl) == 0) {
                const char *v = eq + 1;
                while (*v == ' ')
                    v++;
                const char *ve = end;
                while (ve > v && ve[-1] == ' ')
                    ve--;
                size_t vl = (size_t)(ve - v) < cap - 1 ? (size_t)(ve - v) : cap - 1;
                memcpy(buf, v, vl);
                buf[vl] = '\0';
                return buf;
            }
        }
        p = end;
    }
    return name;
}

/* Every "A=" of a "A=B, C=D" list must be a joint of the manifest. */
static int check_map_keys(const roz_manifest_t *m, const char *list, const roz__mj_joints_t *jn,
                          char *err, size_t errlen)
{
    for (const char *p = list; p != NULL && *p != '\0';) {
        while (*p == ' ' || *p == ',')
            p++;
        if (*p == '\0')
            break;
        const char *end = strchr(p, ',');
        if (end == NULL)
            end = p + strlen(p);
        const char *eq = memchr(p, '=', (size_t)(end - p));
        if (eq == NULL) {
            roz_format(err, errlen, "hardware.params.joint_names: \"%.*s\": expected "
                       "MANIFEST_JOINT=MJCF_JOINT", (int)(end - p), p);
            return ROZ_EINVAL;
        }
        const char *ke = eq;
        while (ke > p && ke[-1] == ' ')
            ke--;
        int found = 0;
        for (uint16_t j = 0; j < jn->n && !found; j++)
            found = strlen(jn->names[j]) == (size_t)(ke - p) &&
                    strncmp(jn->names[j], p, (size_t)(ke - p)) == 0;
        if (!found) {
            roz_format(err, errlen, "hardware.params.joint_names: \"%.*s\" is not a joint of "
                       "manifest %s", (int)(ke - p), p, m->robot_id);
            return ROZ_EINVAL;
        }
        p = end;
    }
    return ROZ_OK;
}

static int add_joint_of(const char *channel, roz__mj_joints_t *jn, char *err, size_t errlen)
{
    const char *slash = strrchr(channel, '/');
    if (slash == NULL)
        return ROZ_OK; /* roz_joints_bind() names it: no place for it */
    size_t len = (size_t)(slash - channel);
    if (len == 8 && strncmp(channel, "base_imu", 8) == 0)
        return ROZ_OK;
    for (uint16_t j = 0; j < jn->n; j++) {
        if (strlen(jn->names[j]) == len && strncmp(jn->names[j], channel, len) == 0)
            return ROZ_OK;
    }
    if (jn->n == ROZ_MUJOCO_MAX_JOINTS || len >= ROZ_MUJOCO_NAME_MAX) {
        roz_format(err, errlen, "channel \"%s\": more than %d joints, or a joint name longer "
                   "than %d bytes", channel, ROZ_MUJOCO_MAX_JOINTS, ROZ_MUJOCO_NAME_MAX - 1);
        return ROZ_ENOSPC;
    }
    memcpy(jn->buf[jn->n], channel, len);
    jn->buf[jn->n][len] = '\0';
    jn->names[jn->n] = jn->buf[jn->n];
    jn->n++;
    return ROZ_OK;
}

/* [hardware] joints when the manifest has them, else the joints its
 * channels name, in order of appearance. */
static int manifest_joints(const roz_manifest_t *m, roz__mj_joints_t *jn, char *err,
                           size_t errlen)
{
    jn->n = 0;
    if (m->hardware != NULL && m->hardware->n_joints > 0) {
        if (m->hardware->n_joints > ROZ_MUJOCO_MAX_JOINTS) {
            roz_format(err, errlen, "%u joints; at most %d", (unsigned)m->hardware->n_joints,
                       ROZ_MUJOCO_MAX_JOINTS);
            return ROZ_ENOSPC;
        }
        for (uint16_t j = 0; j < m->hardware->n_joints; j++)
            jn->names[j] = m->hardware->joints[j];
        jn->n = m->hardware->n_joints;
        return ROZ_OK;
    }
    for (uint16_t i = 0; i < m->n_commands; i++) {
        if (add_joint_of(m->commands[i].name, jn, err, errlen) != ROZ_OK)
            return ROZ_ENOSPC;
    }
    for (uint16_t i = 0; i < m->n_states; i++) {
        if (add_joint_of(m->states[i].name, jn, err, errlen) != ROZ_OK)
            return ROZ_ENOSPC;
    }
    return ROZ_OK;
}

/* Channel "<prefix>/<suffix>" of interface @p type among @p c; -1: none. */
static int16_t find_channel(const roz_channel_t *c, uint16_t n, const char *prefix, size_t plen,
                            const char *suffix, roz_interface_t type)
{
    for (uint16_t i = 0; i < n; i++) {
        const char *name = c[i].name;
        if (strncmp(name, prefix, plen) == 0 && name[plen] == '/' &&
            strcmp(name + plen + 1, suffix) == 0 && c[i].type == type)
            return (int16_t)i;
    }
    return -1;
}

/* A robot commanded by body velocities, as the built-in diff_drive and
 * quadcopter are: every channel one of a mobile base's (roz/loopback.h has
 * the same names). */
static int detect_mobile(const roz_manifest_t *m, roz__mj_joints_t *jn)
{
    const char *slash = strchr(m->commands[0].name, '/');
    if (slash == NULL)
        return ROZ__MJ_MOBILE_NONE;
    const char *pre = m->commands[0].name;
    size_t pl = (size_t)(slash - pre);
    static const char *const wheel_cmd[2] = { "linear.x", "angular.z" };
    static const char *const wheel_st[3] = { "odom.x", "odom.y", "odom.yaw" };
    static const char *const ap_cmd[4] = { "velocity.x", "velocity.y", "velocity.z", "yaw_rate" };
    static const char *const ap_st[4] = { "position.x", "position.y", "position.z", "yaw" };
    int ok = m->n_commands == 2 && m->n_states == 3;
    for (int k = 0; ok && k < 2; k++)
        ok = (jn->mob_cmd[k] = find_channel(m->commands, m->n_commands, pre, pl, wheel_cmd[k],
                                            ROZ_IF_VELOCITY)) >= 0;
    for (int k = 0; ok && k < 3; k++)
        ok = (jn->mob_state[k] = find_channel(m->states, m->n_states, pre, pl, wheel_st[k],
                                              ROZ_IF_POSITION)) >= 0;
    if (ok)
        return ROZ__MJ_MOBILE_WHEELS;
    ok = m->n_commands == 4 && m->n_states == 4;
    for (int k = 0; ok && k < 4; k++)
        ok = (jn->mob_cmd[k] = find_channel(m->commands, m->n_commands, pre, pl, ap_cmd[k],
                                            ROZ_IF_VELOCITY)) >= 0;
    for (int k = 0; ok && k < 4; k++)
        ok = (jn->mob_state[k] = find_channel(m->states, m->n_states, pre, pl, ap_st[k],
                                              ROZ_IF_POSITION)) >= 0;
    return ok ? ROZ__MJ_MOBILE_AUTOPILOT : ROZ__MJ_MOBILE_NONE;
}

int roz__mj_joints_of(const roz_manifest_t *m, const roz_params_t *p, roz__mj_joints_t *jn,
                      char *err, size_t errlen)
{
    jn->n = 0;
    jn->mobile = detect_mobile(m, jn);
    if (jn->mobile == ROZ__MJ_MOBILE_WHEELS) {
        static const char *const wheel_keys[2] = { "wheel_left", "wheel_right" };
        for (int k = 0; k < 2; k++) {
            jn->names[k] = roz_params_get_str(p, wheel_keys[k], NULL);
            if (jn->names[k] == NULL || jn->names[k][0] == '\0') {
                roz_format(err, errlen, "hardware.params.%s: missing: a differential drive "
                           "names its wheels' joints", wheel_keys[k]);
                return ROZ_EINVAL;
            }
            jn->mj[k] = jn->names[k];
        }
        jn->n = 2;
    } else if (jn->mobile == ROZ__MJ_MOBILE_NONE &&
               manifest_joints(m, jn, err, errlen) != ROZ_OK) {
        return ROZ_EINVAL;
    }
    const char *map = roz_params_find(p, "joint_names");
    if (check_map_keys(m, map, jn, err, errlen) != ROZ_OK)
        return ROZ_EINVAL;
    for (uint16_t j = 0; j < jn->n && jn->mobile == ROZ__MJ_MOBILE_NONE; j++)
        jn->mj[j] = map_name(map, jn->names[j], jn->mj_buf[j], sizeof jn->mj_buf[j]);
    return ROZ_OK;
}

int roz__mj_model_path(const char *robot_toml, const char *model, char *out, size_t cap)
{
    size_t dir = 0;
    if (model[0] != '/' && robot_toml != NULL) {
        const char *slash = strrchr(robot_toml, '/');
        dir = slash != NULL ? (size_t)(slash - robot_toml) + 1 : 0;
    }
    if (dir + strlen(model) + 1 > cap)
        return ROZ_EINVAL;
    if (dir > 0)
        memcpy(out, robot_toml, dir);
    memcpy(out + dir, model, strlen(model) + 1);
    return ROZ_OK;
}

void roz__mj_model_missing(const char *robot_id, char *err, size_t errlen)
{
    roz_format(err, errlen, "hardware.params.model: missing, and this build has no built-in "
               "model for robot %s (docs/ports/mujoco.md)", robot_id);
}

int roz__mj_is_builtin(const char *robot_id)
{
    static const char *const ids[] = { ROZ_MUJOCO_BUILTIN_IDS };
    for (size_t i = 0; i < sizeof ids / sizeof ids[0]; i++) {
        if (ids[i] != NULL && strcmp(ids[i], robot_id) == 0)
            return 1;
    }
    return 0;
}

/* ---- the model ----------------------------------------------------------------------- */

/* A motor's ctrlrange is a torque range too: gear x gain x ctrl. The
 * manifest's effort channel @p c must lie inside it (a tighter channel is
 * the law roz applies); [*lo, *hi] narrows to it. Test:
 * test_mujoco_models.c, the ctrlrange cases. */
static int check_ctrlrange(const roz__mj_model_view_t *v, const roz__mj_actuator_view_t *a,
                           const char *name, const roz_channel_t *c, double *lo, double *hi,
                           char *err, size_t errlen)
{
    double gear = a->gear * a->gain;
    if (!a->ctrl_limited || !(gear != 0.0) || !isfinite(gear))
        return ROZ_OK; /* a zero gear: refused after */
    double t0 = gear * a->ctrl[0], t1 = gear * a->ctrl[1];
    double clo = fmin(t0, t1), chi = fmax(t0, t1);
    if (c != NULL && (c->min < clo || c->max > chi)) {
        roz_format(err, errlen, "channel \"%s\": limits [%g, %g] N.m exceed what %s's actuator "
                   "\"%s\" (joint \"%s\") can give, [%g, %g]: its ctrlrange [%g, %g] times gear "
                   "and gain %g; narrow the channel's limits to the actuator's", c->name, c->min,
                   c->max, v->path, a->name != NULL ? a->name : "?", name, clo, chi, a->ctrl[0],
                   a->ctrl[1], gear);
        return ROZ_EINVAL;
    }
    *lo = fmax(*lo, clo);
    *hi = fmin(*hi, chi);
    return ROZ_OK;
}

const char *roz__mj_bind_rule(const roz__mj_model_view_t *v, const char *name, const char *mj,
                              const roz_channel_t *effort, roz__mj_joint_view_t *j,
                              roz__mj_actuator_view_t *a, double *tau_lo, double *tau_hi,
                              char *err, size_t errlen)
{
    int mapped = strcmp(name, mj) != 0;
    if (v->joint(v->ctx, mj, j) != ROZ_OK) {
        roz_format(err, errlen, "joint \"%s\"%s%s%s: no joint of that name in %s "
                   "(hardware.params.joint_names maps manifest joints to the model's)", name,
                   mapped ? " (\"" : "", mapped ? mj : "", mapped ? "\")" : "", v->path);
        return "mujoco-joint";
    }
    if (!j->hinge_or_slide) {
        roz_format(err, errlen, "joint \"%s\": %s's joint \"%s\" is not a hinge or a slide",
                   name, v->path, mj);
        return "mujoco-joint";
    }
    if (v->actuator(v->ctx, j, mj, a) != ROZ_OK) {
        roz_format(err, errlen, "joint \"%s\": no actuator drives %s's joint \"%s\"", name,
                   v->path, mj);
        return "mujoco-joint";
    }
    /* what the actuator can give, in joint torque */
    double lo = -INFINITY, hi = INFINITY;
    if (a->force_limited) {
        double f0 = a->gear * a->force[0], f1 = a->gear * a->force[1];
        lo = fmin(f0, f1);
        hi = fmax(f0, f1);
    }
    if (j->limited) {
        lo = fmax(lo, j->range[0]);
        hi = fmin(hi, j->range[1]);
    }
    const char *an = a->name != NULL ? a->name : "?";
    if (check_ctrlrange(v, a, name, effort, &lo, &hi, err, errlen) != ROZ_OK)
        return "mujoco-effort";
    if (effort != NULL) {
        if (effort->min < lo || effort->max > hi) {
            roz_format(err, errlen, "joint \"%s\": the manifest's effort limits [%g, %g] N.m "
                       "exceed what %s's actuator \"%s\" can give, [%g, %g]", name, effort->min,
                       effort->max, v->path, an, lo, hi);
            return "mujoco-effort";
        }
        *tau_lo = effort->min;
        *tau_hi = effort->max;
    } else if (isfinite(lo) && isfinite(hi)) {
        *tau_lo = lo; /* the manifest has none: the actuator's own */
        *tau_hi = hi;
    } else {
        roz_format(err, errlen, "joint \"%s\": no effort limit: the manifest has no %s/effort "
                   "channel and %s's actuator \"%s\" has no force range", name, name, v->path,
                   an);
        return "mujoco-effort";
    }
    double gear = a->gear * a->gain;
    if (!(gear != 0.0) || !isfinite(gear)) {
        roz_format(err, errlen, "joint \"%s\": %s's actuator \"%s\" has a zero gain or gear",
                   name, v->path, an);
        return "mujoco-joint";
    }
    return NULL;
}

/* The sensor named @p name (NULL: the first of @p kind): its index, -1
 * when none, -2 when the one named is of another kind. */
static int find_sensor(const roz__mj_model_view_t *v, const char *name, int kind,
                       roz__mj_sensor_view_t *out)
{
    for (int i = 0; i < v->n_sensors; i++) {
        v->sensor(v->ctx, i, out);
        if (name != NULL ? (out->name != NULL && strcmp(out->name, name) == 0)
                         : out->kind == kind)
            return out->kind == kind ? i : -2;
    }
    return -1;
}

int roz__mj_imu_rule(const roz__mj_model_view_t *v, const char *gyro, const char *acc,
                     int *gyro_i, int *acc_i, char *err, size_t errlen)
{
    roz__mj_sensor_view_t s;
    *gyro_i = find_sensor(v, gyro, ROZ__MJ_SENSOR_GYRO, &s);
    if (*gyro_i < 0 || s.site < 0) {
        roz_format(err, errlen, "hardware.params.imu_gyro%s%s%s: %s in %s (the manifest has "
                   "base_imu channels)", gyro ? " = \"" : "", gyro ? gyro : "", gyro ? "\"" : "",
                   *gyro_i == -2 ? "not a gyro sensor" : "no gyro sensor on a site", v->path);
        return 1;
    }
    *acc_i = find_sensor(v, acc, ROZ__MJ_SENSOR_ACCELEROMETER, &s);
    if (*acc_i < 0) {
        roz_format(err, errlen, "hardware.params.imu_accelerometer%s%s%s: %s in %s (the "
                   "manifest has base_imu channels)", acc ? " = \"" : "", acc ? acc : "",
                   acc ? "\"" : "", *acc_i == -2 ? "not an accelerometer" : "no accelerometer sensor",
                   v->path);
        return 2;
    }
    return 0;
}

/* ---- the checker's view: the MJCF reader's model ------------------------------------ */

static int reader_joint(const void *ctx, const char *name, roz__mj_joint_view_t *out)
{
    const roz__mjcf_model_t *m = ctx;
    for (size_t i = 0; i < m->n_joints; i++) {
        const roz__mjcf_joint_t *j = &m->joints[i];
        if (strcmp(j->name, name) == 0) {
            out->id = (int)i;
            out->hinge_or_slide = strcmp(j->type, "hinge") == 0 || strcmp(j->type, "slide") == 0;
            out->limited = j->limited;
            out->range[0] = j->range[0];
            out->range[1] = j->range[1];
            return ROZ_OK;
        }
    }
    return ROZ_ENOENT;
}

static int reader_actuator(const void *ctx, const roz__mj_joint_view_t *j, const char *name,
                           roz__mj_actuator_view_t *out)
{
    const roz__mjcf_model_t *m = ctx;
    (void)j;
    for (size_t i = 0; i < m->n_actuators; i++) {
        const roz__mjcf_actuator_t *a = &m->actuators[i];
        if (strcmp(a->joint, name) == 0) {
            memset(out, 0, sizeof *out);
            out->id = (int)i;
            out->name = a->name;
            out->gear = a->gear;
            out->gain = 1.0; /* what MuJoCo compiles of a motor; a servo is made one */
            out->force_limited = a->limited;
            out->force[0] = a->range[0];
            out->force[1] = a->range[1];
            return ROZ_OK; /* the ctrlrange is the port's open's (rozgen --check) */
        }
    }
    return ROZ_ENOENT;
}

static void reader_sensor(const void *ctx, int i, roz__mj_sensor_view_t *out)
{
    const roz__mjcf_sensor_t *x = &((const roz__mjcf_model_t *)ctx)->sensors[i];
    out->name = x->name;
    out->kind = strcmp(x->type, "gyro") == 0            ? ROZ__MJ_SENSOR_GYRO
                : strcmp(x->type, "accelerometer") == 0 ? ROZ__MJ_SENSOR_ACCELEROMETER
                                                        : ROZ__MJ_SENSOR_OTHER;
    out->site = x->site != NULL ? i : -1;
}

/* The joint's effort command, else its effort state; NULL when neither. */
static const roz_channel_t *effort_of(const roz_manifest_t *m, const char *joint)
{
    size_t jl = strlen(joint);
    for (int side = 0; side < 2; side++) {
        const roz_channel_t *c = side == 0 ? m->commands : m->states;
        uint16_t n = side == 0 ? m->n_commands : m->n_states;
        for (uint16_t i = 0; i < n; i++) {
            if (c[i].type == ROZ_IF_EFFORT && strncmp(c[i].name, joint, jl) == 0 &&
                strcmp(c[i].name + jl, "/effort") == 0)
                return &c[i];
        }
    }
    return NULL;
}

static int has_imu(const roz_manifest_t *m)
{
    for (uint16_t i = 0; i < m->n_states; i++) {
        if (strncmp(m->states[i].name, "base_imu/", 9) == 0)
            return 1;
    }
    return 0;
}

/* the checks on the model, after it was read */
static int check_against(const roz_manifest_t *m, const roz_params_t *p,
                         const roz__mj_joints_t *jn, const roz__mj_model_view_t *v,
                         roz_params_reporter_t *to, char *err, size_t errlen)
{
    for (uint16_t k = 0; k < jn->n; k++) {
        roz__mj_joint_view_t j;
        roz__mj_actuator_view_t a;
        double lo, hi;
        const char *rule = roz__mj_bind_rule(v, jn->names[k], jn->mj[k],
                                             effort_of(m, jn->names[k]), &j, &a, &lo, &hi, err,
                                             errlen);
        if (rule != NULL) {
            roz_params_report(to, rule, err);
            return ROZ_EINVAL;
        }
    }
    int gyro, acc;
    if (has_imu(m) && roz__mj_imu_rule(v, roz_params_find(p, "imu_gyro"),
                                       roz_params_find(p, "imu_accelerometer"), &gyro, &acc, err,
                                       errlen) != 0) {
        roz_params_report(to, "mujoco-imu", err);
        return ROZ_EINVAL;
    }
    return ROZ_OK;
}

int roz_mujoco_check_model(const roz_manifest_t *m, const char *robot_toml,
                           roz_params_problem_fn report, void *ctx)
{
    static roz__mj_joints_t jn; /* host tools: one check at a time */
    roz_params_reporter_t to = { report, ctx };
    char err[ROZ_CFG_PROBLEM_LEN], why[ROZ_CFG_PROBLEM_LEN], path[ROZ_MJCF_PATH_MAX];
    roz_params_t p = { NULL, 0 };

    if (m->hardware == NULL || m->hardware->port == NULL ||
        strcmp(m->hardware->port, PORT) != 0)
        return ROZ_OK;
    p.items = m->hardware->params;
    p.n = m->hardware->n_params;
    const char *model = roz_params_find(&p, "model");
    if (model == NULL || model[0] == '\0') {
        if (roz__mj_is_builtin(m->robot_id))
            return ROZ_OK; /* the port's built-in model, where its build found it */
        roz__mj_model_missing(m->robot_id, err, sizeof err);
        roz_params_report(&to, "mujoco-model", err);
        return ROZ_EINVAL;
    }
    if (roz__mj_joints_of(m, &p, &jn, err, sizeof err) != ROZ_OK) {
        roz_params_report(&to, "mujoco-joint", err);
        return ROZ_EINVAL;
    }
    if (roz__mj_model_path(robot_toml, model, path, sizeof path) != ROZ_OK) {
        roz_format(err, sizeof err, "hardware.params.model: the path is longer than %d bytes",
                   ROZ_MJCF_PATH_MAX - 1);
        roz_params_report(&to, "mujoco-model", err);
        return ROZ_EINVAL;
    }
    roz__mjcf_model_t mj;
    int rc = roz__mjcf_read(path, &mj, why, sizeof why);
    if (rc != ROZ_OK) {
        roz_format(err, sizeof err, "hardware.params.model = \"%s\": %s", model, why);
        roz_params_report(&to, "mujoco-model", err);
    } else {
        roz__mj_model_view_t v = { path, &mj, reader_joint, reader_actuator,
                                   (int)mj.n_sensors, reader_sensor };
        rc = check_against(m, &p, &jn, &v, &to, err, sizeof err);
    }
    roz__mjcf_free(&mj);
    return rc == ROZ_OK ? ROZ_OK : ROZ_EINVAL;
}

/* The rule ids of the mujoco port's rules, "<id>\t<what it refuses>", NULL-ended:
 * its registration's RULE_IDS (roz_manifest_json --list-rules). */
const char *const roz_mujoco_rule_ids[] = {
    "mujoco-param\tmujoco port: a [hardware.params] value its parser refuses before "
    "it loads the model (a number out of range, an unknown unbound)",
    "mujoco-model\tmujoco port: the model the file names cannot be read (missing, not "
    "XML, an include that cannot be read), or none is named for a robot without a "
    "built-in one",
    "mujoco-joint\tmujoco port: a manifest joint with no joint of that name in the "
    "model (or joint_names), not a hinge or slide, or driven by no actuator",
    "mujoco-imu\tmujoco port: base_imu channels, and the model has no such gyro (on a "
    "site) or accelerometer",
    "mujoco-effort\tmujoco port: a joint's effort limit that its actuator's force "
    "range cannot give, or no effort limit at all (and, under --check where a rozrun "
    "is found, the port's own: an effort channel wider than its motor's ctrlrange "
    "times gear and gain)",
    NULL,
};
