/* SPDX-License-Identifier: Apache-2.0 */
/* The CAN keys of [hardware]: parsing, checking, binding, the bus figures.
 * Their one implementation: rozgen runs them through roz_manifest_json
 * (manifests/invalid/can-*.toml hold every message). */
#include "roz/port/can_config.h"

#include <string.h>

#include "roz/hal/cmd_watchdog.h"
#include "roz/hal/params.h"
#include "roz/text.h"

/* ---- types ------------------------------------------------------------------ */

typedef struct {
    roz_can_problem_fn fn;
    void              *ctx;
    unsigned           count;
} reporter_t;

enum { K_NETWORK_INTERFACE, K_BITRATE, K_PERIOD, K_MAX_LOAD, K_REPLY_TIMEOUT, K_CMD_TIMEOUT,
       K_MASTER_ID, K_CONSISTENCY, K_MONITOR, K_DECIMATION, K_THREAD_FIRST,
       K_THREAD_LAST = K_THREAD_FIRST + 7, K_CAN_ID, K_REPLY, K_POSITION_RANGE,
       K_VELOCITY_RANGE, K_STIFFNESS_RANGE, K_DAMPING_RANGE, K_EFFORT_RANGE, K_DIRECTION,
       K_ZERO_OFFSET, N_KEYS };

static const char *const key_names[N_KEYS + 1] = {
    "network_interface", "bitrate", "command_writer_period_us", "max_bus_load_percent",
    "reply_timeout_us", ROZ_CMD_WATCHDOG_KEY, "master_id", "consistency_margin", "enable_monitor",
    "state_decimation", ROZ_THREAD_PARAM_KEYS("receive_thread"),
    ROZ_THREAD_PARAM_KEYS("command_writer"), "can_id", "reply", "position_range", "velocity_range", "stiffness_range", "damping_range",
    "effort_range", "direction", "zero_offset", NULL,
};

static const char *const rule_names[] = {
    "unknown-key", "can-param", "can-id", "can-joint", "can-channel", "can-range", "can-bus", NULL,
};

#define KNOWN_KEYS                                                                               \
    "network_interface, bitrate, command_writer_period_us, max_bus_load_percent, "               \
    "reply_timeout_us, command_timeout_us, master_id, consistency_margin, enable_monitor, "     \
    "state_decimation, receive_thread_sched, receive_thread_priority, receive_thread_cpus, "    \
    "receive_thread_stack_kib, command_writer_sched, command_writer_priority, "                \
    "command_writer_cpus, command_writer_stack_kib, can_id, "                                  \
    "reply, position_range, velocity_range, stiffness_range, damping_range, effort_range, "      \
    "direction, zero_offset"

#define DEFAULT_TIMEOUT_US 20000u

/* the five ranges, in roz_mit_ranges_t order, and the channel kinds they hold */
static const roz_interface_t range_types[5] = { ROZ_IF_POSITION, ROZ_IF_VELOCITY,
                                                ROZ_IF_STIFFNESS, ROZ_IF_DAMPING, ROZ_IF_EFFORT };

/* ---- text -------------------------------------------------------------------- */

/* rozgen.fmt.quote */
static void put_quoted(roz_text_t *t, roz_params_span_t s)
{
    roz_text_put_quoted(t, s.s, s.n);
}

static void put_interval(roz_text_t *sb, double lo, double hi)
{
    roz_text_put(sb, "[");
    roz_text_put_double(sb, lo);
    roz_text_put(sb, ", ");
    roz_text_put_double(sb, hi);
    roz_text_put(sb, "]");
}

static void report(reporter_t *r, const char *rule, roz_text_t *sb)
{
    roz_text_finish(sb);
    r->count++;
    if (r->fn != NULL)
        r->fn(r->ctx, rule, sb->buf);
}

/* ": hardware.params: KEY "ENTRY": WHAT" */
static void say_entry(reporter_t *r, const char *rule, const char *key, roz_params_span_t entry,
                      const char *what)
{
    char buf[ROZ_CFG_PROBLEM_LEN];
    roz_text_t sb;
    roz_text_init(&sb, buf, sizeof buf);
    roz_text_put(&sb, ": hardware.params: ");
    roz_text_put(&sb, key);
    roz_text_put(&sb, " ");
    put_quoted(&sb, entry);
    roz_text_put(&sb, ": ");
    roz_text_put(&sb, what);
    report(r, rule, &sb);
}

/* ---- values ------------------------------------------------------------------ */

/* The grammar of the values is the hal's (roz/hal/params.h); CAN ids and
 * every other integer may be written in hex too. */
