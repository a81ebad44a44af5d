/* SPDX-License-Identifier: Apache-2.0 */
/* The mujoco port: roz/port/mujoco.h says what, docs/ports/mujoco.md how to use
 * it; here is how it works. The only file that includes MuJoCo's headers. */
#define _POSIX_C_SOURCE 200809L /* readlink() */
#include "roz/port/mujoco.h"

#include <fnmatch.h>
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <mujoco/mujoco.h>

#include "roz/error.h"
#include "roz/format.h"
#include "roz/hal/params.h"
#include "mj_guard.h"
#include "mj_params.h"
#include "mj_rules.h"
#include "mjcf_scan.h"

/* ---- types and tables --------------------------------------------------------- */

/* How a joint is driven (roz_mujoco_joint_t.law). */
enum {
    LAW_MIT = 1, /* gains commanded: tau = ff + kp(q* - q) + kd(dq* - dq) */
    LAW_VELOCITY, /* velocity commanded: a servo on the integrated velocity */
    LAW_POSITION, /* position commanded without gains: a position servo */
    LAW_EFFORT,   /* effort only: tau = ff */
    LAW_WHEEL,    /* a diff drive's wheel: the velocity servo on (v -+ w b/2) / r */
};

/* A robot commanded by body velocities (roz_mujoco_t.mobile; mj_rules.c
 * finds them): wheels, X/linear.x, X/angular.z -> X/odom.x, .y, .yaw; an
 * autopilot, X/velocity.x, .y, .z, X/yaw_rate -> X/position.x, .y, .z, X/yaw. */
#define MOBILE_NONE ROZ__MJ_MOBILE_NONE
#define MOBILE_WHEELS ROZ__MJ_MOBILE_WHEELS
#define MOBILE_AUTOPILOT ROZ__MJ_MOBILE_AUTOPILOT

/* The quadcopter autopilot's gains (docs/ports/mujoco.md): velocity loops,
 * the tilt it allows, the attitude loop's natural frequency and damping,
 * the yaw-rate loop's bandwidth, and the torques the rotors can give. */
#define AP_KV_XY 2.0       /* 1/s */
#define AP_KV_Z 3.0        /* 1/s */
#define AP_MAX_TILT 0.5236 /* rad, 30 deg */
#define AP_OMEGA 15.0      /* rad/s */
#define AP_ZETA 0.8
#define AP_YAW_BW 8.0      /* rad/s */
#define AP_MAX_TORQUE_XY 2.0 /* N.m */
#define AP_MAX_TORQUE_Z 0.3  /* N.m */

#define PORT "mujoco"
#define PI 3.14159265358979323846
#define DEPTH (ROZ_MUJOCO_MAX_DELAY + 1)

/* The built-in robots, one descriptor each (models/<robot_id>.model.toml,
 * made into builtins.h by this port's CMakeLists.txt): each robot's
 * parameters are defaults a robot.toml's or the caller's override. Its
 * model, defaults[0], is found by builtin_model(): under the install
 * prefix's share/roz/models (cmake --install puts them there,
 * docs/ports/mujoco.md), from the running program (<prefix>/bin/rozrun),
 * else where this build found it. */
typedef struct {
    const char        *robot_id;
    const char        *installed; /* the model under share/roz/models/ */
    const roz_param_t *defaults;
    size_t             n;
} builtin_t;

/* below the program's folder: <prefix>/bin/../share/roz/models/ */
#define INSTALLED_MODELS "/../share/roz/models/"

#include "builtins.h"

#define BUILTIN(id, rel, d) { id, rel, d, sizeof d / sizeof d[0] },
static const builtin_t builtins[] = { ROZ_MUJOCO_BUILTINS };
#undef BUILTIN
#define N_BUILTINS (sizeof builtins / sizeof builtins[0])

static int readable(const char *path)
{
    FILE *f = path[0] == '/' ? fopen(path, "rb") : NULL;
    if (f != NULL)
        fclose(f);
    return f != NULL;
}

/* Where built-in robot @p i's model is: installed beside the program, else
 * this build's; NULL: neither is there. Start-up only (open, and
 * roz_mujoco_builtin_model()): it reads the file system, and its answers
 * are kept in static storage. */
static const char *builtin_model(size_t i)
{
    static char installed[N_BUILTINS][ROZ_MUJOCO_PATH_MAX];
    char exe[ROZ_MUJOCO_PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        exe[n] = '\0';
        char *slash = strrchr(exe, '/');
        if (slash != NULL) {
            *slash = '\0';
            int len = snprintf(installed[i], sizeof installed[i], "%s" INSTALLED_MODELS "%s",
                               exe, builtins[i].installed);
            if (len > 0 && (size_t)len < sizeof installed[i] && readable(installed[i]))
                return installed[i];
        }
    }
    const char *model = builtins[i].defaults[0].value;
    size_t len = strlen(model);
    if (len > 4 && strcmp(model + len - 4, ".xml") == 0 && readable(model))
        return model;
    return NULL;
}

/* Built-in robot @p robot_id and its model (*model), or NULL. */
static const builtin_t *find_builtin(const char *robot_id, const char **model)
{
    for (size_t i = 0; i < N_BUILTINS; i++) {
        if (strcmp(builtins[i].robot_id, robot_id) == 0) {
            *model = builtin_model(i);
            return *model != NULL ? &builtins[i] : NULL;
        }
    }
    return NULL;
}

const char *roz_mujoco_builtin_model(const char *robot_id)
{
    const char *model = NULL;
    return find_builtin(robot_id, &model) != NULL ? model : NULL;
}

/* MuJoCo's warnings (an unstable simulation, a full arena) go to stdout by
 * default, from the tick; here they are counted instead, and the port turns
 * them into a counter the tests read. */
static _Atomic uint64_t mj_warnings;

static void count_warning(const char *msg)
{
    (void)msg;
    atomic_fetch_add_explicit(&mj_warnings, 1u, memory_order_relaxed);
}

/* ---- private: open ------------------------------------------------------------- */

/* How errors name where the robot came from: its robot.toml, or the
 * manifest's id for a built-in one. */
static const char *origin(const roz_mujoco_t *s)
{
    return s->robot_file != NULL ? s->robot_file : s->m->robot_id;
}

/* The parameters that apply: robot.toml's [hardware.params] when its port is
 * this one (a built-in manifest's are another port's), then the caller's
 * over them (the last one wins). */
typedef struct {
    roz_param_t  items[2 * ROZ_CFG_MAX_PARAMS + 64];
    roz_params_t p;
} merged_t;

static int merge_params(const roz_manifest_t *m, const roz_params_t *extra, merged_t *out)
{
    size_t n = 0;
    const size_t cap = sizeof out->items / sizeof out->items[0];
    /* a built-in robot's defaults first, unless a model of its own is named */
    const char *model = NULL;
    const builtin_t *b = find_builtin(m->robot_id, &model);
    int own_model = roz_params_find(extra, "model") != NULL;
    if (m->hardware != NULL && m->hardware->port != NULL && strcmp(m->hardware->port, PORT) == 0) {
        roz_params_t hw = { m->hardware->params, m->hardware->n_params };
        own_model |= roz_params_find(&hw, "model") != NULL;
    }
    for (size_t i = 0; b != NULL && !own_model && i < b->n && n < cap; i++) {
        out->items[n] = b->defaults[i];
        if (i == 0)
            out->items[n].value = model; /* installed, or this build's */
        n++;
    }
    if (m->hardware != NULL && m->hardware->port != NULL && strcmp(m->hardware->port, PORT) == 0) {
        for (uint16_t i = 0; i < m->hardware->n_params && n < cap; i++)
            out->items[n++] = m->hardware->params[i];
    }
    for (size_t i = 0; extra != NULL && i < extra->n; i++) {
        if (n == cap)
            return ROZ_ENOSPC;
        out->items[n++] = extra->items[i];
    }
    out->p.items = out->items;
    out->p.n = n;
    return ROZ_OK;
}

/* One entry of a fault parameter (roz_inject_parse()'s callback): the
 * grammar is the simulators' (roz/hal/inject.h); push's FX,FY,FZ@BODY is
 * read here. */
static int inject_entry(void *ctx, const roz_inject_entry_t *e, char *why, size_t whylen)
{
    roz_mujoco_t *s = ctx;
    roz_mujoco_fault_t f;
    memset(&f, 0, sizeof f);
    f.kind = e->kind;
    f.from = e->from;
    f.to = e->to;
    f.arg = e->arg;
    f.body = -1;
    if (e->kind == ROZ_INJECT_PUSH) {
        char *end;
        const char *p = e->head;
        for (int k = 0; k < 3; k++) {
            f.force[k] = strtod(p, &end);
            if (end == p || !isfinite(f.force[k]) || *end != (k < 2 ? ',' : '@')) {
                roz_format(why, whylen, "FX,FY,FZ are not three finite numbers");
                return ROZ_INJECT_SYNTAX;
            }
            p = end + 1;
        }
        if (*p == '\0' || strlen(p) >= ROZ_MUJOCO_NAME_MAX) {
            roz_format(why, whylen, "no BODY, or one longer than %d characters",
                       ROZ_MUJOCO_NAME_MAX - 1);
            return ROZ_INJECT_SYNTAX;
        }
        f.body = mj_name2id(s->model, mjOBJ_BODY, p);
        if (f.body <= 0) {
            roz_format(why, whylen, "no body \"%s\" in %s (the world cannot be pushed)", p,
                       s->model_path);
            return ROZ_INJECT_BAD;
        }
    }
    if (e->kind == ROZ_INJECT_GANTRY && s->gantry_eq < 0) {
        roz_format(why, whylen, "%s has no floating base to hang", s->model_path);
        return ROZ_INJECT_BAD;
    }
    if (roz_mujoco_inject(s, &f) != ROZ_OK) {
        roz_format(why, whylen, "more than %d fault injections", ROZ_MUJOCO_MAX_FAULTS);
        return ROZ_INJECT_BAD;
    }
    return ROZ_OK;
}

/* The fault injections this port takes, each key's value (the last one
 * given: the caller's over robot.toml's) one entry or a ';' list. */
