/* SPDX-License-Identifier: Apache-2.0 */
#include "deploy.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#if ROZ_HAS_TOML
#include "roz/manifest_toml.h"
#include "roz/toml.h"

#define DEPLOY_MAX_BYTES (1u << 20)
static char deploy_text[DEPLOY_MAX_BYTES];
ROZ_TOML_DOC_DEFINE(deploy_doc, 1u << 14, 1u << 18);

static const char *path_; /* the file, for messages */

#define FAIL(...)                                                                              \
    do {                                                                                       \
        fprintf(stderr, "%s: ", path_);                                                        \
        fprintf(stderr, __VA_ARGS__);                                                          \
        fprintf(stderr, "\n");                                                                 \
        return -1;                                                                             \
    } while (0)

/* The command channel named @p joint + "/" + @p kind of type @p type, or -1. */
static int find_cmd(const roz_manifest_t *m, const char *joint, size_t n, const char *kind,
                    roz_interface_t type)
{
    size_t k = strlen(kind);
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const char *name = m->commands[i].name;
        if (m->commands[i].type == type && strncmp(name, joint, n) == 0 && name[n] == '/' &&
            strcmp(name + n + 1, kind) == 0 && k > 0)
            return (int)i;
    }
    return -1;
}

static int number(const roz_toml_node_t *v, double *out)
{
    if (v == NULL)
        return -1;
    if (v->type == ROZ_TOML_FLOAT)
        *out = v->as.real;
    else if (v->type == ROZ_TOML_INTEGER)
        *out = (double)v->as.integer;
    else
        return -1;
    return 0;
}

/* An input named by key @p key of [deploy.inputs] (@p t, may be NULL), or
 * -1 when absent. */
static int input_key(const roz_manifest_t *m, const roz_toml_node_t *t, const char *key,
                     int32_t *out)
{
    const roz_toml_node_t *v = t != NULL ? roz_toml_get(&deploy_doc, t, key) : NULL;
    *out = -1;
    if (v == NULL)
        return 0;
    if (v->type != ROZ_TOML_STRING)
        FAIL("deploy.inputs.%s: expected the name of an input (a string), got a %s", key,
             roz_toml_type_name((roz_toml_type_t)v->type));
    for (uint16_t k = 0; k < m->n_inputs; k++) {
        if (strlen(m->inputs[k].name) == v->as.str.len &&
            memcmp(m->inputs[k].name, v->as.str.ptr, v->as.str.len) == 0) {
            *out = (int32_t)k;
            return 0;
        }
    }
    FAIL("deploy.inputs.%s: \"%.*s\": no such input in the manifest of %s (its [[manifest.inputs]])",
         key, (int)v->as.str.len, v->as.str.ptr, m->robot_id);
}

/* The number at key @p key of [deploy] into *out (kept when absent). */
static int number_key(const roz_toml_node_t *t, const char *key, double *out)
{
    const roz_toml_node_t *v = roz_toml_get(&deploy_doc, t, key);
    if (v != NULL && number(v, out) != 0)
        FAIL("deploy.%s: expected a number, got a %s", key,
             roz_toml_type_name((roz_toml_type_t)v->type));
    return 0;
}

/* One array of the stand: @p n numbers, each into channel ch[i] within its
 * limits. */
static int stand_values(const roz_manifest_t *m, const roz_toml_node_t *stand, const char *key,
                        size_t n, const int *ch, double *out)
{
    const roz_toml_node_t *a = roz_toml_get(&deploy_doc, stand, key);
    if (a == NULL || a->type != ROZ_TOML_ARRAY)
        FAIL("deploy.stand.%s: missing, or not an array (one number a joint)", key);
    if (roz_toml_count(a) != n)
        FAIL("deploy.stand.%s: %lu values for %lu joints", key, (unsigned long)roz_toml_count(a),
             (unsigned long)n);
    for (size_t i = 0; i < n; i++) {
        const roz_channel_t *c = &m->commands[ch[i]];
        double v;
        if (number(roz_toml_at(&deploy_doc, a, i), &v) != 0)
            FAIL("deploy.stand.%s[%lu]: expected a number", key, (unsigned long)i);
        if (!isfinite(v) || v < c->min || v > c->max)
            FAIL("deploy.stand.%s[%lu]: %g: outside \"%s\"'s limits [%g, %g]", key,
                 (unsigned long)i, v, c->name, c->min, c->max);
        out[ch[i]] = v;
    }
    return 0;
}