static int parse_uint_in(roz_params_span_t s, uint32_t lo, uint32_t hi, uint32_t *out)
{
    return roz_params_parse_u32(s, ROZ_PARAMS_HEX, lo, hi, out) == ROZ_OK;
}

static int parse_number(roz_params_span_t s, double *out)
{
    return roz_params_parse_number(s, out) == ROZ_OK;
}

static int parse_range(roz_params_span_t s, roz_mit_range_t *out)
{
    roz_mit_range_t r;
    if (roz_params_parse_range(s, &r.min, &r.max) != ROZ_OK || !roz_mit_codec_range_valid(&r))
        return 0;
    *out = r;
    return 1;
}

/* ---- the parameters ------------------------------------------------------------ */

/* The parameters merged: the last occurrence of a key wins. */
typedef struct {
    const roz_param_t *a;
    size_t             na;
    const roz_param_t *b;
    size_t             nb;
} params_t;

static const roz_param_t *param_at(const params_t *p, size_t i)
{
    return i < p->na ? &p->a[i] : &p->b[i - p->na];
}

static size_t param_count(const params_t *p)
{
    return p->na + p->nb;
}

/* The effective value of @p key, or NULL. */
static const char *param_value(const params_t *p, const char *key)
{
    const char *v = NULL;
    for (size_t i = 0; i < param_count(p); i++) {
        if (strcmp(param_at(p, i)->key, key) == 0)
            v = param_at(p, i)->value;
    }
    return v;
}

static int known_key(const char *key)
{
    for (int k = 0; k < N_KEYS; k++) {
        if (strcmp(key_names[k], key) == 0)
            return k;
    }
    return -1;
}

/* ---- per-joint keys ------------------------------------------------------------ */

typedef int (*entry_fn)(roz_params_span_t v, roz_can_joint_t *j, int key);

static int entry_can_id(roz_params_span_t v, roz_can_joint_t *j, int key)
{
    uint32_t id;
    (void)key;
    if (!parse_uint_in(v, 1, 0x7FF, &id))
        return 0;
    j->can_id = (uint16_t)id;
    return 1;
}

static int entry_reply(roz_params_span_t v, roz_can_joint_t *j, int key)
{
    char name[32];
    (void)key;
    if (v.n >= sizeof name)
        return 0;
    memcpy(name, v.s, v.n);
    name[v.n] = '\0';
    return roz_mit_codec_layout_parse(name, &j->reply) == ROZ_OK;
}

static roz_mit_range_t *range_slot(roz_can_joint_t *j, int key)
{
    roz_mit_range_t *slots[5] = { &j->ranges.position, &j->ranges.velocity, &j->ranges.kp,
                                  &j->ranges.kd, &j->ranges.torque };
    return slots[key - K_POSITION_RANGE];
}

static const roz_mit_range_t *range_of(const roz_can_joint_t *j, int key)
{
    const roz_mit_range_t *slots[5] = { &j->ranges.position, &j->ranges.velocity, &j->ranges.kp,
                                        &j->ranges.kd, &j->ranges.torque };
    return slots[key - K_POSITION_RANGE];
}

static int entry_range(roz_params_span_t v, roz_can_joint_t *j, int key)
{
    roz_mit_range_t r;
    if (!parse_range(v, &r))
        return 0;
    /* a hold sends velocity, gains and torque 0: it must be a value of theirs */
    if (key != K_POSITION_RANGE && !(r.min <= 0.0 && r.max >= 0.0))
        return 0;
    *range_slot(j, key) = r;
    return 1;
}

static int entry_direction(roz_params_span_t v, roz_can_joint_t *j, int key)
{
    (void)key;
    if (roz_params_span_is(v, "1") || roz_params_span_is(v, "+1"))
        j->direction = 1;
    else if (roz_params_span_is(v, "-1"))
        j->direction = -1;
    else
        return 0;
    return 1;
}

static int entry_zero_offset(roz_params_span_t v, roz_can_joint_t *j, int key)
{
    (void)key;
    return parse_number(v, &j->zero_offset);
}

static const char *entry_expected(int key)
{
    switch (key) {
    case K_CAN_ID: return "expected an actuator's CAN id, 1..2047 (11 bits; decimal or 0x hex)";
    case K_REPLY: return "unknown reply layout (known: basic, temperature_error)";
    case K_DIRECTION: return "expected 1 or -1";
    case K_ZERO_OFFSET: return "expected a finite number (rad)";
    case K_POSITION_RANGE: return "expected MIN:MAX, two finite numbers, MIN below MAX";
    default: return "expected MIN:MAX, two finite numbers, MIN below MAX, 0 between them (a hold "
                    "sends 0)";
    }
}