#define MJ_INJECTIONS                                                                        \
    ((1u << ROZ_INJECT_DROP) | (1u << ROZ_INJECT_FREEZE) | (1u << ROZ_INJECT_DELAY) |       \
     (1u << ROZ_INJECT_PUSH) | (1u << ROZ_INJECT_GANTRY) | (1u << ROZ_INJECT_RESTART))

static int parse_faults(roz_mujoco_t *s, const roz_params_t *p, char *err, size_t errlen)
{
    static const roz_inject_kind_t kinds[] = { ROZ_INJECT_DROP, ROZ_INJECT_FREEZE,
                                               ROZ_INJECT_DELAY, ROZ_INJECT_PUSH,
                                               ROZ_INJECT_GANTRY, ROZ_INJECT_RESTART };
    char why[ROZ_CFG_ERROR_LEN];
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        const char *v = roz_params_find(p, roz_inject_key(kinds[k]));
        if (v != NULL && roz_inject_parse(kinds[k], v, inject_entry, s, why, sizeof why) != ROZ_OK) {
            roz_format(err, errlen, PORT ": %s: %s", origin(s), why);
            return ROZ_EINVAL;
        }
    }
    return ROZ_OK;
}

/* The model's path: `model`, relative to the robot.toml's folder. */
static int model_path(roz_mujoco_t *s, const char *model, char *err, size_t errlen)
{
    if (roz__mj_model_path(s->robot_file, model, s->model_path, sizeof s->model_path) != ROZ_OK) {
        roz_format(err, errlen, PORT ": %s: hardware.params.model: the path is longer than %d "
                   "bytes", origin(s), ROZ_MUJOCO_PATH_MAX - 1);
        return ROZ_EINVAL;
    }
    return ROZ_OK;
}

static const char *spec_name(mjsElement *e)
{
    const char *n = mjs_getString(mjs_getName(e));
    return n != NULL ? n : "";
}

/* Every mesh file the model names is there, before the compile looks for
 * it: a model copied without its meshes (or with another folder layout)
 * gets the file, the place looked in and what to set, rather than the
 * compiler's first "Error opening file". MuJoCo's rule: <compiler meshdir>
 * (absolute, or relative to the model's folder), then the mesh's file.
 * Test: test_mujoco_models.c. */
static int check_meshes(const roz_mujoco_t *s, mjSpec *spec, char *err, size_t errlen)
{
    const char *dir = mjs_getString(spec->modelfiledir);
    const char *meshdir = mjs_getString(spec->compiler.meshdir);
    dir = dir != NULL ? dir : "";
    meshdir = meshdir != NULL ? meshdir : "";
    char path[ROZ_MUJOCO_PATH_MAX], first[ROZ_MUJOCO_PATH_MAX] = "";
    const char *first_name = "", *first_file = "";
    unsigned missing = 0, meshes = 0;
    for (mjsElement *e = mjs_firstElement(spec, mjOBJ_MESH); e != NULL;
         e = mjs_nextElement(spec, e)) {
        const char *file = mjs_getString(mjs_asMesh(e)->file);
        if (file == NULL || file[0] == '\0')
            continue; /* its vertices are in the model */
        meshes++;
        size_t md = strlen(meshdir);
        roz_format(path, sizeof path, "%s%s%s%s", file[0] == '/' || meshdir[0] == '/' ? "" : dir,
                   file[0] == '/' ? "" : meshdir,
                   file[0] != '/' && md > 0 && meshdir[md - 1] != '/' ? "/" : "", file);
        FILE *f = fopen(path, "rb");
        if (f != NULL) {
            fclose(f);
            continue;
        }
        if (missing++ == 0) {
            roz_format(first, sizeof first, "%s", path);
            first_name = spec_name(e);
            first_file = file;
        }
    }
    if (missing == 0)
        return ROZ_OK;
    roz_format(err, errlen, PORT ": %s: %s: <mesh name=\"%s\" file=\"%s\">: no file %s (%u of "
               "the model's %u mesh files are missing): a mesh file is looked for in the "
               "model's <compiler meshdir=\"%s\">, relative to the model's folder; put the "
               "meshes there, or set meshdir to the folder that holds them",
               origin(s), s->model_path, first_name, first_file, first, missing, meshes, meshdir);
    return ROZ_EINVAL;
}

/* The next pattern of the `lock` parameter ("PATTERN, ..." of fnmatch(3)
 * patterns) from *@p p into @p pat: 1, 0 at the end, -1 when it does not
 * fit (@p len: its length, for the message). */
static int next_pattern(const char **p, char *pat, size_t cap, size_t *len)
{
    const char *q = *p;
    while (q != NULL && (*q == ' ' || *q == ','))
        q++;
    if (q == NULL || *q == '\0')
        return 0;
    const char *end = strchr(q, ',');
    if (end == NULL)
        end = q + strlen(q);
    *len = (size_t)(end - q);
    while (*len > 0 && q[*len - 1] == ' ')
        (*len)--;
    *p = end;
    if (*len >= cap)
        return -1;
    memcpy(pat, q, *len);
    pat[*len] = '\0';
    return 1;
}

/* Whether model joint @p name is one @p lock names. */
static int lock_names(const char *lock, const char *name)
{
    char pat[ROZ_MUJOCO_NAME_MAX];
    size_t len;
    int rc;
    while ((rc = next_pattern(&lock, pat, sizeof pat, &len)) != 0) {
        if (rc > 0 && fnmatch(pat, name, 0) == 0)
            return 1;
    }
    return 0;
}

/* Every pattern of `lock` names a hinge or slide of the model: a pattern
 * that names none is a typo that would leave a joint free. */
static int check_lock(const roz_mujoco_t *s, mjSpec *spec, const char *lock, char *err,
                      size_t errlen)
{
    char pat[ROZ_MUJOCO_NAME_MAX];
    size_t len;
    int rc;
    for (const char *p = lock; (rc = next_pattern(&p, pat, sizeof pat, &len)) != 0;) {
        int found = 0;
        for (mjsElement *e = mjs_firstElement(spec, mjOBJ_JOINT); e != NULL && rc > 0 && !found;
             e = mjs_nextElement(spec, e)) {
            int type = mjs_asJoint(e)->type;
            found = (type == mjJNT_HINGE || type == mjJNT_SLIDE) &&
                    fnmatch(pat, spec_name(e), 0) == 0;
        }
        if (rc < 0) {
            roz_format(err, errlen, PORT ": %s: hardware.params.lock = \"%s\": a pattern of %u "
                       "bytes; a joint name has at most %d", origin(s), lock, (unsigned)len,
                       ROZ_MUJOCO_NAME_MAX - 1);
            return ROZ_EINVAL;
        }
        if (!found) {
            roz_format(err, errlen, PORT ": %s: hardware.params.lock = \"%s\": \"%s\" names no "
                       "hinge or slide joint of the model", origin(s), lock, pat);
            return ROZ_EINVAL;
        }
    }
    return ROZ_OK;
}

/* The model as roz drives it: every actuator a motor (roz runs the robot's
 * own law at every step), each model joint no channel binds locked (or
 * limp), and a weld that hangs the floating base (the gantry), off. */
static int edit_spec(roz_mujoco_t *s, mjSpec *spec, const char *const *mj_names, uint16_t n,
                     int lock_unbound, const char *lock, uint32_t *servos, uint32_t *locked,
                     char *err, size_t errlen)
{
    *servos = *locked = 0;
    for (mjsElement *e = mjs_firstElement(spec, mjOBJ_ACTUATOR); e != NULL;
         e = mjs_nextElement(spec, e)) {
        mjsActuator *a = mjs_asActuator(e);
        int motor = a->gaintype == mjGAIN_FIXED && a->biastype == mjBIAS_NONE &&
                    a->dyntype == mjDYN_NONE;
        if (!motor) {
            const char *why = mjs_setToMotor(a);
            if (why != NULL && why[0] != '\0') {
                roz_format(err, errlen, PORT ": %s: %s: actuator \"%s\" cannot be made a "
                           "motor: %s", origin(s), s->model_path, spec_name(e), why);
                return ROZ_EINVAL;
            }
            (*servos)++;
            a->ctrllimited = mjLIMITED_FALSE; /* a servo's range was its set-point's */
        }
        a->inheritrange = 0;
        /* a motor's ctrlrange bounds its torque: bind_joint() reads it from
         * the compiled model, then open clears it (roz saturates the torque) */
    }
    s->gantry_eq = -1;
    for (mjsElement *e = mjs_firstElement(spec, mjOBJ_JOINT); e != NULL;
         e = mjs_nextElement(spec, e)) {
        mjsJoint *j = mjs_asJoint(e);
        const char *name = spec_name(e);
        if (j->type == mjJNT_FREE) {
            if (s->gantry_eq >= 0)
                continue; /* the first free joint is the robot's base */
            mjsBody *b = mjs_getParent(e);
            mjsEquality *w = mjs_addEquality(spec, NULL);
            w->type = mjEQ_WELD;
            w->objtype = mjOBJ_BODY;
            mjs_setString(w->name1, spec_name(b->element));
            w->active = 0;
            s->gantry_eq = 1; /* its id is known after compiling */
            continue;
        }
        if (j->type == mjJNT_BALL)
            continue;
        int bound = 0;
        for (uint16_t k = 0; k < n && !bound; k++)
            bound = strcmp(mj_names[k], name) == 0;
        /* `lock`: held even where a channel binds it (its drive then pushes
         * against the lock), as a training model's fixed joints are */
        int held = lock_names(lock, name) == 1;
        if (bound && held)
            (*locked)++;
        if (((!bound && lock_unbound) || held) && name[0] != '\0') {
            mjsEquality *q = mjs_addEquality(spec, NULL);
            q->type = mjEQ_JOINT;
            q->objtype = mjOBJ_JOINT;
            mjs_setString(q->name1, name);
            memset(q->data, 0, sizeof q->data); /* held at its reference position */
            q->active = 1;
        }
        if (!bound)
            s->unbound++;
    }
    return ROZ_OK;
}

/* The channel that bounds a joint's effort: its effort command, else its
 * effort state; NULL when neither. */
static const roz_channel_t *manifest_effort(const roz_manifest_t *m, const roz_joint_channels_t *ch)
{
    return ch->tau_cmd >= 0     ? &m->commands[ch->tau_cmd]
           : ch->tau_state >= 0 ? &m->states[ch->tau_state]
                                : NULL;
}

