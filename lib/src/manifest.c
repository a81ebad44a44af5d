/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/manifest.h"

#include <math.h>
#include <string.h>

/* ---- private ------------------------------------------------------------- */

static const char *const interface_names[ROZ_IF_COUNT_] = {
    [ROZ_IF_POSITION] = "position",   [ROZ_IF_VELOCITY] = "velocity",
    [ROZ_IF_EFFORT] = "effort",       [ROZ_IF_STIFFNESS] = "stiffness",
    [ROZ_IF_DAMPING] = "damping",     [ROZ_IF_ACCELERATION] = "acceleration",
    [ROZ_IF_ORIENTATION] = "orientation",
};

static int find_channel(const roz_channel_t *list, uint16_t n, const char *name)
{
    if (list == NULL || name == NULL)
        return ROZ_EINVAL;
    for (uint16_t i = 0; i < n; i++) {
        if (list[i].name != NULL && strcmp(list[i].name, name) == 0)
            return (int)i;
    }
    return ROZ_ENOENT;
}

static int valid_id(const char *id)
{
    if (id == NULL || !(id[0] >= 'a' && id[0] <= 'z'))
        return 0;
    for (const char *c = id; *c != '\0'; c++) {
        if (!((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '_'))
            return 0;
    }
    return 1;
}

static int set_problem(roz_manifest_problem_t *p, roz_manifest_rule_t rule,
                       int is_state, int32_t index)
{
    if (p != NULL) {
        p->rule = rule;
        p->is_state = is_state;
        p->index = index;
    }
    return rule == ROZ_MANIFEST_RULE_OK ? ROZ_OK : ROZ_EINVAL;
}

/* Checks one channel list; the position pairing rule needs the state list. */
static int check_channels(const roz_manifest_t *m, int is_state,
                          roz_manifest_problem_t *p)
{
    const roz_channel_t *list = is_state == 2 ? m->inputs : is_state ? m->states : m->commands;
    uint16_t n = is_state == 2 ? m->n_inputs : is_state ? m->n_states : m->n_commands;

    if (n > 0 && list == NULL)
        return set_problem(p, ROZ_MANIFEST_RULE_COUNT, is_state, -1);
    if (is_state == 2 && n > 0 && m->input_rules == NULL)
        return set_problem(p, ROZ_MANIFEST_RULE_INPUT, is_state, -1);
    for (uint16_t i = 0; i < n; i++) {
        const roz_channel_t *c = &list[i];
        int32_t idx = (int32_t)i;

        if (c->name == NULL || c->name[0] == '\0' ||
            strlen(c->name) > ROZ_CFG_MAX_NAME_LEN)
            return set_problem(p, ROZ_MANIFEST_RULE_NAME, is_state, idx);
        for (uint16_t j = 0; j < i; j++) {
            if (strcmp(list[j].name, c->name) == 0)
                return set_problem(p, ROZ_MANIFEST_RULE_DUPLICATE, is_state, idx);
        }
        if ((unsigned)c->type >= (unsigned)ROZ_IF_COUNT_)
            return set_problem(p, ROZ_MANIFEST_RULE_TYPE, is_state, idx);
        /* an input: a staleness rule, nothing of the filter's, and a name
         * no state has (a policy finds its command among both by name) */
        if (is_state == 2) {
            const roz_input_rule_t *r = &m->input_rules[i];
            if (r->stale_after_ms == 0u || !(c->max_rate > 0.0) ||
                c->position_state != ROZ_CHANNEL_UNPAIRED || c->limit_margin != 0.0 ||
                c->safe_default != ROZ_SAFE_FOLLOW)
                return set_problem(p, ROZ_MANIFEST_RULE_INPUT, is_state, idx);
            for (uint16_t j = 0; j < m->n_states; j++) {
                if (strcmp(m->states[j].name, c->name) == 0)
                    return set_problem(p, ROZ_MANIFEST_RULE_INPUT, is_state, idx);
            }
            /* a source: in the vocabulary, with a usable scale, and no
             * other input's (one field, one input) */
            if (r->source != ROZ_OPERATOR_NONE || r->scale != 0.0) {
                if (roz_operator_field_device(r->source) == ROZ_OPERATOR_DEVICE_NONE ||
                    !isfinite(r->scale) || r->scale == 0.0)
                    return set_problem(p, ROZ_MANIFEST_RULE_SOURCE, is_state, idx);
                for (uint16_t j = 0; j < i; j++) {
                    if (m->input_rules[j].source == r->source)
                        return set_problem(p, ROZ_MANIFEST_RULE_SOURCE, is_state, idx);
                }
            }
        }
        if (!isfinite(c->min) || !isfinite(c->max) || !(c->min < c->max))
            return set_problem(p, ROZ_MANIFEST_RULE_LIMITS, is_state, idx);
        if (!isfinite(c->default_value) || c->default_value < c->min ||
            c->default_value > c->max)
            return set_problem(p, ROZ_MANIFEST_RULE_DEFAULT, is_state, idx);
        if (!isfinite(c->max_rate) || c->max_rate < 0.0)
            return set_problem(p, ROZ_MANIFEST_RULE_MAX_RATE, is_state, idx);
        if (c->position_state != ROZ_CHANNEL_UNPAIRED) {
            int32_t s = c->position_state;
            if (is_state || s < 0 || s >= (int32_t)m->n_states ||
                m->states[s].type != ROZ_IF_POSITION)
                return set_problem(p, ROZ_MANIFEST_RULE_PAIRING, is_state, idx);
            /* the filter stops a paired velocity or effort at a position
             * limit with 0 */
            if ((c->type == ROZ_IF_VELOCITY || c->type == ROZ_IF_EFFORT) &&
                !(c->min <= 0.0 && 0.0 <= c->max))
                return set_problem(p, ROZ_MANIFEST_RULE_PAIRING, is_state, idx);
        }
        /* 0 is the default; any other margin belongs to a position state
         * and must leave the joint room to move */
        if (c->limit_margin != 0.0 &&
            (!is_state || c->type != ROZ_IF_POSITION || !isfinite(c->limit_margin) ||
             c->limit_margin < 0.0 || !(2.0 * c->limit_margin < c->max - c->min)))
            return set_problem(p, ROZ_MANIFEST_RULE_MARGIN, is_state, idx);
        /* a hold latches a measured position: a paired position command's */
        if (c->safe_default != ROZ_SAFE_FOLLOW &&
            (c->safe_default != ROZ_SAFE_HOLD || is_state || c->type != ROZ_IF_POSITION ||
             c->position_state == ROZ_CHANNEL_UNPAIRED))
            return set_problem(p, ROZ_MANIFEST_RULE_SAFE_DEFAULT, is_state, idx);
    }
    return ROZ_OK;
}

/* The fall rule: four distinct orientation states, a tilt in (0, pi), a
 * time within ROZ_FALL_MAX_MS, and 0 within every stiffness command's
 * limits (the fallen stop sends it: roz/fall.h). */
static int check_fall(const roz_manifest_t *m, roz_manifest_problem_t *p)
{
    const roz_fall_rule_t *r = m->fall;

    for (int k = 0; k < 4; k++) {
        int32_t s = r->quaternion[k];
        if (s < 0 || s >= (int32_t)m->n_states || m->states[s].type != ROZ_IF_ORIENTATION)
            return set_problem(p, ROZ_MANIFEST_RULE_FALL, 0, -1);
        for (int j = 0; j < k; j++) {
            if (r->quaternion[j] == s)
                return set_problem(p, ROZ_MANIFEST_RULE_FALL, 0, -1);
        }
    }
    /* 3.14159265358979 < pi: a limit at pi or beyond would never trip */
    if (!(r->max_tilt > 0.0 && r->max_tilt < 3.14159265358979) || r->for_ms > ROZ_FALL_MAX_MS)
        return set_problem(p, ROZ_MANIFEST_RULE_FALL, 0, -1);
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        if (c->type == ROZ_IF_STIFFNESS && !(c->min <= 0.0 && 0.0 <= c->max))
            return set_problem(p, ROZ_MANIFEST_RULE_FALL, 0, (int32_t)i);
    }
    return ROZ_OK;
}