static int joint_index(const roz_can_config_t *cfg, roz_params_span_t name)
{
    for (uint16_t j = 0; j < cfg->n_joints; j++) {
        if (roz_params_span_is(name, cfg->joints[j].name))
            return j;
    }
    return -1;
}

/* The entries of a per-joint key, in the order written; then the entry for
 * every joint goes to the joints without their own. Returns 1 when every
 * joint has a valid value (or the key is optional and absent). */
static int per_joint(reporter_t *r, roz_can_config_t *cfg, int key, const char *value,
                     int required, entry_fn fn)
{
    uint8_t have[ROZ_CAN_MAX_JOINTS]; /* 1 valid, 2 invalid */
    roz_can_joint_t scratch;
    int ok = 1, have_default = 0;     /* 1 valid, 2 invalid */
    roz_params_span_t all, deflt = { NULL, 0 };
    const char *name = key_names[key];
    char what[200];

    if (value == NULL) {
        if (!required)
            return 1;
        char buf[ROZ_CFG_PROBLEM_LEN];
        roz_text_t sb;
        roz_text_init(&sb, buf, sizeof buf);
        roz_text_format(&sb, ": hardware.params: %s: required key is missing", name);
        report(r, "can-param", &sb);
        return 0;
    }
    memset(have, 0, sizeof have);
    all = roz_params_span(value);
    roz_params_span_t rest = all, e;
    while (roz_params_list_next(&rest, &e)) {
        const char *eq = e.n > 0 ? memchr(e.s, '=', e.n) : NULL;
        if (e.n == 0) {
            say_entry(r, "can-param", name, all, "an entry is empty");
            ok = 0;
        } else if (eq == NULL) {
            if (have_default != 0) {
                say_entry(r, "can-param", name, e, "a second entry for every joint");
                ok = 0;
            } else if (!fn(e, &scratch, key)) {
                say_entry(r, "can-param", name, e, entry_expected(key));
                have_default = 2;
                ok = 0;
            } else {
                have_default = 1;
                deflt = e;
            }
        } else {
            roz_params_span_t jn = { e.s, (size_t)(eq - e.s) };
            roz_params_span_t v = { eq + 1, (size_t)(e.s + e.n - eq - 1) };
            int j = joint_index(cfg, roz_params_trim(jn));
            if (j < 0) {
                char q[ROZ_CFG_MAX_NAME_LEN * 2 + 8];
                roz_text_t sb;
                roz_text_init(&sb, q, sizeof q);
                put_quoted(&sb, roz_params_trim(jn));
                roz_format(what, sizeof what, "%s is not a joint of hardware.joints", q);
                say_entry(r, "can-param", name, e, what);
                ok = 0;
            } else if (have[j] != 0) {
                roz_format(what, sizeof what, "joint \"%s\" is given twice", cfg->joints[j].name);
                say_entry(r, "can-param", name, e, what);
                ok = 0;
            } else if (!fn(roz_params_trim(v), &cfg->joints[j], key)) {
                say_entry(r, "can-param", name, e, entry_expected(key));
                have[j] = 2;
                ok = 0;
            } else {
                have[j] = 1;
            }
        }
    }
    for (uint16_t j = 0; j < cfg->n_joints; j++) {
        if (have[j] != 0)
            continue;
        if (have_default == 1) {
            (void)fn(deflt, &cfg->joints[j], key);
        } else if (required && have_default == 0) {
            roz_format(what, sizeof what, "no value for joint \"%s\", and none for every joint",
                       cfg->joints[j].name);
            say_entry(r, "can-param", name, all, what);
            ok = 0;
        }
    }
    return ok;
}

static const entry_fn entry_fns[N_KEYS] = {
    [K_CAN_ID] = entry_can_id,           [K_REPLY] = entry_reply,
    [K_POSITION_RANGE] = entry_range,    [K_VELOCITY_RANGE] = entry_range,
    [K_STIFFNESS_RANGE] = entry_range,   [K_DAMPING_RANGE] = entry_range,
    [K_EFFORT_RANGE] = entry_range,      [K_DIRECTION] = entry_direction,
    [K_ZERO_OFFSET] = entry_zero_offset,
};

/* ---- global keys --------------------------------------------------------------- */