/* ---- the model as mj_rules.c's rules see it ---------------------------------------- */

static int view_joint(const void *ctx, const char *name, roz__mj_joint_view_t *out)
{
    const mjModel *mm = ctx;
    int j = mj_name2id(mm, mjOBJ_JOINT, name);
    if (j < 0)
        return ROZ_ENOENT;
    out->id = j;
    out->hinge_or_slide = mm->jnt_type[j] == mjJNT_HINGE || mm->jnt_type[j] == mjJNT_SLIDE;
    out->limited = mm->jnt_actfrclimited[j];
    out->range[0] = mm->jnt_actfrcrange[2 * j];
    out->range[1] = mm->jnt_actfrcrange[2 * j + 1];
    return ROZ_OK;
}

/* A motor's ctrlrange (edit_spec() keeps it limited through the compile;
 * open clears it after binding) is a torque range too. */
static int view_actuator(const void *ctx, const roz__mj_joint_view_t *j, const char *name,
                         roz__mj_actuator_view_t *out)
{
    const mjModel *mm = ctx;
    (void)name;
    for (int a = 0; a < mm->nu; a++) {
        if (mm->actuator_trntype[a] == mjTRN_JOINT && mm->actuator_trnid[2 * a] == j->id) {
            out->id = a;
            out->name = mj_id2name(mm, mjOBJ_ACTUATOR, a);
            out->gear = mm->actuator_gear[6 * a];
            out->gain = mm->actuator_gainprm[a * mjNGAIN];
            out->force_limited = mm->actuator_forcelimited[a];
            out->force[0] = mm->actuator_forcerange[2 * a];
            out->force[1] = mm->actuator_forcerange[2 * a + 1];
            out->ctrl_limited = mm->actuator_ctrllimited[a];
            out->ctrl[0] = mm->actuator_ctrlrange[2 * a];
            out->ctrl[1] = mm->actuator_ctrlrange[2 * a + 1];
            return ROZ_OK;
        }
    }
    return ROZ_ENOENT;
}

static void view_sensor(const void *ctx, int i, roz__mj_sensor_view_t *out)
{
    const mjModel *mm = ctx;
    out->name = mj_id2name(mm, mjOBJ_SENSOR, i);
    out->kind = mm->sensor_type[i] == mjSENS_GYRO            ? ROZ__MJ_SENSOR_GYRO
                : mm->sensor_type[i] == mjSENS_ACCELEROMETER ? ROZ__MJ_SENSOR_ACCELEROMETER
                                                             : ROZ__MJ_SENSOR_OTHER;
    out->site = mm->sensor_objtype[i] == mjOBJ_SITE ? mm->sensor_objid[i] : -1;
}

static roz__mj_model_view_t model_view(const roz_mujoco_t *s)
{
    roz__mj_model_view_t v = { s->model_path, s->model, view_joint, view_actuator,
                               s->model->nsensor, view_sensor };
    return v;
}

/* The port's error: "mujoco: <origin>: ", where a rule's text follows;
 * how many bytes of @p err it took. */
static size_t said_by(const roz_mujoco_t *s, char *err, size_t errlen)
{
    size_t n = (size_t)roz_format(err, errlen, PORT ": %s: ", origin(s));
    return n < errlen ? n : errlen - 1;
}

static int bind_joint(roz_mujoco_t *s, uint16_t k, const char *name, const char *mj_name,
                      char *err, size_t errlen)
{
    const mjModel *mm = s->model;
    roz_mujoco_joint_t *j = &s->joints[k];
    roz__mj_model_view_t v = model_view(s);
    roz__mj_joint_view_t jv;
    roz__mj_actuator_view_t av;
    size_t n = said_by(s, err, errlen);
    if (roz__mj_bind_rule(&v, name, mj_name, manifest_effort(s->m, &j->ch), &jv, &av, &j->tau_lo, &j->tau_hi, err + n,
                          errlen - n) != NULL)
        return ROZ_EINVAL;
    j->jnt = jv.id;
    j->act = av.id;
    j->qadr = mm->jnt_qposadr[j->jnt];
    j->dadr = mm->jnt_dofadr[j->jnt];
    j->gear = av.gear * av.gain;
    const roz_joint_channels_t *c = &j->ch;
    j->law = c->kp_cmd >= 0 || c->kd_cmd >= 0 ? LAW_MIT
             : c->dq_cmd >= 0                 ? LAW_VELOCITY
             : c->q_cmd >= 0                  ? LAW_POSITION
                                              : LAW_EFFORT;
    return ROZ_OK;
}

/* What a model without an IMU needs, after open's refusal in @p err: the
 * lines to add (a site on the base body, a gyro and an accelerometer on
 * it). Only where no sensor was named: a named one that is wrong is the
 * robot.toml's mistake, not the model's. Test: test_mujoco_models.c. */
static void imu_help(const roz_mujoco_t *s, int gyro_too, char *err, size_t errlen)
{
    const mjModel *mm = s->model;
    const char *body = s->base_body >= 0 ? mj_id2name(mm, mjOBJ_BODY, s->base_body) : NULL;
    const char *site = s->imu_site >= 0 ? mj_id2name(mm, mjOBJ_SITE, s->imu_site) : NULL;
    size_t n = strlen(err);
    /* a site meant for the IMU (its name says so) that has no sensors yet */
    const char *named = NULL;
    for (int i = 0; i < mm->nsite && named == NULL && (gyro_too || site == NULL); i++) {
        const char *sn = mj_id2name(mm, mjOBJ_SITE, i);
        if (sn != NULL && (strstr(sn, "imu") != NULL || strstr(sn, "IMU") != NULL))
            named = sn;
    }
    if (named != NULL)
        roz_format(err + n, errlen - n, ": the port reads base_imu from a <gyro> and an "
                   "<accelerometer> on one <site> (the orientation is the site's frame); the "
                   "model has site \"%s\": add to <sensor> <gyro name=\"imu-gyro\" "
                   "site=\"%s\"/> <accelerometer name=\"imu-accelerometer\" site=\"%s\"/>",
                   named, named, named);
    else if (gyro_too || site == NULL)
        roz_format(err + n, errlen - n, ": the port reads base_imu from a <gyro> and an "
                   "<accelerometer> on one <site> (the orientation is the site's frame); add "
                   "to %s%s%s <site name=\"imu\"/>, and to <sensor> <gyro name=\"imu-gyro\" "
                   "site=\"imu\"/> <accelerometer name=\"imu-accelerometer\" site=\"imu\"/>",
                   body != NULL ? "<body name=\"" : "the base body", body != NULL ? body : "",
                   body != NULL ? "\">" : "");
    else
        roz_format(err + n, errlen - n, ": the port reads the acceleration from an "
                   "<accelerometer> on the gyro's site; add to <sensor> <accelerometer "
                   "name=\"imu-accelerometer\" site=\"%s\"/>", site);
}

static int bind_imu(roz_mujoco_t *s, const roz_params_t *p, char *err,
                    size_t errlen)
{
    int want = 0;
    for (int k = 0; k < ROZ_IMU_VALUES; k++)
        want |= s->imu[k] >= 0;
    s->gyro_adr = s->acc_adr = s->imu_site = -1;
    if (!want)
        return ROZ_OK;
    const char *gyro = roz_params_get_str(p, "imu_gyro", NULL);
    const char *acc = roz_params_get_str(p, "imu_accelerometer", NULL);
    const mjModel *mm = s->model;
    roz__mj_model_view_t v = model_view(s);
    int gi = -1, ai = -1;
    size_t n = said_by(s, err, errlen);
    int bad = roz__mj_imu_rule(&v, gyro, acc, &gi, &ai, err + n, errlen - n);
    if (bad != 1)
        s->imu_site = mm->sensor_objid[gi]; /* the gyro is on a site (imu_help() names it) */
    if (bad != 0) {
        if ((bad == 1 && gyro == NULL) || (bad == 2 && acc == NULL))
            imu_help(s, bad == 1, err, errlen);
        return ROZ_EINVAL;
    }
    s->gyro_adr = mm->sensor_adr[gi];
    s->acc_adr = mm->sensor_adr[ai];
    int acc_site = mm->sensor_objtype[ai] == mjOBJ_SITE ? mm->sensor_objid[ai] : -1;
    if (acc_site != s->imu_site && s->log != NULL) {
        char msg[512];
        const char *gs = mj_id2name(s->model, mjOBJ_SITE, s->imu_site);
        const char *as = acc_site >= 0 ? mj_id2name(s->model, mjOBJ_SITE, acc_site) : NULL;
        roz_format(msg, sizeof msg, PORT ": %s: warning: %s: the accelerometer is on %s%s%s, "
                   "the gyro on site \"%s\": base_imu's orientation and rate are the gyro's "
                   "site's, its acceleration another place's", origin(s), s->model_path,
                   as != NULL ? "site \"" : "no site", as != NULL ? as : "", as != NULL ? "\"" : "",
                   gs != NULL ? gs : "?");
        s->log(s->log_ctx, ROZ_LOG_WARN, msg);
    }
    return ROZ_OK;
}

static void note(const roz_mujoco_t *s, roz_log_level_t level, const char *msg)
{
    if (s->log != NULL)
        s->log(s->log_ctx, level, msg);
}

static void close_model(roz_mujoco_t *s)
{
    if (s->data != NULL)
        mj_deleteData(s->data);
    if (s->model != NULL)
        mj_deleteModel(s->model);
    s->data = NULL;
    s->model = NULL;
}

static void update_base(roz_mujoco_t *s);
static int perturb_open(roz_mujoco_t *s, const roz_params_t *p, char *err, size_t errlen);
static int perturb_command(roz_mujoco_t *s);
static void perturb_sample(roz_mujoco_t *s, double *out);

/* The spec being made into a model, for the guard's clean-up (open is
 * start-up, one at a time). */
static mjSpec *open_spec;