/* Appends the decimal digits of v to out; returns the number written. */
static size_t put_uint(char *out, unsigned v)
{
    char tmp[10];
    size_t n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    for (size_t i = 0; i < n; i++)
        out[i] = tmp[n - 1 - i];
    return n;
}

/* ---- public -------------------------------------------------------------- */

const char *roz_interface_name(roz_interface_t type)
{
    if ((unsigned)type >= (unsigned)ROZ_IF_COUNT_)
        return "?";
    return interface_names[type];
}

int roz_interface_parse(const char *name, roz_interface_t *type)
{
    if (name == NULL || type == NULL)
        return ROZ_EINVAL;
    for (int i = 0; i < (int)ROZ_IF_COUNT_; i++) {
        if (strcmp(interface_names[i], name) == 0) {
            *type = (roz_interface_t)i;
            return ROZ_OK;
        }
    }
    return ROZ_EINVAL;
}

int roz_manifest_find_command(const roz_manifest_t *m, const char *name)
{
    if (m == NULL)
        return ROZ_EINVAL;
    return find_channel(m->commands, m->n_commands, name);
}

int roz_manifest_find_state(const roz_manifest_t *m, const char *name)
{
    if (m == NULL)
        return ROZ_EINVAL;
    return find_channel(m->states, m->n_states, name);
}