/* Returns 1 when valid (or absent: the default stays). */
static int global_key(reporter_t *r, roz_can_config_t *cfg, int key, const char *value,
                      int *timeout_given)
{
    roz_params_span_t v;
    int ok = 1, b;
    const char *what = NULL;
    char ifname[128];

    if (value == NULL)
        return 1;
    v = roz_params_span(value);
    switch (key) {
    case K_NETWORK_INTERFACE:
        ok = roz_params_ifname_valid(v, ROZ_CAN_IFNAME_MAX, ROZ_PARAMS_IFNAME_LINUX);
        if (ok) {
            memcpy(cfg->network_interface, v.s, v.n);
            cfg->network_interface[v.n] = '\0';
        }
        roz_params_ifname_expected(ifname, sizeof ifname, ROZ_CAN_IFNAME_MAX,
                                   ROZ_PARAMS_IFNAME_LINUX);
        what = ifname;
        break;
    case K_BITRATE:
        ok = parse_uint_in(v, 10000, 1000000, &cfg->bitrate);
        what = "expected an integer in 10000..1000000 (bit/s)";
        break;
    case K_PERIOD:
        ok = roz_params_span_is(v, "0") ? (cfg->command_writer_period_us = 0, 1)
                             : parse_uint_in(v, 100, 1000000, &cfg->command_writer_period_us);
        what = "expected 0 (a round per write) or an integer in 100..1000000 (us)";
        break;
    case K_MAX_LOAD:
        ok = parse_uint_in(v, 10, 100, &cfg->max_bus_load_percent);
        what = "expected an integer in 10..100 (percent)";
        break;
    case K_REPLY_TIMEOUT:
        ok = parse_uint_in(v, 1000, 10000000, &cfg->reply_timeout_us);
        *timeout_given = ok;
        what = "expected an integer in 1000..10000000 (us)";
        break;
    case K_CMD_TIMEOUT:
        ok = parse_uint_in(v, 1000, ROZ_CMD_WATCHDOG_MAX_US, &cfg->command_timeout_us);
        what = "expected an integer in 1000..60000000 (us)";
        break;
    case K_MASTER_ID:
        ok = parse_uint_in(v, 0, 0x7FF, &cfg->master_id);
        what = "expected a CAN id, 0..2047 (decimal or 0x hex)";
        break;
    case K_CONSISTENCY:
        ok = parse_number(v, &cfg->consistency_margin) && cfg->consistency_margin >= 0.0;
        what = "expected a finite number, 0 or more (rad; 0 = off)";
        break;
    case K_MONITOR:
        ok = roz_params_parse_bool(v, &b) == ROZ_OK;
        if (ok)
            cfg->enable_monitor = b;
        what = ROZ_PARAMS_EXPECTED_BOOL " (1/0, yes/no, on/off)";
        break;
    case K_DECIMATION:
        ok = roz_params_span_is(v, "1");
        what = "must be 1: the socketcan port converts every reply";
        break;
    default:
        break;
    }
    if (!ok)
        say_entry(r, "can-param", key_names[key], v, what);
    return ok;
}

/* ---- checks -------------------------------------------------------------------- */

static void say_joint(reporter_t *r, size_t index, const char *name, const char *what)
{
    char buf[ROZ_CFG_PROBLEM_LEN];
    roz_text_t sb;
    roz_text_init(&sb, buf, sizeof buf);
    roz_text_format(&sb, ": hardware: joints[%lu] ", (unsigned long)index);
    put_quoted(&sb, roz_params_span(name));
    roz_text_put(&sb, ": ");
    roz_text_put(&sb, what);
    report(r, "can-joint", &sb);
}

static int check_joints(reporter_t *r, roz_can_config_t *cfg, const roz_hardware_t *hw)
{
    int ok = 1;
    if (hw->n_joints == 0) {
        char buf[ROZ_CFG_PROBLEM_LEN];
        roz_text_t sb;
        roz_text_init(&sb, buf, sizeof buf);
        roz_text_put(&sb, ": hardware: joints: the socketcan port drives the joints listed here, "
                     "one actuator each, and none is");
        report(r, "can-joint", &sb);
        return 0;
    }
    if (hw->n_joints > ROZ_CAN_MAX_JOINTS) {
        char buf[ROZ_CFG_PROBLEM_LEN];
        roz_text_t sb;
        roz_text_init(&sb, buf, sizeof buf);
        roz_text_format(&sb, ": hardware: joints: %u joints, more than the maximum of %d "
                       "(ROZ_CFG_MAX_JOINTS)", (unsigned)hw->n_joints, (int)ROZ_CAN_MAX_JOINTS);
        report(r, "can-joint", &sb);
        return 0;
    }
    for (uint16_t j = 0; j < hw->n_joints; j++) {
        const char *n = hw->joints[j];
        roz_params_span_t sp = roz_params_span(n);
        if (strpbrk(n, ",=") != NULL || sp.n == 0 || roz_params_trim(sp).n != sp.n) {
            say_joint(r, j, n, "the socketcan port needs joint names without ',' and '=' "
                               "and without spaces around them");
            ok = 0;
        }
        cfg->joints[j].name = n;
    }
    cfg->n_joints = hw->n_joints;
    return ok;
}