static int open_model(roz_mujoco_t *s, const roz_manifest_t *m, const roz_params_t *extra,
                      char *err, size_t errlen)
{
    static merged_t merged; /* open is start-up, one at a time */
    static roz__mj_joints_t jn;
    char mjerr[1024] = "";
    char msg[512];

    close_model(s);
    roz_log_fn log = s->log;
    void *log_ctx = s->log_ctx;
    const char *robot_file = s->robot_file;
    memset(s, 0, sizeof *s);
    s->log = log;
    s->log_ctx = log_ctx;
    s->robot_file = robot_file;
    s->m = m;
    s->base_jnt = s->base_body = s->base_qadr = s->base_dadr = -1;
    s->gantry_eq = -1;

    if (merge_params(m, extra, &merged) != ROZ_OK) {
        roz_format(err, errlen, PORT ": more than %u parameters",
                   (unsigned)(sizeof merged.items / sizeof merged.items[0]));
        return ROZ_EINVAL;
    }
    const roz_params_t *p = &merged.p;
    /* the keys, the numbers and words that need no model (mj_params.c,
     * which rozgen runs too) */
    roz__mj_values_t v;
    if (roz__mj_params_read(p, &v, err, errlen, NULL, NULL) != ROZ_OK)
        return ROZ_EINVAL;
    s->wheel_radius = v.wheel_radius;
    s->wheel_separation = v.wheel_separation;
    s->max_thrust = v.max_thrust;
    s->noise_q = v.noise_q;
    s->noise_dq = v.noise_dq;
    s->noise_tau = v.noise_tau;
    s->noise_gyro = v.noise_gyro;
    s->noise_acc = v.noise_acc;
    s->velocity_kp = v.servo_kp;
    s->velocity_kd = v.servo_kd;
    s->latency = v.latency;
    s->rng = 0x9E3779B97F4A7C15ull ^ v.seed;
    const char *unbound = roz_params_get_str(p, "unbound", "lock"); /* lock or limp: read */

    const char *model = roz_params_get_str(p, "model", NULL);
    if (model == NULL || model[0] == '\0') {
        size_t n = said_by(s, err, errlen);
        roz__mj_model_missing(m->robot_id, err + n, errlen - n);
        return ROZ_EINVAL;
    }
    if (model_path(s, model, err, errlen) != ROZ_OK)
        return ROZ_EINVAL;

    /* the joints, and what they are called in the model (mj_rules.c) */
    for (int k = 0; k < ROZ_IMU_VALUES; k++)
        s->imu[k] = -1;
    size_t said = said_by(s, err, errlen);
    if (roz__mj_joints_of(m, p, &jn, err + said, errlen - said) != ROZ_OK)
        return ROZ_EINVAL;
    s->mobile = (uint8_t)jn.mobile;
    memcpy(s->mob_cmd, jn.mob_cmd, sizeof s->mob_cmd);
    memcpy(s->mob_state, jn.mob_state, sizeof s->mob_state);
    const char *const *mj_names = jn.mj;
    if (s->mobile == MOBILE_WHEELS) {
        for (int k = 0; k < 2; k++)
            memset(&s->joints[k].ch, 0xff, sizeof s->joints[k].ch); /* no channel: -1 */
        s->n_joints = 2;
        if (s->wheel_radius == 0.0 || s->wheel_separation == 0.0) {
            roz_format(err, errlen, PORT ": %s: hardware.params.%s: missing (m)", origin(s),
                       s->wheel_radius == 0.0 ? "wheel_radius" : "wheel_separation");
            return ROZ_EINVAL;
        }
    }
    if (s->mobile == MOBILE_NONE) {
        roz_joint_channels_t ch[ROZ_MUJOCO_MAX_JOINTS];
        if (roz_joints_bind(m, PORT, "this robot", jn.names, jn.n, ch, s->imu, err, errlen) !=
            ROZ_OK)
            return ROZ_EINVAL;
        for (uint16_t j = 0; j < jn.n; j++)
            s->joints[j].ch = ch[j];
        s->n_joints = jn.n;
    }

    /* read within the checker's limits before MuJoCo reads it (its include
     * tree: mjcf_scan.c) */
    char why[ROZ_MUJOCO_PATH_MAX + 160];
    roz__mjcf_model_t scanned;
    int scan = roz__mjcf_read(s->model_path, &scanned, why, sizeof why);
    roz__mjcf_free(&scanned);
    if (scan != ROZ_OK) {
        roz_format(err, errlen, PORT ": %s: hardware.params.model = \"%s\": %s", origin(s),
                   s->model_path, why);
        return ROZ_EINVAL;
    }
    /* parse, make it roz's, compile: the heap's busiest moments, all here */
    mjSpec *spec = open_spec = mj_parseXML(s->model_path, NULL, mjerr, sizeof mjerr);
    if (spec == NULL) {
        roz_format(err, errlen, PORT ": %s: hardware.params.model = \"%s\": %s", origin(s),
                   s->model_path, mjerr[0] ? mjerr : "cannot be read");
        return ROZ_EINVAL;
    }
    if (check_meshes(s, spec, err, errlen) != ROZ_OK) {
        mj_deleteSpec(spec);
        open_spec = NULL;
        return ROZ_EINVAL;
    }
    uint32_t servos = 0, locked = 0;
    const char *lock = roz_params_find(p, "lock");
    if (check_lock(s, spec, lock, err, errlen) != ROZ_OK ||
        edit_spec(s, spec, mj_names, jn.n, strcmp(unbound, "lock") == 0, lock, &servos, &locked,
                  err, errlen) != ROZ_OK) {
        mj_deleteSpec(spec);
        open_spec = NULL;
        return ROZ_EINVAL;
    }
    s->model = mj_compile(spec, NULL);
    if (s->model == NULL) {
        roz_format(err, errlen, PORT ": %s: hardware.params.model = \"%s\": %s", origin(s),
                   s->model_path, mjs_getError(spec));
        mj_deleteSpec(spec);
        open_spec = NULL;
        return ROZ_EINVAL;
    }
    mj_deleteSpec(spec);
    open_spec = NULL;
    mjModel *mm = s->model;
    /* a diverged simulation is never reset behind the test's back (it read
     * back as a robot standing at its start): it warns, and the warning
     * fails every read after it (test_mujoco_warning_fails_the_run) */
    mm->opt.disableflags |= mjDSBL_AUTORESET;

    for (uint16_t j = 0; j < jn.n; j++) {
        if (bind_joint(s, j, jn.names[j], mj_names[j], err, errlen) != ROZ_OK) {
            close_model(s);
            return ROZ_EINVAL;
        }
        if (s->mobile == MOBILE_WHEELS)
            s->joints[j].law = LAW_WHEEL;
    }
    for (int a = 0; a < mm->nu; a++)
        mm->actuator_ctrllimited[a] = 0; /* read by bind_joint(); roz saturates the torque */
    for (int j = 0; j < mm->njnt; j++) {
        if (mm->jnt_type[j] == mjJNT_FREE) {
            s->base_jnt = j;
            s->base_body = mm->jnt_bodyid[j];
            s->base_qadr = mm->jnt_qposadr[j];
            s->base_dadr = mm->jnt_dofadr[j];
            break;
        }
    }
    if (s->gantry_eq >= 0) {
        s->gantry_eq = -1;
        for (int e = mm->neq - 1; e >= 0 && s->gantry_eq < 0; e--) {
            if (mm->eq_type[e] == mjEQ_WELD && mm->eq_obj1id[e] == s->base_body)
                s->gantry_eq = e;
        }
    }
    if (s->mobile == MOBILE_AUTOPILOT) {
        if (s->base_body < 0) {
            roz_format(err, errlen, PORT ": %s: %s: a quadcopter needs a free joint (the "
                       "airframe's)", origin(s), s->model_path);
            close_model(s);
            return ROZ_EINVAL;
        }
        s->mass = mm->body_subtreemass[s->base_body];
        if (!(s->max_thrust > s->mass * 9.81)) {
            roz_format(err, errlen, PORT ": %s: hardware.params.max_thrust = %g N: it must lift "
                       "the %.3f kg airframe (more than %.2f N)", origin(s), s->max_thrust,
                       s->mass, s->mass * 9.81);
            close_model(s);
            return ROZ_EINVAL;
        }
    }
    if (bind_imu(s, p, err, errlen) != ROZ_OK) {
        close_model(s);
        return ROZ_EINVAL;
    }

    /* time: one tick is a whole number of steps */
    double dt;
    char dflt[32];
    roz_format(dflt, sizeof dflt, "%.17g", mm->opt.timestep);
    const char *ts = roz_params_get_str(p, "timestep", dflt);
    roz_param_t one = { "timestep", ts };
    roz_params_t onep = { &one, 1 };
    if (roz_params_get_row_double(&onep, MJ_PARAMS, "timestep", &dt, err, errlen) != ROZ_OK) {
        close_model(s);
        return ROZ_EINVAL;
    }
    double period = 1.0 / m->control_rate_hz;
    double steps = floor(period / dt + 0.5);
    if (steps < 1.0 || fabs(steps * dt - period) > 1e-9 * period) {
        roz_format(err, errlen, PORT ": %s: hardware.params.timestep = %g s: the control period "
                   "(%g s, %u Hz) must be a whole number of timesteps", origin(s), dt, period,
                   (unsigned)m->control_rate_hz);
        close_model(s);
        return ROZ_EINVAL;
    }
    mm->opt.timestep = dt;
    s->timestep = dt;
    s->steps_per_tick = (uint32_t)steps;

    s->data = mj_makeData(mm);
    if (s->data == NULL) {
        roz_format(err, errlen, PORT ": %s: %s: no memory for its data", origin(s), s->model_path);
        close_model(s);
        return ROZ_EINVAL;
    }
    if (perturb_open(s, p, err, errlen) != ROZ_OK) {
        close_model(s);
        return ROZ_EINVAL;
    }
    const char *key = roz_params_get_str(p, "keyframe", NULL);
    if (key != NULL && key[0] != '\0') {
        int k = mj_name2id(mm, mjOBJ_KEY, key);
        if (k < 0) {
            roz_format(err, errlen, PORT ": %s: hardware.params.keyframe = \"%s\": no keyframe of "
                       "that name in %s", origin(s), key, s->model_path);
            close_model(s);
            return ROZ_EINVAL;
        }
        mj_resetDataKeyframe(mm, s->data, k);
    }
    mju_zero(s->data->ctrl, mm->nu);
    mj_forward(mm, s->data);
    for (uint16_t j = 0; j < s->n_joints; j++)
        s->joints[j].q_ref = s->data->qpos[s->joints[j].qadr];

    if (parse_faults(s, p, err, errlen) != ROZ_OK) {
        close_model(s);
        return ROZ_EINVAL;
    }
    mju_user_warning = count_warning;
    s->base.min_height = INFINITY;
    update_base(s);

    char held[64] = "";
    if (locked > 0)
        roz_format(held, sizeof held, ", %u bound joint%s locked (lock)", (unsigned)locked,
                   locked == 1 ? "" : "s");
    roz_format(msg, sizeof msg, PORT ": %s: %u joints bound%s, %u actuator%s turned from servos "
               "into motors (roz applies the robot's own law), %u model joint%s %s; %u steps of "
               "%g s a tick", s->model_path, (unsigned)s->n_joints, held, (unsigned)servos,
               servos == 1 ? "" : "s", (unsigned)s->unbound, s->unbound == 1 ? "" : "s",
               strcmp(unbound, "lock") == 0 ? "locked (no channel binds them)" : "limp",
               (unsigned)s->steps_per_tick, dt);
    note(s, ROZ_LOG_INFO, msg);
    return ROZ_OK;
}