static const char *const deploy_keys[] = { "robot", "move_s", "stop_damping", "inputs", "stand",
                                           NULL };
static const char *const input_keys[] = { "start", "run", "stand", "stop", NULL };
static const char *const stand_keys[] = { "joints", "pose", "kp", "kd", NULL };

/* Every key of table @p t is one of @p keys. */
static int known_keys(const roz_toml_node_t *t, const char *where, const char *const *keys)
{
    for (const roz_toml_node_t *k = roz_toml_first(&deploy_doc, t); k != NULL;
         k = roz_toml_next(&deploy_doc, k)) {
        int ok = 0;
        for (int i = 0; keys[i] != NULL && !ok; i++)
            ok = strlen(keys[i]) == k->key.len && memcmp(keys[i], k->key.ptr, k->key.len) == 0;
        if (!ok)
            FAIL("%s.%.*s: not a key of the deploy sequence (docs/deploy.md)", where,
                 (int)k->key.len, k->key.ptr);
    }
    return 0;
}

int rozrun_deploy_load(rozrun_deploy_t *d, const char *path, const roz_manifest_t *m)
{
    static int pos[ROZ_CFG_MAX_COMMANDS], kp[ROZ_CFG_MAX_COMMANDS], kd[ROZ_CFG_MAX_COMMANDS];
    roz_manifest_toml_problem_t problem;
    roz_toml_error_t terr;
    size_t len, n = 0;
    char err[ROZ_CFG_ERROR_LEN];

    path_ = path;
    if (roz_manifest_toml_read_file(path, deploy_text, sizeof deploy_text, &len, &problem) !=
        ROZ_OK) {
        fprintf(stderr, "%s%s\n", path, problem.text);
        return -1;
    }
    roz_toml_init(&deploy_doc, deploy_doc_nodes,
                  sizeof deploy_doc_nodes / sizeof deploy_doc_nodes[0], deploy_doc_arena,
                  sizeof deploy_doc_arena);
    if (roz_toml_parse(&deploy_doc, deploy_text, len, &terr) != ROZ_OK)
        FAIL("%lu:%lu: %s", (unsigned long)terr.line, (unsigned long)terr.column, terr.message);
    const roz_toml_node_t *t = roz_toml_get(&deploy_doc, roz_toml_root(&deploy_doc), "deploy");
    if (t == NULL || t->type != ROZ_TOML_TABLE)
        FAIL("no [deploy] table");
    if (known_keys(roz_toml_root(&deploy_doc), "", (const char *const[]){ "deploy", NULL }) != 0 ||
        known_keys(t, "deploy", deploy_keys) != 0)
        return -1;
    const roz_toml_node_t *robot = roz_toml_get(&deploy_doc, t, "robot");
    if (robot != NULL && (robot->type != ROZ_TOML_STRING ||
                          robot->as.str.len != strlen(m->robot_id) ||
                          memcmp(robot->as.str.ptr, m->robot_id, robot->as.str.len) != 0))
        FAIL("deploy.robot: written for another robot than %s", m->robot_id);
    memset(d, 0, sizeof *d);
    d->cfg.stand = d->stand;
    d->cfg.move_s = 2.0;       /* unitree_rl_gym's deploy */
    d->cfg.stop_damping = 8.0; /* Unitree's damping command */
    const roz_toml_node_t *in = roz_toml_get(&deploy_doc, t, "inputs");
    if (in != NULL && (in->type != ROZ_TOML_TABLE || known_keys(in, "deploy.inputs", input_keys)))
        FAIL("deploy.inputs: expected a table of start, run, stand, stop");
    if (number_key(t, "move_s", &d->cfg.move_s) != 0 ||
        number_key(t, "stop_damping", &d->cfg.stop_damping) != 0 ||
        input_key(m, in, "start", &d->cfg.start) != 0 || input_key(m, in, "run", &d->cfg.run) != 0 ||
        input_key(m, in, "stand", &d->cfg.stand_input) != 0 ||
        input_key(m, in, "stop", &d->cfg.stop) != 0)
        return -1;
    const roz_toml_node_t *stand = roz_toml_get(&deploy_doc, t, "stand");
    if (stand == NULL || stand->type != ROZ_TOML_TABLE)
        FAIL("no [deploy.stand] table (pose, kp, kd)");
    if (known_keys(stand, "deploy.stand", stand_keys) != 0)
        return -1;
    const roz_toml_node_t *joints = roz_toml_get(&deploy_doc, stand, "joints");
    if (joints != NULL) {
        if (joints->type != ROZ_TOML_ARRAY)
            FAIL("deploy.stand.joints: expected an array of joint names");
        if (roz_toml_count(joints) > m->n_commands)
            FAIL("deploy.stand.joints: %lu names, more than %s has commands",
                 (unsigned long)roz_toml_count(joints), m->robot_id);
        for (size_t i = 0; i < roz_toml_count(joints); i++) {
            const roz_toml_node_t *j = roz_toml_at(&deploy_doc, joints, i);
            if (j->type != ROZ_TOML_STRING)
                FAIL("deploy.stand.joints[%lu]: expected a joint name", (unsigned long)i);
            pos[n] = find_cmd(m, j->as.str.ptr, j->as.str.len, "position", ROZ_IF_POSITION);
            kp[n] = find_cmd(m, j->as.str.ptr, j->as.str.len, "stiffness", ROZ_IF_STIFFNESS);
            kd[n] = find_cmd(m, j->as.str.ptr, j->as.str.len, "damping", ROZ_IF_DAMPING);
            if (pos[n] < 0 || kp[n] < 0 || kd[n] < 0)
                FAIL("deploy.stand.joints[%lu]: \"%.*s/%s\": no such command in %s",
                     (unsigned long)i, (int)j->as.str.len, j->as.str.ptr,
                     pos[n] < 0 ? "position" : kp[n] < 0 ? "stiffness" : "damping", m->robot_id);
            n++;
        }
    } else {
        for (uint16_t i = 0; i < m->n_commands; i++) {
            const char *name = m->commands[i].name, *slash = strrchr(name, '/');
            if (m->commands[i].type != ROZ_IF_POSITION || slash == NULL)
                continue;
            pos[n] = i;
            kp[n] = find_cmd(m, name, (size_t)(slash - name), "stiffness", ROZ_IF_STIFFNESS);
            kd[n] = find_cmd(m, name, (size_t)(slash - name), "damping", ROZ_IF_DAMPING);
            if (kp[n] < 0 || kd[n] < 0)
                FAIL("deploy.stand: \"%s\" has no stiffness or damping command: name the "
                     "stand's joints (deploy.stand.joints)", name);
            n++;
        }
    }
    /* every other channel: velocity and effort 0, the rest its default */
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        double v = c->type == ROZ_IF_VELOCITY || c->type == ROZ_IF_EFFORT ? 0.0 : c->default_value;
        d->stand[i] = v < c->min ? c->min : v > c->max ? c->max : v;
    }
    if (stand_values(m, stand, "pose", n, pos, d->stand) != 0 ||
        stand_values(m, stand, "kp", n, kp, d->stand) != 0 ||
        stand_values(m, stand, "kd", n, kd, d->stand) != 0)
        return -1;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        int named = 0;
        for (size_t k = 0; k < n && !named; k++)
            named = pos[k] == (int)i;
        if (m->commands[i].type == ROZ_IF_POSITION && !named)
            FAIL("deploy.stand.joints: \"%s\" is not in the stand: the stand holds every joint",
                 m->commands[i].name);
    }
    if (roz_stages_check(m, &d->cfg, err, sizeof err) != ROZ_OK)
        FAIL("%s", err);
    return 0;
}
#else
int rozrun_deploy_load(rozrun_deploy_t *d, const char *path, const roz_manifest_t *m)
{
    (void)d;
    (void)m;
    fprintf(stderr, "rozrun: --deploy %s: this build reads no TOML (ROZ_TOML is OFF)\n", path);
    return -1;
}
#endif