static void check_ids(reporter_t *r, const roz_can_config_t *cfg)
{
    for (uint16_t j = 0; j < cfg->n_joints; j++) {
        const roz_can_joint_t *a = &cfg->joints[j];
        char buf[ROZ_CFG_PROBLEM_LEN];
        roz_text_t sb;
        roz_text_init(&sb, buf, sizeof buf);
        roz_text_format(&sb, ": hardware.params: can_id: joint \"%s\": id %u", a->name,
                  (unsigned)a->can_id);
        size_t head = sb.len;
        if (a->can_id == cfg->master_id) {
            roz_text_format(&sb, " is master_id, where replies come from");
            report(r, "can-id", &sb);
            continue;
        }
        for (uint16_t k = 0; k < j; k++) {
            const roz_can_joint_t *b = &cfg->joints[k];
            roz_text_truncate(&sb, head);
            if (b->can_id == a->can_id) {
                roz_text_format(&sb, " is also that of joint \"%s\"", b->name);
                report(r, "can-id", &sb);
                break;
            }
            if ((b->can_id & 0xFFu) == (a->can_id & 0xFFu)) {
                roz_text_format(&sb, " (0x%03X) answers with id byte 0x%02X, as joint \"%s\" "
                               "(id %u) does", (unsigned)a->can_id, (unsigned)(a->can_id & 0xFFu),
                          b->name, (unsigned)b->can_id);
                report(r, "can-id", &sb);
                break;
            }
        }
    }
}

/* The joint of a channel ("knee" of "knee/position") and whether its
 * suffix is its type's name. */
static int bind_channel(roz_can_config_t *cfg, const roz_channel_t *ch, int32_t index,
                        int is_state)
{
    const char *slash = strrchr(ch->name, '/');
    if (slash == NULL)
        return 0;
    roz_params_span_t jn = { ch->name, (size_t)(slash - ch->name) };
    int j = joint_index(cfg, jn);
    if (j < 0 || strcmp(slash + 1, roz_interface_name(ch->type)) != 0)
        return 0;
    roz_can_joint_t *jt = &cfg->joints[j];
    int32_t *slot = NULL;
    if (is_state) {
        slot = ch->type == ROZ_IF_POSITION   ? &jt->pos_state
               : ch->type == ROZ_IF_VELOCITY ? &jt->vel_state
               : ch->type == ROZ_IF_EFFORT   ? &jt->eff_state
                                             : NULL;
    } else {
        slot = ch->type == ROZ_IF_POSITION    ? &jt->pos_cmd
               : ch->type == ROZ_IF_VELOCITY  ? &jt->vel_cmd
               : ch->type == ROZ_IF_STIFFNESS ? &jt->kp_cmd
               : ch->type == ROZ_IF_DAMPING   ? &jt->kd_cmd
               : ch->type == ROZ_IF_EFFORT    ? &jt->eff_cmd
                                              : NULL;
    }
    if (slot == NULL)
        return 0;
    *slot = index;
    return 1;
}

static int check_channels(reporter_t *r, roz_can_config_t *cfg, const roz_manifest_t *m)
{
    int ok = 1;
    for (int pass = 0; pass < 2; pass++) {
        const roz_channel_t *chs = pass == 0 ? m->commands : m->states;
        uint16_t n = pass == 0 ? m->n_commands : m->n_states;
        for (uint16_t i = 0; i < n; i++) {
            if (bind_channel(cfg, &chs[i], i, pass == 1))
                continue;
            char buf[ROZ_CFG_PROBLEM_LEN];
            roz_text_t sb;
            roz_text_init(&sb, buf, sizeof buf);
            roz_text_format(&sb, ": manifest.%s[%u] ", pass == 0 ? "commands" : "states", (unsigned)i);
            put_quoted(&sb, roz_params_span(chs[i].name));
            roz_text_put(&sb, pass == 0 ? ": the socketcan port takes JOINT/position, /velocity, "
                                     "/stiffness, /damping and /effort commands, of a joint of "
                                     "hardware.joints, each of its type"
                                   : ": the socketcan port gives JOINT/position, /velocity and "
                                     "/effort states, of a joint of hardware.joints, each of its "
                                     "type");
            report(r, "can-channel", &sb);
            ok = 0;
        }
    }
    for (uint16_t j = 0; j < cfg->n_joints; j++) {
        const roz_can_joint_t *jt = &cfg->joints[j];
        if (jt->pos_state < 0 && jt->vel_state < 0 && jt->eff_state < 0 && jt->pos_cmd < 0 &&
            jt->vel_cmd < 0 && jt->kp_cmd < 0 && jt->kd_cmd < 0 && jt->eff_cmd < 0) {
            say_joint(r, j, jt->name, "no channel of the manifest is this joint's");
            ok = 0;
        }
    }
    return ok;
}