typedef struct {
    roz_mujoco_t         *s;
    const roz_manifest_t *m;
    const roz_params_t   *extra;
    char                 *err;
    size_t                errlen;
} open_args_t;

static int open_guarded(void *ctx)
{
    open_args_t *a = ctx;
    return open_model(a->s, a->m, a->extra, a->err, a->errlen);
}

/* Open, with whatever MuJoCo raises or throws meanwhile (mj_guard.h) a
 * refusal naming the model (test_mujoco_engine_error_is_a_fault). */
static int mj_open(void *self, const roz_manifest_t *m, const roz_params_t *extra, char *err,
                   size_t errlen)
{
    roz_mujoco_t *s = self;
    open_args_t a = { s, m, extra, err, errlen };
    char what[sizeof s->engine_error];
    what[0] = '\0';
    open_spec = NULL;
    int rc = roz__mj_guard(open_guarded, &a, what, sizeof what);
    if (what[0] == '\0')
        return rc;
    if (open_spec != NULL)
        mj_deleteSpec(open_spec);
    open_spec = NULL;
    close_model(s);
    roz_format(err, errlen, PORT ": %s: hardware.params.model = \"%s\": %s", origin(s),
               s->model_path, what);
    return ROZ_EINVAL;
}

/* ---- private: the tick ------------------------------------------------------------ */

static int active(const roz_mujoco_fault_t *f, uint64_t t)
{
    return t >= f->from && (f->to == 0 || t < f->to);
}