double roz_manifest_limit_margin(const roz_channel_t *state)
{
    double share = ROZ_MANIFEST_MARGIN_SHARE * (state->max - state->min);

    if (state->limit_margin > 0.0)
        return state->limit_margin;
    return share < ROZ_MANIFEST_MARGIN_MAX ? share : ROZ_MANIFEST_MARGIN_MAX;
}

int roz_manifest_validate(const roz_manifest_t *m, roz_manifest_problem_t *problem)
{
    int rc;

    if (m == NULL)
        return set_problem(problem, ROZ_MANIFEST_RULE_ID, 0, -1);
    if (!valid_id(m->robot_id))
        return set_problem(problem, ROZ_MANIFEST_RULE_ID, 0, -1);
    if (m->control_rate_hz == 0)
        return set_problem(problem, ROZ_MANIFEST_RULE_RATE, 0, -1);
    if (m->n_commands == 0 || m->n_commands > ROZ_CFG_MAX_COMMANDS)
        return set_problem(problem, ROZ_MANIFEST_RULE_COUNT, 0, -1);
    if (m->n_states > ROZ_CFG_MAX_STATES)
        return set_problem(problem, ROZ_MANIFEST_RULE_COUNT, 1, -1);
    if (m->n_inputs > ROZ_CFG_MAX_INPUTS ||
        (uint32_t)m->n_states + m->n_inputs > ROZ_CFG_MAX_STATES)
        return set_problem(problem, ROZ_MANIFEST_RULE_COUNT, 2, -1);
    rc = check_channels(m, 1, problem);
    if (rc != ROZ_OK)
        return rc;
    rc = check_channels(m, 2, problem);
    if (rc != ROZ_OK)
        return rc;
    rc = check_channels(m, 0, problem);
    if (rc != ROZ_OK)
        return rc;
    if (m->fall != NULL) {
        rc = check_fall(m, problem);
        if (rc != ROZ_OK)
            return rc;
    }
    return set_problem(problem, ROZ_MANIFEST_RULE_OK, 0, -1);
}

int roz_manifest_generic_velocity(uint16_t n, double max_vel,
                                  roz_manifest_storage_t *storage)
{
    static const char prefix[] = "joint";
    static const char suffix[] = "/velocity";

    if (storage == NULL || n == 0 || n > ROZ_CFG_MAX_COMMANDS ||
        !isfinite(max_vel) || !(max_vel > 0.0))
        return ROZ_EINVAL;

    storage->arena_used = 0;
    for (uint16_t i = 0; i < n; i++) {
        /* "joint" + up to 4 digits + "/velocity" + NUL */
        size_t need = sizeof prefix - 1 + 5 + sizeof suffix;
        char *name;
        size_t len = 0;

        if (storage->arena_used + need > sizeof storage->arena)
            return ROZ_ENOSPC;
        name = &storage->arena[storage->arena_used];
        memcpy(name, prefix, sizeof prefix - 1);
        len += sizeof prefix - 1;
        len += put_uint(name + len, i);
        memcpy(name + len, suffix, sizeof suffix); /* copies the NUL */
        len += sizeof suffix;
        storage->arena_used += len;

        storage->commands[i] = (roz_channel_t){
            .name = name,
            .type = ROZ_IF_VELOCITY,
            .unit = "rad/s",
            .min = -max_vel,
            .max = max_vel,
            .default_value = 0.0,
            .max_rate = 0.0,
            .position_state = ROZ_CHANNEL_UNPAIRED,
            .limit_margin = 0.0,
        };
    }
    storage->manifest = (roz_manifest_t){
        .robot_id = "generic",
        .robot_class = "generic",
        .control_rate_hz = 100,
        .commands = storage->commands,
        .n_commands = n,
        .states = NULL,
        .n_states = 0,
        .hardware = NULL,
    };
    return ROZ_OK;
}