/* One channel's limits against the actuator's range, seen from the actuator. */
static void check_range(reporter_t *r, const roz_can_joint_t *jt, const roz_channel_t *ch,
                        uint16_t index, int is_state)
{
    const roz_mit_range_t *range = NULL;
    int key = 0;
    for (int k = 0; k < 5; k++) {
        if (range_types[k] == ch->type) {
            range = range_of(jt, K_POSITION_RANGE + k);
            key = K_POSITION_RANGE + k;
        }
    }
    double a = ch->min, b = ch->max;
    if (ch->type == ROZ_IF_POSITION) {
        a = (double)jt->direction * (ch->min - jt->zero_offset);
        b = (double)jt->direction * (ch->max - jt->zero_offset);
    } else if (ch->type == ROZ_IF_VELOCITY || ch->type == ROZ_IF_EFFORT) {
        a = (double)jt->direction * ch->min;
        b = (double)jt->direction * ch->max;
    }
    double lo = a < b ? a : b, hi = a < b ? b : a;
    if (lo >= range->min && hi <= range->max)
        return;
    char buf[ROZ_CFG_PROBLEM_LEN];
    roz_text_t sb;
    roz_text_init(&sb, buf, sizeof buf);
    roz_text_format(&sb, ": hardware.params: %s: joint \"%s\": the actuator's range ", key_names[key],
              jt->name);
    put_interval(&sb, range->min, range->max);
    roz_text_format(&sb, " does not hold manifest.%s[%u] ", is_state ? "states" : "commands",
              (unsigned)index);
    put_quoted(&sb, roz_params_span(ch->name));
    roz_text_put(&sb, " limits ");
    put_interval(&sb, ch->min, ch->max);
    if (lo != ch->min || hi != ch->max) {
        roz_text_put(&sb, " (the actuator sees ");
        put_interval(&sb, lo, hi);
        roz_text_put(&sb, ")");
    }
    report(r, "can-range", &sb);
}

static void check_ranges(reporter_t *r, const roz_can_config_t *cfg, const roz_manifest_t *m)
{
    for (int pass = 0; pass < 2; pass++) {
        const roz_channel_t *chs = pass == 0 ? m->commands : m->states;
        uint16_t n = pass == 0 ? m->n_commands : m->n_states;
        for (uint16_t i = 0; i < n; i++) {
            const char *slash = strrchr(chs[i].name, '/');
            roz_params_span_t jn = { chs[i].name, (size_t)(slash - chs[i].name) };
            int j = joint_index(cfg, jn);
            check_range(r, &cfg->joints[j], &chs[i], i, pass == 1);
        }
    }
}

/* The command watchdog (roz/hal/cmd_watchdog.h): at least two ticks and two
 * command intervals of a joint; by default 50 ms, or five of them when
 * longer. */
static int check_command_timeout(reporter_t *r, roz_can_config_t *cfg, const roz_manifest_t *m,
                                 const char *text)
{
    uint64_t tick_us = (1000000u + m->control_rate_hz - 1u) / m->control_rate_hz;
    uint64_t slowest = tick_us > cfg->joint_interval_us ? tick_us : cfg->joint_interval_us;
    uint64_t least = ROZ_CMD_WATCHDOG_MIN_PERIODS * slowest;
    uint64_t def = ROZ_CMD_WATCHDOG_DEFAULT_PERIODS * slowest;

    if (def < ROZ_CMD_WATCHDOG_DEFAULT_US)
        def = ROZ_CMD_WATCHDOG_DEFAULT_US;
    if (def > ROZ_CMD_WATCHDOG_MAX_US)
        def = least > ROZ_CMD_WATCHDOG_MAX_US ? least : ROZ_CMD_WATCHDOG_MAX_US;
    if (text == NULL) {
        cfg->command_timeout_us = (uint32_t)def;
        return 1;
    }
    if ((uint64_t)cfg->command_timeout_us >= least)
        return 1;
    char buf[ROZ_CFG_PROBLEM_LEN];
    roz_text_t sb;
    roz_text_init(&sb, buf, sizeof buf);
    roz_text_put(&sb, ": hardware.params: command_timeout_us ");
    put_quoted(&sb, roz_params_span(text));
    roz_text_format(&sb, ": shorter than two command intervals of a joint or two ticks (2 x %lu us)",
              (unsigned long)slowest);
    report(r, "can-bus", &sb);
    return 0;
}