/* Gaussian noise from a seeded splitmix64: the same run, the same bits. */
static double uniform01(roz_mujoco_t *s)
{
    uint64_t z = (s->rng += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return ((double)(z >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

static double gauss(roz_mujoco_t *s, double sigma)
{
    if (sigma == 0.0)
        return 0.0;
    double u = uniform01(s), v = uniform01(s);
    return sigma * sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

/* ---- private: perturbations ------------------------------------------------------ */

/* docs/ports/mujoco.md, "Perturbations". The model's own numbers are changed
 * at open, before anything runs (mj_setConst() then recomputes what the
 * compiler derived from them); the sensors' offsets are drawn once, at open,
 * from the noise's seed (only those asked for, so a run without them draws
 * the same noise as before); the rest acts at read() and write(). */

/* Mass @p kg at body @p b, at @p at (its frame) or, NULL, its centre of
 * mass: the body's mass, centre of mass and inertia (about the new centre,
 * its principal axes found again). */
static void add_payload(mjModel *mm, int b, double kg, const double *at)
{
    double M = mm->body_mass[b], M2 = M + kg;
    if (!(M2 > 0.0))
        return;
    mjtNum c[3], p[3], c2[3], R[9], Rt[9], D[9] = { 0 }, tmp[9], I[9], d[3];
    mju_copy3(c, mm->body_ipos + 3 * b);
    mju_copy3(p, at != NULL ? at : c);
    for (int k = 0; k < 3; k++)
        c2[k] = (M * c[k] + kg * p[k]) / M2;
    mju_quat2Mat(R, mm->body_iquat + 4 * b);
    for (int k = 0; k < 3; k++)
        D[4 * k] = mm->body_inertia[3 * b + k];
    mju_transpose(Rt, R, 3, 3);
    mju_mulMatMat(tmp, R, D, 3, 3, 3);
    mju_mulMatMat(I, tmp, Rt, 3, 3, 3); /* about the old centre, body frame */
    const mjtNum *pts[2] = { c, p };
    const double mass[2] = { M, kg };
    for (int e = 0; e < 2; e++) { /* parallel axes: each mass about the new centre */
        mju_sub3(d, pts[e], c2);
        double dd = mju_dot3(d, d);
        for (int r = 0; r < 3; r++)
            for (int q = 0; q < 3; q++)
                I[3 * r + q] += mass[e] * ((r == q ? dd : 0.0) - d[r] * d[q]);
    }
    mjtNum eigval[3], eigvec[9], quat[4];
    mju_eig3(eigval, eigvec, quat, I);
    mm->body_mass[b] = M2;
    mju_copy3(mm->body_ipos + 3 * b, c2);
    mju_copy3(mm->body_inertia + 3 * b, eigval);
    mju_copy4(mm->body_iquat + 4 * b, quat);
}

/* "ENTRY;ENTRY": the next entry into @p buf (blanks trimmed); NULL at the end. */
static const char *next_entry(const char *e, char *buf, size_t cap)
{
    while (e != NULL && (*e == ' ' || *e == ';'))
        e++;
    if (e == NULL || *e == '\0')
        return NULL;
    const char *end = strchr(e, ';');
    size_t n = end != NULL ? (size_t)(end - e) : strlen(e);
    while (n > 0 && e[n - 1] == ' ')
        n--;
    n = n < cap - 1 ? n : cap - 1;
    memcpy(buf, e, n);
    buf[n] = '\0';
    return end != NULL ? end : e + strlen(e);
}

static int parse_payloads(roz_mujoco_t *s, const char *v, char *err, size_t errlen)
{
    char e[2 * ROZ_MUJOCO_NAME_MAX + 96];
    for (const char *rest = next_entry(v, e, sizeof e); rest != NULL;
         rest = next_entry(rest, e, sizeof e)) {
        char *end, *at = strchr(e, '@');
        double kg = strtod(e, &end);
        char *at2 = at != NULL ? strchr(at + 1, '@') : NULL;
        double xyz[3];
        int ok = end != e && end == at && isfinite(kg) && kg >= 0.0 && kg <= 1000.0 &&
                 at[1] != '\0' && (at2 == NULL || at2 > at + 1);
        if (ok && at2 != NULL) {
            *at2 = '\0';
            const char *q = at2 + 1;
            for (int k = 0; ok && k < 3; k++) {
                xyz[k] = strtod(q, &end);
                ok = end != q && isfinite(xyz[k]) && fabs(xyz[k]) <= 10.0 &&
                     *end == (k < 2 ? ',' : '\0');
                q = end + 1;
            }
        }
        if (!ok) {
            roz_format(err, errlen, PORT ": %s: hardware.params.payload = \"%s\": expected "
                       "KG@BODY[@X,Y,Z] (kg in 0..1000, m in -10..10), ';' between entries",
                       origin(s), v);
            return ROZ_EINVAL;
        }
        int b = mj_name2id(s->model, mjOBJ_BODY, at + 1);
        if (b <= 0) {
            roz_format(err, errlen, PORT ": %s: hardware.params.payload = \"%s\": no body "
                       "\"%s\" in %s (the world carries no payload)", origin(s), v, at + 1,
                       s->model_path);
            return ROZ_EINVAL;
        }
        add_payload(s->model, b, kg, at2 != NULL ? xyz : NULL);
    }
    return ROZ_OK;
}

static int parse_strength(roz_mujoco_t *s, const char *v, char *err, size_t errlen)
{
    char e[ROZ_MUJOCO_NAME_MAX + 48];
    for (const char *rest = next_entry(v, e, sizeof e); rest != NULL;
         rest = next_entry(rest, e, sizeof e)) {
        char *end, *at = strchr(e, '@');
        double k = strtod(e, &end);
        int ok = end != e && (end == at || (at == NULL && *end == '\0')) && isfinite(k) &&
                 k >= 0.0 && k <= 1.0 && (at == NULL || at[1] != '\0');
        if (!ok) {
            roz_format(err, errlen, PORT ": %s: hardware.params.strength_scale = \"%s\": "
                       "expected S[@JOINT] (S in 0..1), ';' between entries", origin(s), v);
            return ROZ_EINVAL;
        }
        int found = 0;
        for (uint16_t j = 0; j < s->n_joints; j++) {
            roz_mujoco_joint_t *jt = &s->joints[j];
            const char *name = mj_id2name(s->model, mjOBJ_JOINT, jt->jnt);
            if (at != NULL && (name == NULL || strcmp(name, at + 1) != 0))
                continue;
            jt->tau_lo *= k;
            jt->tau_hi *= k;
            found = 1;
        }
        if (!found && at != NULL) {
            roz_format(err, errlen, PORT ": %s: hardware.params.strength_scale = \"%s\": no "
                       "bound joint \"%s\" in %s", origin(s), v, at + 1, s->model_path);
            return ROZ_EINVAL;
        }
    }
    return ROZ_OK;
}

static int perturb_open(roz_mujoco_t *s, const roz_params_t *p, char *err, size_t errlen)
{
    mjModel *mm = s->model;
    roz__mj_perturb_t v;
    if (roz__mj_perturb_read(p, &v, err, errlen, NULL, NULL) != ROZ_OK)
        return ROZ_EINVAL;
    double mass = v.mass, friction = v.friction, damping = v.damping, armature = v.armature;
    double bq = v.bias_q, bg = v.bias_gyro, ba = v.bias_acc, bo = v.bias_orientation;
    s->gains_scale = v.gains;
    s->cmd_latency = v.cmd_latency;
    if (mass != 1.0) {
        for (int b = 1; b < mm->nbody; b++) {
            mm->body_mass[b] *= mass;
            mju_scl3(mm->body_inertia + 3 * b, mm->body_inertia + 3 * b, mass);
        }
    }
    if (parse_payloads(s, roz_params_find(p, "payload"), err, errlen) != ROZ_OK ||
        parse_strength(s, roz_params_find(p, "strength_scale"), err, errlen) != ROZ_OK)
        return ROZ_EINVAL;
    if (friction != 1.0) {
        for (int g = 0; g < mm->ngeom; g++)
            mm->geom_friction[3 * g] *= friction;
        for (int q = 0; q < mm->npair; q++) {
            mm->pair_friction[5 * q] *= friction;
            mm->pair_friction[5 * q + 1] *= friction;
        }
    }
    for (uint16_t j = 0; j < s->n_joints; j++) {
        mm->dof_damping[s->joints[j].dadr] += damping;
        mm->dof_armature[s->joints[j].dadr] += armature;
    }
    mj_setConst(mm, s->data); /* what the compiler derived: subtree masses, M0, ... */
    for (uint16_t j = 0; j < s->n_joints; j++)
        s->bias_q[j] = gauss(s, bq);
    for (int k = 0; k < 6; k++)
        s->bias_imu[k] = gauss(s, k < 3 ? bg : ba);
    mjtNum r[3] = { gauss(s, bo), gauss(s, bo), gauss(s, bo) };
    mjtNum angle = mju_normalize3(r);
    s->bias_quat[0] = 1.0;
    s->bias_quat[1] = s->bias_quat[2] = s->bias_quat[3] = 0.0;
    if (angle > 0.0)
        mju_axisAngle2Quat(s->bias_quat, r, angle);
    return ROZ_OK;
}

/* write() under command latency: the command just clamped into s->cmd goes
 * into the ring, the one written cmd_latency ticks ago comes out to the
 * drivers; 0 while none is that old yet (the drivers have none). */
static int perturb_command(roz_mujoco_t *s)
{
    size_t n = s->m->n_commands;
    uint64_t w = s->cmd_count++;
    memcpy(s->cmd_hist[w % DEPTH], s->cmd, n * sizeof s->cmd[0]);
    if (w < s->cmd_latency)
        return 0;
    memcpy(s->cmd, s->cmd_hist[(w - s->cmd_latency) % DEPTH], n * sizeof s->cmd[0]);
    return 1;
}

/* What a sampled frame carries besides the noise: the encoders' offsets,
 * the IMU's mounting error and its offsets. */
static void perturb_sample(roz_mujoco_t *s, double *out)
{
    for (uint16_t j = 0; j < s->n_joints; j++) {
        if (s->joints[j].ch.q_state >= 0)
            out[s->joints[j].ch.q_state] += s->bias_q[j];
    }
    if (s->imu_site < 0)
        return;
    const int16_t *ix = s->imu; /* x, y, z, w, gyro x..z, accelerometer x..z */
    if (s->bias_quat[0] != 1.0 && ix[0] >= 0 && ix[1] >= 0 && ix[2] >= 0 && ix[3] >= 0) {
        mjtNum q[4] = { out[ix[3]], out[ix[0]], out[ix[1]], out[ix[2]] }, r[4];
        mju_mulQuat(r, q, s->bias_quat);
        out[ix[3]] = r[0];
        out[ix[0]] = r[1];
        out[ix[1]] = r[2];
        out[ix[2]] = r[3];
    }
    for (int k = 0; k < 6; k++) {
        if (ix[4 + k] >= 0)
            out[ix[4 + k]] += s->bias_imu[k];
    }
}

/* The joint drivers, one physics step: the robot's own law from the last
 * command, saturated at the joint's effort limit. */
static void drive(roz_mujoco_t *s)
{
    mjData *d = s->data;
    const double *c = s->cmd;
    for (uint16_t k = 0; k < s->n_joints; k++) {
        roz_mujoco_joint_t *j = &s->joints[k];
        const roz_joint_channels_t *ch = &j->ch;
        double q = d->qpos[j->qadr], dq = d->qvel[j->dadr], tau = 0.0;
        int on = s->have_cmd && !s->dead;
        switch (j->law) {
        case LAW_MIT:
            if (on) {
                double kp = ch->kp_cmd >= 0 ? c[ch->kp_cmd] * s->gains_scale : 0.0;
                double kd = ch->kd_cmd >= 0 ? c[ch->kd_cmd] * s->gains_scale : 0.0;
                double qd = ch->q_cmd >= 0 ? c[ch->q_cmd] : q;
                double dqd = ch->dq_cmd >= 0 ? c[ch->dq_cmd] : 0.0;
                double ff = ch->tau_cmd >= 0 ? c[ch->tau_cmd] : 0.0;
                tau = ff + kp * (qd - q) + kd * (dqd - dq);
            }
            break;
        case LAW_VELOCITY:
        case LAW_WHEEL:
        case LAW_POSITION: {
            /* the drive's own servo, with the arm's gravity compensation; it
             * holds where it is until the first command, as a powered arm does */
            double dqd = 0.0;
            if (on && j->law == LAW_VELOCITY)
                dqd = c[ch->dq_cmd];
            if (on && j->law == LAW_WHEEL) /* joints[0] is the left wheel */
                dqd = (c[s->mob_cmd[0]] + (k == 0 ? -0.5 : 0.5) * s->wheel_separation *
                                              c[s->mob_cmd[1]]) / s->wheel_radius;
            if (on && j->law == LAW_POSITION)
                j->q_ref = c[ch->q_cmd];
            else
                j->q_ref += dqd * s->timestep;
            if (s->dead)
                break;
            /* the reference never runs further ahead than the torque can pull */
            double lead = s->velocity_kp > 0.0 ? fmax(-j->tau_lo, j->tau_hi) / s->velocity_kp : 0.0;
            if (j->law != LAW_POSITION && j->q_ref - q > lead)
                j->q_ref = q + lead;
            if (j->law != LAW_POSITION && q - j->q_ref > lead)
                j->q_ref = q - lead;
            tau = d->qfrc_bias[j->dadr] + s->velocity_kp * (j->q_ref - q) +
                  s->velocity_kd * (dqd - dq);
            break;
        }
        default:
            tau = on && ch->tau_cmd >= 0 ? c[ch->tau_cmd] : 0.0;
            break;
        }
        if (tau > j->tau_hi || tau < j->tau_lo) {
            tau = tau > j->tau_hi ? j->tau_hi : j->tau_lo;
            s->saturated++;
        }
        if (!isfinite(tau))
            tau = 0.0;
        s->tau[k] = tau;
        d->ctrl[j->act] = tau / j->gear;
    }
}

/* The quadcopter's autopilot, one physics step: body velocities (x, y in
 * the heading frame, z up) and a yaw rate become a total thrust along the
 * body's z axis and body torques, as a flight controller's velocity mode
 * does over its rotors; the wrench it gives the airframe (world frame) goes
 * in @p out. Nothing before the first command, nor while the board is down. */
static void autopilot(const roz_mujoco_t *s, mjtNum out[6])
{
    const mjModel *mm = s->model;
    const mjData *d = s->data;
    mju_zero(out, 6);
    if (!s->have_cmd || s->dead)
        return;
    const mjtNum *R = d->xmat + 9 * s->base_body; /* body to world, row-major */
    const mjtNum *v = d->qvel + s->base_dadr, *w = d->qvel + s->base_dadr + 3; /* world, body */
    double yaw = atan2(R[3], R[0]), cy = cos(yaw), sy = sin(yaw);
    const double *c = s->cmd;
    double vx = c[s->mob_cmd[0]], vy = c[s->mob_cmd[1]];
    double vw[3] = { cy * vx - sy * vy, sy * vx + cy * vy, c[s->mob_cmd[2]] };
    double a[3] = { AP_KV_XY * (vw[0] - v[0]), AP_KV_XY * (vw[1] - v[1]), AP_KV_Z * (vw[2] - v[2]) };
    double ah = sqrt(a[0] * a[0] + a[1] * a[1]), amax = 9.81 * tan(AP_MAX_TILT);
    if (ah > amax) {
        a[0] *= amax / ah;
        a[1] *= amax / ah;
    }
    mjtNum F[3] = { s->mass * a[0], s->mass * a[1], s->mass * (a[2] + 9.81) };
    if (F[2] < 0.0)
        F[2] = 0.0;
    mjtNum zb[3] = { R[2], R[5], R[8] }, zd[3], e[3], eb[3];
    mju_copy3(zd, F);
    if (mju_normalize3(zd) < 1e-9)
        mju_copy3(zd, zb);
    mju_cross(e, zb, zd);    /* the tilt that brings the body's z to zd, world frame */
    mju_mulMatTVec3(eb, R, e); /* in the body's frame */
    const mjtNum *I = mm->body_inertia + 3 * s->base_body;
    mjtNum tb[3];
    for (int k = 0; k < 2; k++) {
        tb[k] = I[k] * (AP_OMEGA * AP_OMEGA * eb[k] - 2.0 * AP_ZETA * AP_OMEGA * w[k]);
        tb[k] = tb[k] > AP_MAX_TORQUE_XY ? AP_MAX_TORQUE_XY : tb[k] < -AP_MAX_TORQUE_XY ? -AP_MAX_TORQUE_XY : tb[k];
    }
    tb[2] = I[2] * AP_YAW_BW * (c[s->mob_cmd[3]] - w[2]);
    tb[2] = tb[2] > AP_MAX_TORQUE_Z ? AP_MAX_TORQUE_Z : tb[2] < -AP_MAX_TORQUE_Z ? -AP_MAX_TORQUE_Z : tb[2];
    double thrust = mju_dot3(F, zb); /* what the rotors give: along the body's z only */
    thrust = thrust < 0.0 ? 0.0 : thrust > s->max_thrust ? s->max_thrust : thrust;
    mju_scl3(out, zb, thrust);
    mju_mulMatVec3(out + 3, R, tb);
}

/* A diff drive's odometry, one physics step: its wheel encoders integrated,
 * as the base's firmware does (wheel slip shows as odometry error). */
static void odometry(roz_mujoco_t *s)
{
    const mjData *d = s->data;
    double wl = d->qvel[s->joints[0].dadr], wr = d->qvel[s->joints[1].dadr];
    double v = 0.5 * s->wheel_radius * (wl + wr);
    double w = s->wheel_radius * (wr - wl) / s->wheel_separation;
    s->odom[2] += w * s->timestep;
    if (s->odom[2] > PI)
        s->odom[2] -= 2.0 * PI;
    if (s->odom[2] < -PI)
        s->odom[2] += 2.0 * PI;
    s->odom[0] += v * cos(s->odom[2]) * s->timestep;
    s->odom[1] += v * sin(s->odom[2]) * s->timestep;
}

static void advance(roz_mujoco_t *s, uint64_t t)
{
    const mjModel *mm = s->model;
    mjData *d = s->data;
    int gantry = 0;
    mju_zero(d->xfrc_applied, 6 * mm->nbody);
    for (uint32_t i = 0; i < s->n_faults; i++) {
        const roz_mujoco_fault_t *f = &s->faults[i];
        if (f->kind == ROZ_INJECT_PUSH && active(f, t)) {
            for (int k = 0; k < 3; k++)
                d->xfrc_applied[6 * f->body + k] += f->force[k];
        }
        gantry |= f->kind == ROZ_INJECT_GANTRY && active(f, t);
        if (f->kind == ROZ_INJECT_RESTART) {
            if (t == f->from) {
                s->dead = 1;
                s->have_cmd = 0; /* a board that boots knows no command */
            }
            if (t == f->to && s->dead) {
                s->dead = 0;
                s->rebooted = 1;
            }
        }
    }
    if (s->gantry_eq >= 0) {
        if (gantry && !d->eq_active[s->gantry_eq]) {
            /* hung where it is now: the world's pose in the base's frame */
            mjtNum *e = s->model->eq_data + mjNEQDATA * s->gantry_eq;
            const mjtNum *pos = d->xpos + 3 * s->base_body, *q = d->xquat + 4 * s->base_body;
            mjtNum qi[4], rel[3];
            mju_negQuat(qi, q);
            mju_rotVecQuat(rel, pos, qi);
            mju_zero3(e);             /* anchor */
            mju_scl3(e + 3, rel, -1); /* relpose position */
            mju_copy4(e + 6, qi);     /* relpose orientation */
            e[10] = 1.0;              /* torque scale */
        }
        d->eq_active[s->gantry_eq] = (mjtByte)gantry;
    }
    mjtNum ap[6] = { 0, 0, 0, 0, 0, 0 };
    for (uint32_t k = 0; k < s->steps_per_tick; k++) {
        drive(s);
        if (s->mobile == MOBILE_AUTOPILOT) {
            mjtNum *x = d->xfrc_applied + 6 * s->base_body;
            mju_subFrom(x, ap, 6); /* the pushes stay, the last step's wrench goes */
            autopilot(s, ap);
            mju_addTo(x, ap, 6);
        }
        mj_step(mm, d);
        for (int w = 0; s->warned == 0 && w < mjNWARNING; w++) {
            if (d->warning[w].number > 0) {
                s->warned = w + 1;
                s->warned_step = s->steps;
            }
        }
        if (s->mobile == MOBILE_WHEELS)
            odometry(s);
        s->steps++;
    }
}

/* The state a real robot's sensors give now (manifest order), noise added. */
static void sample(roz_mujoco_t *s, double *out)
{
    const mjModel *mm = s->model;
    const mjData *d = s->data;
    const roz_manifest_t *m = s->m;
    for (uint16_t i = 0; i < m->n_states; i++)
        out[i] = m->states[i].default_value;
    for (uint16_t k = 0; k < s->n_joints; k++) {
        const roz_mujoco_joint_t *j = &s->joints[k];
        if (j->ch.q_state >= 0)
            out[j->ch.q_state] = d->qpos[j->qadr] + gauss(s, s->noise_q);
        if (j->ch.dq_state >= 0)
            out[j->ch.dq_state] = d->qvel[j->dadr] + gauss(s, s->noise_dq);
        if (j->ch.tau_state >= 0)
            out[j->ch.tau_state] = s->tau[k] + gauss(s, s->noise_tau);
    }
    if (s->mobile == MOBILE_WHEELS) {
        for (int k = 0; k < 3; k++)
            out[s->mob_state[k]] = s->odom[k] + gauss(s, k < 2 ? s->noise_q : s->noise_q);
    }
    if (s->mobile == MOBILE_AUTOPILOT) {
        const mjtNum *p = d->qpos + s->base_qadr, *R = d->xmat + 9 * s->base_body;
        for (int k = 0; k < 3; k++)
            out[s->mob_state[k]] = p[k] + gauss(s, s->noise_q);
        out[s->mob_state[3]] = atan2(R[3], R[0]) + gauss(s, s->noise_q);
    }
    if (s->imu_site >= 0) {
        mjtNum q[4]; /* w, x, y, z */
        mju_mat2Quat(q, d->site_xmat + 9 * s->imu_site);
        const double v[ROZ_IMU_VALUES] = {
            q[1], q[2], q[3], q[0],
            d->sensordata[s->gyro_adr] + gauss(s, s->noise_gyro),
            d->sensordata[s->gyro_adr + 1] + gauss(s, s->noise_gyro),
            d->sensordata[s->gyro_adr + 2] + gauss(s, s->noise_gyro),
            d->sensordata[s->acc_adr] + gauss(s, s->noise_acc),
            d->sensordata[s->acc_adr + 1] + gauss(s, s->noise_acc),
            d->sensordata[s->acc_adr + 2] + gauss(s, s->noise_acc),
        };
        for (int k = 0; k < ROZ_IMU_VALUES; k++) {
            if (s->imu[k] >= 0)
                out[s->imu[k]] = v[k];
        }
    }
    (void)mm;
}

static void update_base(roz_mujoco_t *s)
{
    const mjData *d = s->data;
    roz_mujoco_base_t *b = &s->base;
    b->sim_time = d->time;
    b->steps = s->steps;
    b->floating = s->base_qadr >= 0;
    if (!b->floating)
        return;
    const mjtNum *p = d->qpos + s->base_qadr, *v = d->qvel + s->base_dadr;
    for (int k = 0; k < 3; k++) {
        b->pos[k] = p[k];
        b->lin_vel[k] = v[k];
        b->ang_vel[k] = v[3 + k];
    }
    for (int k = 0; k < 4; k++)
        b->quat[k] = p[3 + k];
    double w = p[3], x = p[4], y = p[5], z = p[6];
    b->roll = atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
    double sp = 2.0 * (w * y - z * x);
    b->pitch = asin(sp > 1.0 ? 1.0 : sp < -1.0 ? -1.0 : sp);
    b->yaw = atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
    if (b->pos[2] < b->min_height)
        b->min_height = b->pos[2];
    double tilt = fmax(fabs(b->roll), fabs(b->pitch));
    if (tilt > b->max_tilt)
        b->max_tilt = tilt;
}

/* The contacts between the robot and the world (body 0) now, and the first
 * @p cap distinct robot bodies in them, as ids into @p ids. Bounded by the
 * model's contacts; no heap, no text: the tick may call it (mj_truth). */
static uint32_t contact_bodies(const roz_mujoco_t *s, int32_t *ids, uint32_t cap, uint32_t *n_ids)
{
    uint32_t contacts = 0;
    *n_ids = 0;
    if (s->data == NULL)
        return 0;
    const mjModel *mm = s->model;
    const mjData *d = s->data;
    for (int i = 0; i < d->ncon; i++) {
        int b1 = mm->geom_bodyid[d->contact[i].geom[0]], b2 = mm->geom_bodyid[d->contact[i].geom[1]];
        if ((b1 == 0) == (b2 == 0))
            continue; /* the robot with itself, or the world with itself */
        int32_t b = b1 == 0 ? b2 : b1;
        contacts++;
        int seen = 0;
        for (uint32_t k = 0; k < *n_ids && !seen; k++)
            seen = ids[k] == b;
        if (!seen && *n_ids < cap)
            ids[(*n_ids)++] = b;
    }
    return contacts;
}

typedef struct {
    roz_mujoco_t *s;
    uint64_t      t;
} advance_args_t;

static int advance_guarded(void *ctx)
{
    advance_args_t *a = ctx;
    advance(a->s, a->t);
    return ROZ_OK;
}

static int mj_read(void *self, double *state, size_t n)
{
    roz_mujoco_t *s = self;
    const roz_manifest_t *m = s->m;
    if (s->data == NULL || n != m->n_states)
        return ROZ_EINVAL;
    uint64_t t = s->tick++;
    if (t > 0 && s->engine_error[0] == '\0') {
        advance_args_t a = { s, t };
        char what[sizeof s->engine_error];
        what[0] = '\0';
        (void)roz__mj_guard(advance_guarded, &a, what, sizeof what);
        if (what[0] != '\0') {
            /* once, and the physics is over: no robot to tick any more */
            s->engine_step = s->steps;
            roz_format(s->engine_error, sizeof s->engine_error, "%s, in %s", what,
                       s->model_path);
        }
    }
    update_base(s);

    double *slot = s->hist[t % DEPTH];
    sample(s, slot);
    perturb_sample(s, slot);
    uint32_t delay = s->latency;
    int lost = s->dead;
    for (uint32_t i = 0; i < s->n_faults; i++) {
        const roz_mujoco_fault_t *f = &s->faults[i];
        if (!active(f, t))
            continue;
        if (f->kind == ROZ_INJECT_DROP || f->kind == ROZ_INJECT_FREEZE)
            lost = 1;
        if (f->kind == ROZ_INJECT_DELAY && delay + f->arg > delay)
            delay += f->arg;
    }
    if (delay > ROZ_MUJOCO_MAX_DELAY)
        delay = ROZ_MUJOCO_MAX_DELAY;
    if (lost || t < delay) {
        s->frames_dropped += lost;
        if (s->frames == 0)
            return ROZ_ENOENT;
        return 0; /* state holds the previous frame: the caller's */
    }
    memcpy(state, s->hist[(t - delay) % DEPTH], n * sizeof *state);
    s->frames++;
    if (s->warned != 0 || s->engine_error[0] != '\0')
        return ROZ_EROBOT; /* the physics is no robot any more: mj_fault() names why */
    if (s->rebooted) {
        s->rebooted = 0;
        return ROZ_ELINK; /* the robot's board came back: a new link */
    }
    return 1;
}

static int mj_write(void *self, const double *cmd, size_t n)
{
    roz_mujoco_t *s = self;
    if (s->data == NULL || n != s->m->n_commands)
        return ROZ_EINVAL;
    s->writes++;
    /* what the filter upstream must never let through, counted before
     * anything else (test_mujoco_pendulum breaks it on purpose) */
    for (uint16_t i = 0; i < s->m->n_commands; i++) {
        if (!(cmd[i] >= s->m->commands[i].min && cmd[i] <= s->m->commands[i].max))
            s->violations++;
    }
    if (s->dead || s->frames == 0) {
        s->writes_withheld += s->frames == 0;
        return ROZ_OK; /* nobody listens, or nothing is sent before the first state */
    }
    /* the runtime's filter is upstream; the drivers see nothing outside the
     * manifest whoever calls write() */
    s->clamped += roz_commands_clamp(s->m, cmd, s->cmd);
    s->have_cmd = 1;
    if (s->cmd_latency > 0)
        s->have_cmd = perturb_command(s);
    return ROZ_OK;
}

/* MuJoCo's warnings by mjtWarning, for the fault's account. */
_Static_assert(mjNWARNING == 8, "MuJoCo's warnings as named below");
static const char *const warning_names[mjNWARNING] = {
    "MuJoCo warning: (near) singular inertia matrix",
    "MuJoCo warning: too many contacts",
    "MuJoCo warning: too many constraints",
    "MuJoCo warning: too many visual geoms",
    "MuJoCo warning: bad number in qpos (the simulation diverged)",
    "MuJoCo warning: bad number in qvel (the simulation diverged)",
    "MuJoCo warning: bad number in qacc (the simulation diverged)",
    "MuJoCo warning: bad number in ctrl",
};

/* After read() returned ROZ_EROBOT: MuJoCo's first warning, named, with
 * the physics step that raised it. */
static int mj_fault(void *self, roz_port_fault_t *out)
{
    roz_mujoco_t *s = self;
    if (s->engine_error[0] != '\0') {
        out->what = "physics";
        out->kind = s->engine_error;
        out->code = s->engine_step > UINT32_MAX ? UINT32_MAX : (uint32_t)s->engine_step;
        out->limit = 0;
        return ROZ_OK;
    }
    if (s->warned == 0)
        return ROZ_ENOENT;
    out->what = "physics";
    out->kind = warning_names[s->warned - 1];
    out->code = s->warned_step > UINT32_MAX ? UINT32_MAX : (uint32_t)s->warned_step;
    out->limit = 0;
    return ROZ_OK;
}

static void mj_close(void *self)
{
    close_model(self);
}

/* ---- public ------------------------------------------------------------------------ */

/* The physics has no wire: every frame read() gave is one taken. */
static int mj_link_counters(const void *self, roz_port_link_counters_t *out)
{
    const roz_mujoco_t *s = self;
    memset(out, 0, sizeof *out);
    out->accepted = s->frames;
    return ROZ_OK;
}

/* In the summary: the simulator's truth, so that standing is told from
 * fallen. Shut-down only: it formats. */
static int mj_report(const void *self, roz_port_report_when_t when, char *buf, size_t len)
{
    const roz_mujoco_t *s = self;
    roz_mujoco_base_t b;
    int n, at;

    if (when != ROZ_PORT_REPORT_SUMMARY || s->model == NULL) {
        if (len > 0)
            buf[0] = '\0';
        return 0;
    }
    roz_mujoco_base(s, &b);
    n = snprintf(buf, len,
                 "physics                %.3f s simulated in %llu steps of %g s; %llu torques "
                 "saturated at the effort limit; %llu values outside the manifest written\n",
                 b.sim_time, (unsigned long long)b.steps, s->timestep,
                 (unsigned long long)s->saturated, (unsigned long long)s->clamped);
    at = n;
    if (b.floating) {
        n = snprintf(at >= 0 && (size_t)at < len ? buf + at : NULL,
                     at >= 0 && (size_t)at < len ? len - (size_t)at : 0,
                     "base                   height %.3f m (lowest %.3f), roll %.1f, pitch "
                     "%.1f deg (largest tilt %.1f)\n",
                     b.pos[2], b.min_height, b.roll * 57.29578, b.pitch * 57.29578,
                     b.max_tilt * 57.29578);
        at += n;
    }
    n = snprintf(at >= 0 && (size_t)at < len ? buf + at : NULL,
                 at >= 0 && (size_t)at < len ? len - (size_t)at : 0,
                 "ground contacts        %u", (unsigned)b.contacts);
    at += n;
    for (uint32_t i = 0; i < b.n_bodies; i++) {
        n = snprintf(at >= 0 && (size_t)at < len ? buf + at : NULL,
                     at >= 0 && (size_t)at < len ? len - (size_t)at : 0, "%s%s",
                     i == 0 ? ": " : ", ", b.bodies[i]);
        at += n;
    }
    return at;
}

/* The recorder's /roz/truth (roz/port.h): the base as the last read() left
 * it, the contacts of the physics now (read() stepped it; write() does
 * not). Copies and one bounded loop: the tick calls it. */
static int mj_truth(const void *self, roz_port_truth_t *out)
{
    const roz_mujoco_t *s = self;
    const roz_mujoco_base_t *b = &s->base;
    if (s->data == NULL)
        return ROZ_ESTATE;
    out->floating = b->floating ? 1u : 0u;
    for (int k = 0; k < 3; k++)
        out->pos[k] = b->floating ? b->pos[k] : NAN;
    for (int k = 0; k < 4; k++)
        out->quat[k] = b->floating ? b->quat[k] : NAN;
    out->roll = b->floating ? b->roll : NAN;
    out->pitch = b->floating ? b->pitch : NAN;
    out->yaw = b->floating ? b->yaw : NAN;
    out->contacts = contact_bodies(s, out->bodies, ROZ_PORT_TRUTH_MAX_BODIES, &out->n_bodies);
    return ROZ_OK;
}

/* A body's name from the compiled model: read-only while the port is open,
 * so the recorder's drain may ask from its own thread. */
static const char *mj_truth_body(const void *self, int32_t id)
{
    const roz_mujoco_t *s = self;
    if (s->model == NULL || id < 0 || id >= s->model->nbody)
        return NULL;
    return mj_id2name(s->model, mjOBJ_BODY, id);
}

static void mj_set_origin(void *self, const char *robot_toml)
{
    roz_mujoco_set_robot_file(self, robot_toml);
}

/* The simulator extension of the port contract (roz/port.h). */
static const roz_port_sim_t mj_sim = {
    .set_origin = mj_set_origin,
    .truth = mj_truth,
    .truth_body = mj_truth_body,
};

const roz_port_ops_t roz_mujoco_ops = {
    .name = PORT,
    .open = mj_open,
    .activate = NULL,
    .read = mj_read,
    .write = mj_write,
    .deactivate = NULL,
    .close = mj_close,
    .fault = mj_fault,
    .caps = ROZ_PORT_CAP_SIMULATOR,
    .info = &roz__mj_info,
    .sim = &mj_sim,
    .link_counters = mj_link_counters,
    .report = mj_report,
};

roz_port_t roz__mujoco_port(roz_mujoco_t *self, const roz_port_layout_t *caller,
                            size_t bytes, roz_log_fn log, void *log_ctx)
{
    roz_port_t p = roz_port_make(&roz_mujoco_ops, self, caller, bytes, sizeof *self);
    if (p.self == NULL)
        return p; /* misbuilt: nothing written to *self */
    memset(self, 0, sizeof *self); /* open frees a model only if it made one */
    self->log = log;
    self->log_ctx = log_ctx;
    return p;
}

void roz_mujoco_set_robot_file(roz_mujoco_t *self, const char *robot_toml)
{
    self->robot_file = robot_toml;
}

void roz_mujoco_counters(const roz_mujoco_t *self, roz_mujoco_counters_t *out)
{
    out->writes = self->writes;
    out->writes_withheld = self->writes_withheld;
    out->frames = self->frames;
    out->frames_dropped = self->frames_dropped;
    out->clamped = self->clamped;
    out->saturated = self->saturated;
    out->violations = self->violations;
    out->warnings = self->warned != 0;
}

int roz_mujoco_inject(roz_mujoco_t *s, const roz_mujoco_fault_t *f)
{
    if (f->kind < ROZ_INJECT_DROP || f->kind >= ROZ_INJECT_KIND_END ||
        (MJ_INJECTIONS & (1u << f->kind)) == 0u)
        return ROZ_EINVAL;
    if (f->kind == ROZ_INJECT_DELAY && (f->arg < 1 || f->arg > ROZ_MUJOCO_MAX_DELAY))
        return ROZ_EINVAL;
    if (f->kind == ROZ_INJECT_PUSH &&
        (s->model == NULL || f->body <= 0 || f->body >= s->model->nbody))
        return ROZ_EINVAL;
    if (f->kind == ROZ_INJECT_GANTRY && s->gantry_eq < 0)
        return ROZ_EINVAL;
    if (s->n_faults == ROZ_MUJOCO_MAX_FAULTS) {
        uint32_t w = 0; /* forget the injections that are over */
        for (uint32_t i = 0; i < s->n_faults; i++) {
            if (s->faults[i].to == 0 || s->faults[i].to > s->tick)
                s->faults[w++] = s->faults[i];
        }
        s->n_faults = w;
        if (w == ROZ_MUJOCO_MAX_FAULTS)
            return ROZ_ENOSPC;
    }
    s->faults[s->n_faults++] = *f;
    return ROZ_OK;
}

const double *roz_mujoco_last_command(const roz_mujoco_t *s)
{
    return s->have_cmd && !s->dead ? s->cmd : NULL;
}

void roz_mujoco_base(const roz_mujoco_t *s, roz_mujoco_base_t *out)
{
    int32_t ids[ROZ_MUJOCO_MAX_CONTACT_BODIES];
    *out = s->base;
    out->contacts = contact_bodies(s, ids, ROZ_MUJOCO_MAX_CONTACT_BODIES, &out->n_bodies);
    for (uint32_t k = 0; k < out->n_bodies; k++) {
        const char *name = mj_id2name(s->model, mjOBJ_BODY, ids[k]);
        roz_format(out->bodies[k], ROZ_MUJOCO_NAME_MAX, "%s", name != NULL ? name : "?");
    }
}