/* The bus: round-robin groups, the load, the reply timeout. */
static int check_bus(reporter_t *r, roz_can_config_t *cfg, const roz_manifest_t *m,
                     int timeout_given, const char *period_text, const char *timeout_text)
{
    uint64_t round_us = cfg->command_writer_period_us != 0
                            ? cfg->command_writer_period_us
                            : 1000000u / m->control_rate_hz;
    if (round_us == 0)
        round_us = 1;
    uint64_t budget = (uint64_t)cfg->bitrate * round_us * cfg->max_bus_load_percent / 100000000u;
    uint32_t groups = 0, worst = 0;

    for (uint32_t k = 1; k <= cfg->n_joints && groups == 0; k++) {
        uint32_t busiest = 0;
        for (uint32_t g = 0; g < k; g++) {
            uint32_t bits = 0;
            for (uint32_t j = g; j < cfg->n_joints; j += k)
                bits += ROZ_CAN_FRAME_BITS(8u) +
                        ROZ_CAN_FRAME_BITS((unsigned)roz_mit_codec_reply_bytes(cfg->joints[j].reply));
            if (bits > busiest)
                busiest = bits;
        }
        worst = busiest;
        if (busiest <= budget)
            groups = k;
    }
    if (groups == 0) {
        char buf[ROZ_CFG_PROBLEM_LEN];
        roz_text_t sb;
        roz_text_init(&sb, buf, sizeof buf);
        roz_text_put(&sb, ": hardware.params: command_writer_period_us");
        if (period_text != NULL) {
            roz_text_put(&sb, " ");
            put_quoted(&sb, roz_params_span(period_text));
        }
        roz_text_format(&sb, ": a joint's command and reply take %u bits, more than %u%% of a "
                       "%lu us round at %u bit/s (%lu bits)",
                  (unsigned)worst, (unsigned)cfg->max_bus_load_percent, (unsigned long)round_us,
                  (unsigned)cfg->bitrate, (unsigned long)budget);
        report(r, "can-bus", &sb);
        return 0;
    }
    cfg->round_us = (uint32_t)round_us;
    cfg->groups = groups;
    cfg->group_bits = worst;
    cfg->bus_load = (double)worst * 1e6 / ((double)cfg->bitrate * (double)round_us);
    cfg->joint_interval_us = (uint32_t)(round_us * groups);
    if (!timeout_given) {
        uint64_t three = 3u * (uint64_t)cfg->joint_interval_us;
        cfg->reply_timeout_us = three > DEFAULT_TIMEOUT_US ? (uint32_t)three : DEFAULT_TIMEOUT_US;
    } else if ((uint64_t)cfg->reply_timeout_us < 2u * (uint64_t)cfg->joint_interval_us) {
        char buf[ROZ_CFG_PROBLEM_LEN];
        roz_text_t sb;
        roz_text_init(&sb, buf, sizeof buf);
        roz_text_put(&sb, ": hardware.params: reply_timeout_us ");
        put_quoted(&sb, roz_params_span(timeout_text));
        roz_text_format(&sb, ": shorter than two command intervals of a joint (2 x %u us)",
                  (unsigned)cfg->joint_interval_us);
        report(r, "can-bus", &sb);
        return 0;
    }
    return 1;
}

/* ---- public -------------------------------------------------------------------- */

int roz_can_config_load(roz_can_config_t *cfg, const roz_manifest_t *m, const roz_params_t *extra,
                        roz_can_problem_fn fn, void *ctx)
{
    reporter_t r = { fn, ctx, 0 };
    const roz_hardware_t *hw = m != NULL ? m->hardware : NULL;
    params_t p = { NULL, 0, NULL, 0 };
    int parsed[N_KEYS];
    int timeout_given = 0;

    memset(cfg, 0, sizeof *cfg);
    strcpy(cfg->network_interface, "can0");
    cfg->bitrate = 1000000;
    cfg->command_writer_period_us = 2000;
    cfg->max_bus_load_percent = 80;
    cfg->reply_timeout_us = DEFAULT_TIMEOUT_US;
    cfg->command_timeout_us = ROZ_CMD_WATCHDOG_DEFAULT_US;
    cfg->master_id = 0;
    cfg->consistency_margin = 0.2;
    cfg->enable_monitor = 1;
    for (size_t j = 0; j < ROZ_CAN_MAX_JOINTS; j++) {
        roz_can_joint_t *jt = &cfg->joints[j];
        jt->direction = 1;
        jt->pos_state = jt->vel_state = jt->eff_state = -1;
        jt->pos_cmd = jt->vel_cmd = jt->kp_cmd = jt->kd_cmd = jt->eff_cmd = -1;
    }
    if (hw == NULL || hw->port == NULL || strcmp(hw->port, "socketcan") != 0) {
        char buf[ROZ_CFG_PROBLEM_LEN];
        roz_text_t sb;
        roz_text_init(&sb, buf, sizeof buf);
        if (hw == NULL) {
            roz_text_put(&sb, ": hardware: the socketcan port needs the [hardware] table "
                         "(port = \"socketcan\", joints, the CAN keys in params)");
        } else {
            roz_text_put(&sb, ": hardware: port ");
            put_quoted(&sb, roz_params_span(hw->port != NULL ? hw->port : ""));
            roz_text_put(&sb, ": this robot is not one for the socketcan port");
        }
        report(&r, "can-joint", &sb);
        return ROZ_EINVAL;
    }
    p.a = hw->params;
    p.na = hw->params != NULL ? hw->n_params : 0;
    if (extra != NULL && extra->items != NULL) {
        p.b = extra->items;
        p.nb = extra->n;
    }

    int joints_ok = check_joints(&r, cfg, hw);

    /* unknown keys, each once, in order of first appearance */
    for (size_t i = 0; i < param_count(&p); i++) {
        const char *key = param_at(&p, i)->key;
        int first = 1;
        for (size_t k = 0; k < i && first; k++)
            first = strcmp(param_at(&p, k)->key, key) != 0;
        if (!first || known_key(key) >= 0)
            continue;
        char buf[ROZ_CFG_PROBLEM_LEN];
        roz_text_t sb;
        roz_text_init(&sb, buf, sizeof buf);
        roz_text_put(&sb, ": hardware.params: ");
        roz_params_span_t ks = roz_params_span(key);
        int bare = ks.n > 0;
        for (size_t c = 0; c < ks.n; c++) {
            char ch = ks.s[c];
            bare &= (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';
        }
        if (bare)
            roz_text_put(&sb, key);
        else
            put_quoted(&sb, ks);
        roz_text_put(&sb, ": unknown key of the socketcan port (known keys: " KNOWN_KEYS ")");
        report(&r, "unknown-key", &sb);
    }

    /* the known keys, in their order */
    for (int k = 0; k < N_KEYS; k++) {
        const char *value = param_value(&p, key_names[k]);
        if (entry_fns[k] == NULL)
            parsed[k] = global_key(&r, cfg, k, value, &timeout_given);
        else if (joints_ok)
            parsed[k] = per_joint(&r, cfg, k, value, k != K_DIRECTION && k != K_ZERO_OFFSET,
                                  entry_fns[k]);
        else
            parsed[k] = 0;
    }

    /* the two threads' keys (roz/hal/thread.h) */
    {
        roz_param_t tp[K_THREAD_LAST - K_THREAD_FIRST + 1];
        size_t n = 0;
        for (int k = K_THREAD_FIRST; k <= K_THREAD_LAST; k++) {
            const char *value = param_value(&p, key_names[k]);
            if (value != NULL)
                tp[n++] = (roz_param_t){ key_names[k], value };
        }
        roz_params_t tps = { tp, n };
        char terr[ROZ_CFG_PROBLEM_LEN / 2];
        if (roz_thread_params(&tps, "receive_thread", &cfg->receive_thread, terr, sizeof terr) !=
                ROZ_OK ||
            roz_thread_params(&tps, "command_writer", &cfg->writer_thread, terr, sizeof terr) !=
                ROZ_OK) {
            char buf[ROZ_CFG_PROBLEM_LEN];
            roz_text_t sb;
            roz_text_init(&sb, buf, sizeof buf);
            roz_text_put(&sb, ": hardware.params: ");
            roz_text_put(&sb, terr);
            report(&r, "can-param", &sb);
        }
    }

    if (joints_ok && parsed[K_CAN_ID] && parsed[K_MASTER_ID])
        check_ids(&r, cfg);
    int bound = joints_ok && check_channels(&r, cfg, m);
    int ranges_ok = bound;
    for (int k = K_POSITION_RANGE; k <= K_ZERO_OFFSET; k++)
        ranges_ok &= parsed[k];
    if (ranges_ok)
        check_ranges(&r, cfg, m);
    if (joints_ok && parsed[K_BITRATE] && parsed[K_PERIOD] && parsed[K_MAX_LOAD] &&
        parsed[K_REPLY_TIMEOUT] && parsed[K_REPLY] &&
        check_bus(&r, cfg, m, timeout_given, param_value(&p, key_names[K_PERIOD]),
                  param_value(&p, key_names[K_REPLY_TIMEOUT])) &&
        parsed[K_CMD_TIMEOUT])
        (void)check_command_timeout(&r, cfg, m, param_value(&p, key_names[K_CMD_TIMEOUT]));
    return r.count == 0 ? ROZ_OK : ROZ_EINVAL;
}

const char *const *roz_can_config_rules(void)
{
    return rule_names;
}

const char *const *roz_can_config_keys(void)
{
    return key_names;
}
