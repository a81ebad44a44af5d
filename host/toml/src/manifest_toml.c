/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/manifest_toml.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "roz/text.h"

/*
 * The robot.toml rules: their one implementation. rozgen runs them through
 * roz_manifest_json (tools/manifest_json), rozrun and the loader API
 * directly; the rule ids and what each refuses are listed by
 * `rozgen --list-rules` (docs/robot-toml.md).
 *
 * Each problem gets a sort key (section, channel index, rank of its key,
 * sequence), so that the problems come out in the file's schema order
 * whatever order the checks run in; only the first max_problems are kept,
 * smallest keys first. Facts about a channel (is its name valid? its
 * interface type?) are recomputed from the document where they are needed,
 * so checking needs no storage of its own. The manifest is built only when
 * nothing is wrong.
 */

/* ---- types ---------------------------------------------------------------- */

enum { SEC_TOP, SEC_MANIFEST, SEC_COMMANDS, SEC_STATES, SEC_INPUTS, SEC_FALL, SEC_HARDWARE };

/* Where problems go: section and index for ordering, text for messages. */
typedef struct place {
    uint32_t           section;
    uint32_t           index;
    const char        *where; /* "" at top level */
    const char *const *keys;  /* known keys, in reporting order */
    size_t             n_keys;
} place_t;

typedef struct checker {
    const roz_toml_doc_t        *doc;
    roz_manifest_toml_problem_t *out;
    size_t                       cap;
    size_t                       stored;
    size_t                       found;
    uint32_t                     seq;
    const roz_toml_node_t       *robot_id; /* when valid */
    roz_manifest_toml_maxima_t   max;      /* of the target build */
} checker_t;

#define ROBOT_ID_MAX 32
#define RATE_MAX 100000
#define DEFAULT_RATE 100
#define STALE_MAX_MS 3600000 /* an hour: longer is no staleness rule at all */
#define MSG_ARRAY_ITEMS 8
/* room for a constant made of the longest name a maximum allows */
#define NAME_ROOM (ROZ_MANIFEST_TOML_MAX_NAME_LEN + 2)

static const char *const top_keys[] = { "manifest", "hardware" };
static const char *const manifest_keys[] = { "robot_id", "robot_class", "control_rate_hz",
                                             "commands", "states", "inputs", "remote_estop", "fall" };
static const char *const channel_keys[] = { "name",    "interface_type",     "unit",
                                            "limits",  "default",            "max_rate_of_change",
                                            "position_state_index",          "limit_margin",
                                            "safe_default" };
/* an operator input: a channel without the filter's keys, with a staleness rule */
static const char *const input_keys[] = { "name",    "interface_type",     "unit",
                                          "limits",  "default",            "max_rate_of_change",
                                          "stale_after_ms", "source", "scale" };
static const char *const hardware_keys[] = { "port", "joints", "params" };
static const char *const fall_keys[] = { "orientation", "max_tilt_rad", "for_ms" };
/* the quaternion's states, <orientation> + these, in roz_fall_rule_t order */
static const char *const fall_axes[4] = { ".x", ".y", ".z", ".w" };

#define N_OF(a) (sizeof(a) / sizeof((a)[0]))

/* ---- private: text ------------------------------------------------------------- */

/* A TOML basic string, for messages. */
static void put_quoted(roz_text_t *sb, const char *s, size_t n)
{
    roz_text_put_quoted(sb, s, n);
}

/* A double as C writes it (roz/text.h). */
static void c_double(double x, char out[44])
{
    roz_text_t t;
    roz_text_init(&t, out, 44);
    roz_text_put_double(&t, x);
}

/* Python's isoformat() of what tomllib makes of a date/time. */
static void put_isoformat(roz_text_t *sb, const roz_toml_node_t *v)
{
    const roz_toml_datetime_t *t = &v->as.datetime;
    uint32_t micro = t->nanosecond / 1000u;
    if (v->type != ROZ_TOML_TIME_LOCAL)
        roz_text_format(sb, "%04u-%02u-%02u", (unsigned)t->year, (unsigned)t->month, (unsigned)t->day);
    if (v->type == ROZ_TOML_DATE_LOCAL)
        return;
    if (v->type != ROZ_TOML_TIME_LOCAL)
        roz_text_put(sb, "T");
    roz_text_format(sb, "%02u:%02u:%02u", (unsigned)t->hour, (unsigned)t->minute, (unsigned)t->second);
    if (micro != 0)
        roz_text_format(sb, ".%06lu", (unsigned long)micro);
    if (v->type == ROZ_TOML_DATETIME) {
        int off = t->offset_min < 0 ? -t->offset_min : t->offset_min;
        roz_text_format(sb, "%c%02d:%02d", t->offset_min < 0 ? '-' : '+', off / 60, off % 60);
    }
}

/* A value that toml_value() shows without looking inside. */
static void put_brief(roz_text_t *sb, const roz_toml_node_t *v)
{
    char num[44];
    switch (v->type) {
    case ROZ_TOML_TABLE:   roz_text_put(sb, "{...}"); break;
    case ROZ_TOML_ARRAY:   roz_text_put(sb, "[...]"); break;
    case ROZ_TOML_STRING:  put_quoted(sb, v->as.str.ptr, v->as.str.len); break;
    case ROZ_TOML_INTEGER: roz_text_format(sb, "%lld", (long long)v->as.integer); break;
    case ROZ_TOML_BOOL:    roz_text_put(sb, v->as.boolean ? "true" : "false"); break;
    case ROZ_TOML_FLOAT:
        c_double(v->as.real, num);
        roz_text_put(sb, num);
        break;
    default:               put_isoformat(sb, v); break;
    }
}

/* An array's first MSG_ARRAY_ITEMS items, each shown briefly. */
static void put_array_brief(roz_text_t *sb, const roz_toml_doc_t *d, const roz_toml_node_t *a)
{
    size_t i = 0;
    roz_text_put(sb, "[");
    for (const roz_toml_node_t *c = roz_toml_first(d, a); c != NULL; c = roz_toml_next(d, c)) {
        if (i > 0)
            roz_text_put(sb, ", ");
        if (i++ == MSG_ARRAY_ITEMS) {
            roz_text_put(sb, "...");
            break;
        }
        put_brief(sb, c);
    }
    roz_text_put(sb, "]");
}

/* A value as written, for messages; arrays show two
 * levels, deeper ones as "[...]". */
static void put_value(roz_text_t *sb, const roz_toml_doc_t *d, const roz_toml_node_t *v)
{
    size_t i = 0;
    if (v->type != ROZ_TOML_ARRAY) {
        put_brief(sb, v);
        return;
    }
    roz_text_put(sb, "[");
    for (const roz_toml_node_t *c = roz_toml_first(d, v); c != NULL; c = roz_toml_next(d, c)) {
        if (i > 0)
            roz_text_put(sb, ", ");
        if (i++ == MSG_ARRAY_ITEMS) {
            roz_text_put(sb, "...");
            break;
        }
        if (c->type == ROZ_TOML_ARRAY)
            put_array_brief(sb, d, c);
        else
            put_brief(sb, c);
    }
    roz_text_put(sb, "]");
}

/* A key bare when it can be, else quoted. */
static void put_key(roz_text_t *sb, roz_toml_string_t k)
{
    int bare = k.len > 0;
    for (uint32_t i = 0; i < k.len && bare; i++) {
        char c = k.ptr[i];
        bare = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               c == '_' || c == '-';
    }
    if (bare)
        roz_text_putn(sb, k.ptr, k.len);
    else
        put_quoted(sb, k.ptr, k.len);
}

/* ---- private: values --------------------------------------------------------------- */

static int is_type(const roz_toml_node_t *n, roz_toml_type_t t)
{
    return n != NULL && n->type == (uint8_t)t;
}

static int is_number(const roz_toml_node_t *n)
{
    return is_type(n, ROZ_TOML_INTEGER) || is_type(n, ROZ_TOML_FLOAT);
}

/* Python's float(value) of an int or float. */
static double number_of(const roz_toml_node_t *n)
{
    return n->type == ROZ_TOML_INTEGER ? (double)n->as.integer : n->as.real;
}

static int has_nul(roz_toml_string_t s)
{
    return s.len > 0 && memchr(s.ptr, '\0', s.len) != NULL;
}

static int str_eq(roz_toml_string_t s, const char *z)
{
    size_t n = strlen(z);
    return s.len == n && memcmp(s.ptr, z, n) == 0;
}

static int str_eq2(roz_toml_string_t a, roz_toml_string_t b)
{
    return a.len == b.len && (a.len == 0 || memcmp(a.ptr, b.ptr, a.len) == 0);
}

/* Index of an interface type name, or -1. */
static int interface_of(roz_toml_string_t s)
{
    for (int i = 0; i < (int)ROZ_IF_COUNT_; i++) {
        if (str_eq(s, roz_interface_name((roz_interface_t)i)))
            return i;
    }
    return -1;
}

/* The <NAME> of a channel's C constant (as rozgen.names.constant_suffix
 * makes it for the generated headers): upper case, runs of anything but letters
 * and digits made one '_', none at the ends. */
static size_t constant_suffix(roz_toml_string_t name, char *out, size_t cap)
{
    size_t n = 0;
    int gap = 0;
    for (uint32_t i = 0; i < name.len && n + 2 < cap; i++) {
        char c = name.ptr[i];
        int alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
        if (!alnum) {
            gap = 1;
            continue;
        }
        if (gap && n > 0)
            out[n++] = '_';
        gap = 0;
        out[n++] = (char)(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
    }
    out[n] = '\0';
    return n;
}

/* ---- private: problems ------------------------------------------------------------- */

static int order_less(const uint32_t a[4], const uint32_t b[4])
{
    for (int i = 0; i < 4; i++) {
        if (a[i] != b[i])
            return a[i] < b[i];
    }
    return 0;
}

/* Keeps the max_problems problems with the smallest sort keys. */
static void keep(checker_t *ck, const roz_manifest_toml_problem_t *p)
{
    ck->found++;
    if (ck->stored < ck->cap) {
        ck->out[ck->stored++] = *p;
        return;
    }
    if (ck->cap == 0)
        return;
    size_t worst = 0;
    for (size_t i = 1; i < ck->stored; i++) {
        if (order_less(ck->out[worst].order, ck->out[i].order))
            worst = i;
    }
    if (order_less(p->order, ck->out[worst].order))
        ck->out[worst] = *p;
}

static void sort_kept(checker_t *ck)
{
    for (size_t i = 1; i < ck->stored; i++) {
        roz_manifest_toml_problem_t p = ck->out[i];
        size_t j = i;
        while (j > 0 && order_less(p.order, ck->out[j - 1].order)) {
            ck->out[j] = ck->out[j - 1];
            j--;
        }
        ck->out[j] = p;
    }
}

/* "<where>: <key> <value>: <what>" under @pl; @value
 * NULL for none; the key's rank is that of @rank_key (default @key). */
static void report(checker_t *ck, const char *rule, const place_t *pl, const char *key,
                   const char *what, const roz_toml_node_t *value, const char *rank_key)
{
    roz_manifest_toml_problem_t p;
    const char *rk = rank_key != NULL ? rank_key : key;
    uint32_t rank = 0; /* unknown keys (rank -1) first */
    roz_text_t sb;

    for (size_t i = 0; i < pl->n_keys; i++) {
        if (strcmp(pl->keys[i], rk) == 0)
            rank = (uint32_t)i + 1u;
    }
    p.rule = rule;
    roz_text_init(&sb, p.text, sizeof p.text);
    roz_text_put(&sb, ": ");
    if (pl->where[0] != '\0') {
        roz_text_put(&sb, pl->where);
        roz_text_put(&sb, ": ");
    }
    roz_text_put(&sb, key);
    if (value != NULL) {
        roz_text_put(&sb, " ");
        put_value(&sb, ck->doc, value);
    }
    roz_text_put(&sb, ": ");
    roz_text_put(&sb, what);
    roz_text_finish(&sb);
    p.order[0] = pl->section;
    p.order[1] = pl->index;
    p.order[2] = rank;
    p.order[3] = ck->seq++;
    keep(ck, &p);
}

/* A problem without a place (TOML, UTF-8, I/O, storage). */
#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 3, 4)))
#endif
static void report_raw(checker_t *ck, const char *rule, const char *fmt, ...)
{
    roz_manifest_toml_problem_t p;
    va_list ap;
    p.rule = rule;
    va_start(ap, fmt);
    vsnprintf(p.text, sizeof p.text, fmt, ap);
    va_end(ap);
    memset(p.order, 0, sizeof p.order);
    p.order[3] = ck->seq++;
    keep(ck, &p);
}

static void unknown_keys(checker_t *ck, const place_t *pl, const roz_toml_node_t *table)
{
    for (const roz_toml_node_t *c = roz_toml_first(ck->doc, table); c != NULL;
         c = roz_toml_next(ck->doc, c)) {
        char key[ROZ_CFG_PROBLEM_LEN], what[ROZ_CFG_PROBLEM_LEN];
        roz_text_t kb, wb;
        int known = 0;
        for (size_t i = 0; i < pl->n_keys && !known; i++)
            known = str_eq(c->key, pl->keys[i]);
        if (known)
            continue;
        roz_text_init(&kb, key, sizeof key);
        put_key(&kb, c->key);
        roz_text_finish(&kb);
        roz_text_init(&wb, what, sizeof what);
        roz_text_put(&wb, "unknown key (known keys: ");
        for (size_t i = 0; i < pl->n_keys; i++) {
            roz_text_put(&wb, i > 0 ? ", " : "");
            roz_text_put(&wb, pl->keys[i]);
        }
        roz_text_put(&wb, ")");
        report(ck, "unknown-key", pl, key, what, NULL, "");
    }
}

static const char *expected(const roz_toml_node_t *v, const char *what, char *buf, size_t cap)
{
    snprintf(buf, cap, "expected %s%s", what, is_type(v, ROZ_TOML_BOOL) ? ", not a boolean" : "");
    return buf;
}

/* A string: 1 and *out (NULL when absent and not @required) when
 * valid, else 0 with the problem reported. */
static int check_string(checker_t *ck, const place_t *pl, const roz_toml_node_t *table,
                        const char *key, int required, const roz_toml_node_t **out)
{
    const roz_toml_node_t *v = roz_toml_get(ck->doc, table, key);
    *out = NULL;
    if (v == NULL) {
        if (required)
            report(ck, "missing-key", pl, key, "required key is missing", NULL, NULL);
        return !required;
    }
    if (v->type != ROZ_TOML_STRING) {
        report(ck, "type", pl, key, "expected a string", v, NULL);
        return 0;
    }
    if (has_nul(v->as.str)) {
        report(ck, "nul-char", pl, key, "must not contain a NUL character", v, NULL);
        return 0;
    }
    *out = v;
    return 1;
}

/* A finite number as a double. */
static int check_number(checker_t *ck, const place_t *pl, const roz_toml_node_t *table,
                        const char *key, int required, double def, double *out)
{
    const roz_toml_node_t *v = roz_toml_get(ck->doc, table, key);
    char buf[64];
    if (v == NULL) {
        if (required) {
            report(ck, "missing-key", pl, key, "required key is missing", NULL, NULL);
            return 0;
        }
        *out = def;
        return 1;
    }
    if (!is_number(v)) {
        report(ck, "type", pl, key, expected(v, "a number", buf, sizeof buf), v, NULL);
        return 0;
    }
    if (!isfinite(number_of(v))) {
        report(ck, "not-finite", pl, key, "must be finite", v, NULL);
        return 0;
    }
    *out = number_of(v);
    return 1;
}

/* An integer, quietly when @ck is NULL. */
static int check_integer(checker_t *ck, const roz_toml_doc_t *d, const place_t *pl,
                         const roz_toml_node_t *table, const char *key, int64_t def,
                         int64_t *out)
{
    const roz_toml_node_t *v = roz_toml_get(d, table, key);
    char buf[64];
    if (v == NULL) {
        *out = def;
        return 1;
    }
    if (v->type != ROZ_TOML_INTEGER) {
        if (ck != NULL)
            report(ck, "type", pl, key, expected(v, "an integer", buf, sizeof buf), v, NULL);
        return 0;
    }
    *out = v->as.integer;
    return 1;
}

/* An array whose elements should be tables; *ok and the
 * array (NULL for an absent optional one, which counts as empty). */
static const roz_toml_node_t *check_tables(checker_t *ck, const place_t *pl,
                                           const roz_toml_node_t *table, const char *key,
                                           int required, int *ok)
{
    const roz_toml_node_t *v = roz_toml_get(ck->doc, table, key);
    uint32_t i = 0;
    *ok = 0;
    if (v == NULL) {
        if (required)
            report(ck, "missing-key", pl, key, "required key is missing", NULL, NULL);
        *ok = !required;
        return NULL;
    }
    if (v->type != ROZ_TOML_ARRAY) {
        report(ck, "type", pl, key, "expected an array of tables", v, NULL);
        return NULL;
    }
    for (const roz_toml_node_t *c = roz_toml_first(ck->doc, v); c != NULL;
         c = roz_toml_next(ck->doc, c), i++) {
        if (c->type != ROZ_TOML_TABLE) {
            char k[48];
            snprintf(k, sizeof k, "%s[%lu]", key, (unsigned long)i);
            report(ck, "type", pl, k, "expected a table", c, key);
        }
    }
    *ok = 1;
    return v;
}

static void check_count(checker_t *ck, const place_t *pl, const char *key, size_t n,
                        size_t maximum, const char *option)
{
    if (n > maximum) {
        char what[128];
        snprintf(what, sizeof what, "%lu channels, more than the maximum of %lu (%s)",
                 (unsigned long)n, (unsigned long)maximum, option);
        report(ck, "too-many-channels", pl, key, what, NULL, NULL);
    }
}

/* ---- private: channels ---------------------------------------------------------------- */

/* The channel's name when valid, else NULL (reported when @pl is not
 * NULL). */
static const roz_toml_node_t *channel_name(checker_t *ck, const place_t *pl,
                                           const roz_toml_node_t *table)
{
    const roz_toml_doc_t *d = ck->doc;
    const roz_toml_node_t *v = roz_toml_get(d, table, "name");
    const char *what = NULL;
    char buf[128], suffix[NAME_ROOM];
    int printable = 1;

    if (v == NULL || v->type != ROZ_TOML_STRING || has_nul(v->as.str)) {
        if (pl != NULL) {
            const roz_toml_node_t *dummy;
            (void)check_string(ck, pl, table, "name", 1, &dummy);
        }
        return NULL;
    }
    for (uint32_t i = 0; i < v->as.str.len && printable; i++) {
        unsigned char c = (unsigned char)v->as.str.ptr[i];
        printable = c >= 0x20 && c < 0x7F && c != '"' && c != '\\';
    }
    if (v->as.str.len == 0) {
        what = "must not be empty";
    } else if (!printable) {
        what = "must be printable ASCII other than \" and \\";
    } else if (v->as.str.len > ck->max.name_len) {
        snprintf(buf, sizeof buf, "%lu bytes, more than the maximum of %lu (ROZ_CFG_MAX_NAME_LEN)",
                 (unsigned long)v->as.str.len, (unsigned long)ck->max.name_len);
        what = buf;
    } else if (constant_suffix(v->as.str, suffix, sizeof suffix) == 0) {
        what = "must have a letter or digit (it names a C constant)";
    }
    if (what != NULL) {
        if (pl != NULL)
            report(ck, "name", pl, "name", what, v, NULL);
        return NULL;
    }
    return v;
}

/* The interface type of a channel table when valid, else -1. */
static int channel_interface(const roz_toml_doc_t *d, const roz_toml_node_t *table)
{
    const roz_toml_node_t *v = roz_toml_get(d, table, "interface_type");
    if (!is_type(v, ROZ_TOML_STRING) || has_nul(v->as.str))
        return -1;
    return interface_of(v->as.str);
}

/* "manifest.commands[3]", and with the name when it is valid. */
static void channel_where(checker_t *ck, const char *kind, uint32_t index,
                          const roz_toml_node_t *table, char *buf, size_t cap)
{
    roz_text_t sb;
    const roz_toml_node_t *name = channel_name(ck, NULL, table);
    roz_text_init(&sb, buf, cap);
    roz_text_format(&sb, "manifest.%s[%lu]", kind, (unsigned long)index);
    if (name != NULL) {
        roz_text_put(&sb, " ");
        put_quoted(&sb, name->as.str.ptr, name->as.str.len);
    }
}

/* limits: 1 with [lo, hi] when valid. */
static int check_limits(checker_t *ck, const place_t *pl, const roz_toml_node_t *table,
                        double *lo, double *hi)
{
    const roz_toml_node_t *v = roz_toml_get(ck->doc, table, "limits");
    const roz_toml_node_t *a, *b;
    if (v == NULL) {
        report(ck, "missing-key", pl, "limits", "required key is missing", NULL, NULL);
        return 0;
    }
    a = roz_toml_first(ck->doc, v);
    b = a != NULL ? roz_toml_next(ck->doc, a) : NULL;
    if (v->type != ROZ_TOML_ARRAY || roz_toml_count(v) != 2 || !is_number(a) || !is_number(b)) {
        report(ck, "limits-shape", pl, "limits", "expected [min, max], two numbers", v, NULL);
        return 0;
    }
    *lo = number_of(a);
    *hi = number_of(b);
    if (!isfinite(*lo) || !isfinite(*hi)) {
        report(ck, "not-finite", pl, "limits", "must be finite", v, NULL);
        return 0;
    }
    if (!(*lo < *hi)) {
        report(ck, "limits-order", pl, "limits", "min must be below max", v, NULL);
        return 0;
    }
    return 1;
}

/* limit_margin, on a position state only, above 0 and
 * leaving the joint room to move; @lim says whether [lo, hi] is valid. */
static void check_margin(checker_t *ck, const place_t *pl, uint32_t section,
                         const roz_toml_node_t *t, int lim, double lo, double hi)
{
    const roz_toml_node_t *v = roz_toml_get(ck->doc, t, "limit_margin");
    int type = channel_interface(ck->doc, t);
    char what[ROZ_CFG_PROBLEM_LEN], a[44], b[44];
    double margin;

    if (v == NULL || !check_number(ck, pl, t, "limit_margin", 1, 0.0, &margin))
        return;
    if (section == SEC_COMMANDS || (type >= 0 && type != ROZ_IF_POSITION)) {
        report(ck, "margin-channel", pl, "limit_margin",
               "only a position state has a limit margin (the filter keeps a velocity command "
               "paired with it that far inside its limits)", v, NULL);
    } else if (!(margin > 0.0)) {
        report(ck, "margin-range", pl, "limit_margin",
               "must be above 0 (leave it out for the default)", v, NULL);
    } else if (lim && !(2.0 * margin < hi - lo)) {
        c_double(lo, a);
        c_double(hi, b);
        snprintf(what, sizeof what,
                 "leaves no room to move within limits [%s, %s]: twice the margin must be "
                 "below max - min", a, b);
        report(ck, "margin-range", pl, "limit_margin", what, v, NULL);
    }
}

/* safe_default: "follow" or "hold", and "hold" only on a
 * position command paired with a position state (@pair as written, valid
 * when @pair_ok). */
static void check_safe_default(checker_t *ck, const place_t *pl, uint32_t section,
                               const roz_toml_node_t *t, int pair_ok, int64_t pair)
{
    const roz_toml_node_t *v;
    int type = channel_interface(ck->doc, t);

    if (!check_string(ck, pl, t, "safe_default", 0, &v) || v == NULL)
        return;
    if (!str_eq(v->as.str, "follow") && !str_eq(v->as.str, "hold")) {
        report(ck, "safe-default", pl, "safe_default", "must be \"follow\" or \"hold\"", v,
               NULL);
    } else if (str_eq(v->as.str, "hold") &&
               (section == SEC_STATES || (type >= 0 && type != ROZ_IF_POSITION) ||
                (pair_ok && pair == ROZ_CHANNEL_UNPAIRED))) {
        report(ck, "safe-default", pl, "safe_default",
               "only a position command paired with a position state can hold (the setpoint a "
               "stop latched)", v, NULL);
    }
}

/* An input's source: a field of an operator device (roz/operator.h), and a
 * scale only beside one, finite and not 0. */
static void check_source(checker_t *ck, const place_t *pl, const roz_toml_node_t *t)
{
    const roz_toml_node_t *s, *v = roz_toml_get(ck->doc, t, "scale");
    roz_operator_field_t f;
    double scale;
    int has_source = check_string(ck, pl, t, "source", 0, &s) && s != NULL;

    if (has_source && roz_operator_field_parse(s->as.str.ptr, s->as.str.len, &f) != ROZ_OK) {
        report(ck, "input-source", pl, "source",
               "unknown source (known: remote.lx, remote.ly, remote.rx, remote.ry, remote.l2, "
               "remote.r2, remote.btn.<r1|l1|start|select|r2|l2|f1|f2|a|b|x|y|up|right|down|"
               "left>, twist.linear.<x|y|z>, twist.angular.<x|y|z>)", s, NULL);
    }
    if (v == NULL || !check_number(ck, pl, t, "scale", 0, 1.0, &scale))
        return;
    if (roz_toml_get(ck->doc, t, "source") == NULL)
        report(ck, "input-scale", pl, "scale",
               "only an input with a source has a scale (the value is scale times the field)",
               v, NULL);
    else if (scale == 0.0)
        report(ck, "input-scale", pl, "scale",
               "must not be 0 (the value is scale times the field)", v, NULL);
}

static void check_channel(checker_t *ck, uint32_t section, const char *kind, uint32_t index,
                          const roz_toml_node_t *t)
{
    const roz_toml_doc_t *d = ck->doc;
    char bare[48], where[ROZ_CFG_PROBLEM_LEN], what[ROZ_CFG_PROBLEM_LEN];
    place_t pl = { section, index, bare, channel_keys, N_OF(channel_keys) };
    const roz_toml_node_t *s;
    double lo = 0, hi = 0, def, rate;

    if (section == SEC_INPUTS) {
        pl.keys = input_keys;
        pl.n_keys = N_OF(input_keys);
    }
    int64_t pair;
    int lim;

    snprintf(bare, sizeof bare, "manifest.%s[%lu]", kind, (unsigned long)index);
    (void)channel_name(ck, &pl, t);
    channel_where(ck, kind, index, t, where, sizeof where);
    pl.where = where;
    unknown_keys(ck, &pl, t);

    if (check_string(ck, &pl, t, "interface_type", 1, &s) && interface_of(s->as.str) < 0) {
        roz_text_t sb;
        roz_text_init(&sb, what, sizeof what);
        roz_text_put(&sb, "unknown type (known types: ");
        for (int i = 0; i < (int)ROZ_IF_COUNT_; i++) {
            roz_text_put(&sb, i > 0 ? ", " : "");
            roz_text_put(&sb, roz_interface_name((roz_interface_t)i));
        }
        roz_text_put(&sb, ")");
        report(ck, "interface-type", &pl, "interface_type", what, s, NULL);
    }
    (void)check_string(ck, &pl, t, "unit", 1, &s);
    lim = check_limits(ck, &pl, t, &lo, &hi);
    if (check_number(ck, &pl, t, "default", 1, 0.0, &def) && lim && !(lo <= def && def <= hi)) {
        char a[44], b[44];
        c_double(lo, a);
        c_double(hi, b);
        snprintf(what, sizeof what, "must be within limits [%s, %s]", a, b);
        report(ck, "default-range", &pl, "default", what, roz_toml_get(d, t, "default"), NULL);
    }
    if (check_number(ck, &pl, t, "max_rate_of_change", 0, 0.0, &rate) && rate < 0)
        report(ck, "max-rate", &pl, "max_rate_of_change", "must not be negative",
               roz_toml_get(d, t, "max_rate_of_change"), NULL);
    if (section == SEC_INPUTS) {
        const roz_toml_node_t *v = roz_toml_get(d, t, "max_rate_of_change");
        int64_t ms;
        /* a stale input returns to its default at this rate: never a jump */
        if (v == NULL)
            report(ck, "missing-key", &pl, "max_rate_of_change",
                   "required on an input (a stale input returns to its default at this rate, "
                   "never a jump)", NULL, NULL);
        else if (is_number(v) && isfinite(number_of(v)) && number_of(v) == 0.0)
            report(ck, "input-rate", &pl, "max_rate_of_change",
                   "must be above 0 on an input (a stale input returns to its default at this "
                   "rate, never a jump)", v, NULL);
        v = roz_toml_get(d, t, "stale_after_ms");
        if (v == NULL) {
            report(ck, "missing-key", &pl, "stale_after_ms", "required key is missing", NULL,
                   NULL);
        } else if (check_integer(ck, d, &pl, t, "stale_after_ms", 0, &ms) &&
                   !(ms >= 1 && ms <= STALE_MAX_MS)) {
            snprintf(what, sizeof what,
                     "must be in 1..%d (milliseconds without an update before the input "
                     "returns to its default)", STALE_MAX_MS);
            report(ck, "stale-after", &pl, "stale_after_ms", what, v, NULL);
        }
        check_source(ck, &pl, t);
        return; /* the filter's keys are not an input's (unknown-key) */
    }
    int pair_ok = check_integer(ck, d, &pl, t, "position_state_index", ROZ_CHANNEL_UNPAIRED,
                                &pair);
    if (pair_ok && section == SEC_STATES && pair != ROZ_CHANNEL_UNPAIRED)
        report(ck, "pairing-on-state", &pl, "position_state_index",
               "only commands are paired with a position state; must be -1 or left out",
               roz_toml_get(d, t, "position_state_index"), NULL);
    check_margin(ck, &pl, section, t, lim, lo, hi);
    check_safe_default(ck, &pl, section, t, pair_ok, pair);
}

/* Names, and the C constants made of them, once
 * per list, among its first @max channels (a longer list is refused as too
 * long, and comparing every pair of it would take quadratic time). */
static void unique_names(checker_t *ck, uint32_t section, const char *kind,
                         const roz_toml_node_t *list, uint32_t max)
{
    const roz_toml_doc_t *d = ck->doc;
    const char *tag = section == SEC_COMMANDS ? "_CMD_" : section == SEC_INPUTS ? "_INPUT_"
                                                                               : "_STATE_";
    uint32_t i = 0;

    for (const roz_toml_node_t *t = roz_toml_first(d, list); t != NULL && i < max;
         t = roz_toml_next(d, t), i++) {
        const roz_toml_node_t *name = t->type == ROZ_TOML_TABLE ? channel_name(ck, NULL, t)
                                                                : NULL;
        char bare[48], what[ROZ_CFG_PROBLEM_LEN];
        char mine[NAME_ROOM], theirs[NAME_ROOM];
        place_t pl = { section, i, bare, section == SEC_INPUTS ? input_keys : channel_keys,
                       section == SEC_INPUTS ? N_OF(input_keys) : N_OF(channel_keys) };
        uint32_t j = 0;
        const roz_toml_node_t *u, *dup = NULL, *clash = NULL;
        uint32_t dup_j = 0, clash_j = 0;

        if (name == NULL)
            continue;
        snprintf(bare, sizeof bare, "manifest.%s[%lu]", kind, (unsigned long)i);
        constant_suffix(name->as.str, mine, sizeof mine);
        for (u = roz_toml_first(d, list); u != t; u = roz_toml_next(d, u), j++) {
            const roz_toml_node_t *other = u->type == ROZ_TOML_TABLE
                                               ? channel_name(ck, NULL, u) : NULL;
            if (other == NULL)
                continue;
            if (dup == NULL && str_eq2(other->as.str, name->as.str)) {
                dup = u;
                dup_j = j;
            }
            if (clash == NULL) {
                constant_suffix(other->as.str, theirs, sizeof theirs);
                if (strcmp(mine, theirs) == 0) {
                    clash = u;
                    clash_j = j;
                }
            }
        }
        if (dup != NULL) {
            snprintf(what, sizeof what, "duplicate of manifest.%s[%lu]", kind,
                     (unsigned long)dup_j);
            report(ck, "duplicate-name", &pl, "name", what, name, NULL);
        } else if (clash != NULL) {
            char other_where[ROZ_CFG_PROBLEM_LEN];
            roz_text_t sb;
            channel_where(ck, kind, clash_j, clash, other_where, sizeof other_where);
            roz_text_init(&sb, what, sizeof what);
            roz_text_put(&sb, "C constant ROZ_");
            if (ck->robot_id != NULL) {
                for (uint32_t k = 0; k < ck->robot_id->as.str.len; k++) {
                    char c = ck->robot_id->as.str.ptr[k];
                    char up = (char)(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
                    roz_text_putn(&sb, &up, 1);
                }
            } else {
                roz_text_put(&sb, "<ID>");
            }
            roz_text_put(&sb, tag);
            roz_text_put(&sb, mine);
            roz_text_put(&sb, " is also that of ");
            roz_text_put(&sb, other_where);
            roz_text_finish(&sb);
            report(ck, "constant-collision", &pl, "name", what, name, NULL);
        }
    }
}

static void check_channels(checker_t *ck, uint32_t section, const char *kind,
                           const roz_toml_node_t *list)
{
    uint32_t i = 0;
    if (list == NULL)
        return;
    for (const roz_toml_node_t *t = roz_toml_first(ck->doc, list); t != NULL;
         t = roz_toml_next(ck->doc, t), i++) {
        if (t->type == ROZ_TOML_TABLE)
            check_channel(ck, section, kind, i, t);
    }
    unique_names(ck, section, kind, list,
                 section == SEC_COMMANDS ? ck->max.commands : ck->max.states);
}

/* An input is read as a state: no state may have its name (a policy finds
 * its command among both by name). */
static void input_names(checker_t *ck, const roz_toml_node_t *inputs,
                        const roz_toml_node_t *states)
{
    const roz_toml_doc_t *d = ck->doc;
    uint32_t i = 0;

    for (const roz_toml_node_t *t = roz_toml_first(d, inputs); t != NULL && i < ck->max.states;
         t = roz_toml_next(d, t), i++) {
        const roz_toml_node_t *name = t->type == ROZ_TOML_TABLE ? channel_name(ck, NULL, t)
                                                                : NULL;
        uint32_t j = 0;
        if (name == NULL)
            continue;
        for (const roz_toml_node_t *u = roz_toml_first(d, states);
             u != NULL && j < ck->max.states; u = roz_toml_next(d, u), j++) {
            const roz_toml_node_t *other = u->type == ROZ_TOML_TABLE
                                               ? channel_name(ck, NULL, u) : NULL;
            if (other != NULL && str_eq2(other->as.str, name->as.str)) {
                char bare[48], what[64];
                place_t pl = { SEC_INPUTS, i, bare, input_keys, N_OF(input_keys) };
                snprintf(bare, sizeof bare, "manifest.inputs[%lu]", (unsigned long)i);
                snprintf(what, sizeof what, "also the name of manifest.states[%lu]",
                         (unsigned long)j);
                report(ck, "duplicate-name", &pl, "name", what, name, NULL);
                break;
            }
        }
    }
}

/* One device field feeds one input: two inputs on one stick are a slip of
 * the pen far more often than a need (a controller that wants the value
 * twice reads the one input twice). */
static void input_sources(checker_t *ck, const roz_toml_node_t *inputs)
{
    const roz_toml_doc_t *d = ck->doc;
    uint32_t i = 0;

    for (const roz_toml_node_t *t = roz_toml_first(d, inputs); t != NULL && i < ck->max.states;
         t = roz_toml_next(d, t), i++) {
        const roz_toml_node_t *src = t->type == ROZ_TOML_TABLE ? roz_toml_get(d, t, "source")
                                                               : NULL;
        uint32_t j = 0;
        if (!is_type(src, ROZ_TOML_STRING))
            continue;
        for (const roz_toml_node_t *u = roz_toml_first(d, inputs); u != t && j < i;
             u = roz_toml_next(d, u), j++) {
            const roz_toml_node_t *other = u->type == ROZ_TOML_TABLE
                                               ? roz_toml_get(d, u, "source") : NULL;
            if (is_type(other, ROZ_TOML_STRING) && str_eq2(other->as.str, src->as.str)) {
                char where[ROZ_CFG_PROBLEM_LEN], what[96];
                place_t pl = { SEC_INPUTS, i, where, input_keys, N_OF(input_keys) };
                channel_where(ck, "inputs", i, t, where, sizeof where);
                snprintf(what, sizeof what,
                         "also the source of manifest.inputs[%lu] (one field feeds one input)",
                         (unsigned long)j);
                report(ck, "duplicate-source", &pl, "source", what, src, NULL);
                break;
            }
        }
    }
}

/* Each paired command points at a position state. */
static void check_pairing(checker_t *ck, const roz_toml_node_t *commands,
                          const roz_toml_node_t *states)
{
    const roz_toml_doc_t *d = ck->doc;
    size_t n_states = roz_toml_count(states);
    uint32_t i = 0;

    for (const roz_toml_node_t *t = roz_toml_first(d, commands); t != NULL;
         t = roz_toml_next(d, t), i++) {
        char where[ROZ_CFG_PROBLEM_LEN], what[ROZ_CFG_PROBLEM_LEN];
        place_t pl = { SEC_COMMANDS, i, where, channel_keys, N_OF(channel_keys) };
        const roz_toml_node_t *value, *target;
        int64_t pair;
        int type;

        if (t->type != ROZ_TOML_TABLE ||
            !check_integer(NULL, d, &pl, t, "position_state_index", ROZ_CHANNEL_UNPAIRED,
                           &pair) ||
            pair == ROZ_CHANNEL_UNPAIRED)
            continue;
        channel_where(ck, "commands", i, t, where, sizeof where);
        value = roz_toml_get(d, t, "position_state_index");
        if (pair < 0 || (uint64_t)pair >= n_states) {
            if (n_states == 0)
                snprintf(what, sizeof what, "must be -1 (unpaired): there are no states");
            else if (n_states == 1)
                snprintf(what, sizeof what, "must be -1 (unpaired) or 0, the only state");
            else
                snprintf(what, sizeof what, "must be -1 (unpaired) or a state index 0..%lu",
                         (unsigned long)n_states - 1u);
            report(ck, "pairing-range", &pl, "position_state_index", what, value, NULL);
            continue;
        }
        target = roz_toml_at(d, states, (size_t)pair);
        if (target->type != ROZ_TOML_TABLE)
            continue;
        type = channel_interface(d, target);
        if (type == ROZ_IF_POSITION) {
            /* pairing-zero: the filter stops a paired velocity
             * or effort command at a position limit by commanding 0, so 0
             * must be a value it may send. Limits that fail their own
             * checks are reported where they are. */
            const roz_toml_node_t *lim = roz_toml_get(d, t, "limits");
            const roz_toml_node_t *a = lim != NULL ? roz_toml_first(d, lim) : NULL;
            const roz_toml_node_t *b = a != NULL ? roz_toml_next(d, a) : NULL;
            int ctype = channel_interface(d, t);
            if ((ctype == ROZ_IF_VELOCITY || ctype == ROZ_IF_EFFORT) && lim != NULL &&
                lim->type == ROZ_TOML_ARRAY &&
                roz_toml_count(lim) == 2 && is_number(a) && is_number(b)) {
                double lo = number_of(a), hi = number_of(b);
                if (isfinite(lo) && isfinite(hi) && lo < hi && !(lo <= 0.0 && 0.0 <= hi)) {
                    char sa[44], sb_[44];
                    c_double(lo, sa);
                    c_double(hi, sb_);
                    snprintf(what, sizeof what,
                             "a paired %s command must have 0 within its limits "
                             "[%s, %s], to stop at a position limit",
                             ctype == ROZ_IF_EFFORT ? "effort" : "velocity", sa, sb_);
                    report(ck, "pairing-zero", &pl, "position_state_index", what, value, NULL);
                }
            }
            continue;
        }
        if (type < 0)
            continue; /* a broken target is reported where it is */
        {
            char target_where[ROZ_CFG_PROBLEM_LEN];
            roz_text_t sb;
            channel_where(ck, "states", (uint32_t)pair, target, target_where,
                          sizeof target_where);
            roz_text_init(&sb, what, sizeof what);
            roz_text_put(&sb, target_where);
            roz_text_format(&sb, " is a %s state, not a position state",
                      roz_interface_name((roz_interface_t)type));
            roz_text_finish(&sb);
        }
        report(ck, "pairing-type", &pl, "position_state_index", what, value, NULL);
    }
}

/* ---- private: the fall rule ------------------------------------------------------------ */

/* The index of the state called @p prefix + @p axis among @p states, or -1
 * (and *where names nothing). */
static int64_t fall_state(checker_t *ck, const roz_toml_node_t *states, roz_toml_string_t prefix,
                          const char *axis, const roz_toml_node_t **table)
{
    const roz_toml_doc_t *d = ck->doc;
    size_t n = strlen(axis);
    int64_t i = 0;

    *table = NULL;
    for (const roz_toml_node_t *t = roz_toml_first(d, states); t != NULL;
         t = roz_toml_next(d, t), i++) {
        const roz_toml_node_t *name = t->type == ROZ_TOML_TABLE ? channel_name(ck, NULL, t) : NULL;
        if (name != NULL && name->as.str.len == prefix.len + n &&
            memcmp(name->as.str.ptr, prefix.ptr, prefix.len) == 0 &&
            memcmp(name->as.str.ptr + prefix.len, axis, n) == 0) {
            *table = t;
            return i;
        }
    }
    return -1;
}

/* [manifest.fall]: the base's quaternion among the states, the angle, the
 * time; and 0 within every stiffness command's limits, which the fallen
 * stop sends (roz/fall.h). */
static void check_fall(checker_t *ck, const roz_toml_node_t *fall, const roz_toml_node_t *states,
                       const roz_toml_node_t *commands)
{
    const roz_toml_doc_t *d = ck->doc;
    place_t pl = { SEC_FALL, 0, "manifest.fall", fall_keys, N_OF(fall_keys) };
    const roz_toml_node_t *o;
    char what[ROZ_CFG_PROBLEM_LEN];
    double tilt;
    int64_t ms;

    unknown_keys(ck, &pl, fall);
    if (check_string(ck, &pl, fall, "orientation", 1, &o)) {
        for (int k = 0; k < 4; k++) {
            const roz_toml_node_t *t;
            int64_t s = fall_state(ck, states, o->as.str, fall_axes[k], &t);
            int type = t != NULL ? channel_interface(d, t) : -1;
            roz_text_t sb;
            roz_text_init(&sb, what, sizeof what);
            if (s < 0) {
                roz_text_put(&sb, "no state \"");
                roz_text_putn(&sb, o->as.str.ptr, o->as.str.len);
                roz_text_put(&sb, fall_axes[k]);
                roz_text_put(&sb, "\" (the rule reads the base's orientation quaternion from the "
                                  "orientation states <orientation>.x, .y, .z and .w)");
            } else if (type >= 0 && type != ROZ_IF_ORIENTATION) {
                char where[ROZ_CFG_PROBLEM_LEN];
                channel_where(ck, "states", (uint32_t)s, t, where, sizeof where);
                roz_text_put(&sb, where);
                roz_text_format(&sb, " is of type %s, not orientation",
                                roz_interface_name((roz_interface_t)type));
            } else {
                continue;
            }
            roz_text_finish(&sb);
            report(ck, "fall-orientation", &pl, "orientation", what, o, NULL);
            break;
        }
    }
    if (check_number(ck, &pl, fall, "max_tilt_rad", 1, 0.0, &tilt) &&
        !(tilt > 0.0 && tilt < 3.14159265358979))
        report(ck, "fall-tilt", &pl, "max_tilt_rad",
               "must be above 0 and below pi (the angle, in rad, between the base's z axis and "
               "the vertical beyond which the robot is down)",
               roz_toml_get(d, fall, "max_tilt_rad"), NULL);
    if (roz_toml_get(d, fall, "for_ms") == NULL) {
        report(ck, "missing-key", &pl, "for_ms", "required key is missing", NULL, NULL);
    } else if (check_integer(ck, d, &pl, fall, "for_ms", 0, &ms) &&
               !(ms >= 0 && ms <= (int64_t)ROZ_FALL_MAX_MS)) {
        snprintf(what, sizeof what,
                 "must be in 0..%u (milliseconds the tilt must last; 0: one tick)",
                 (unsigned)ROZ_FALL_MAX_MS);
        report(ck, "fall-time", &pl, "for_ms", what, roz_toml_get(d, fall, "for_ms"), NULL);
    }
    /* the fallen stop sends stiffness 0: it must be a value the channel takes */
    uint32_t i = 0;
    for (const roz_toml_node_t *t = roz_toml_first(d, commands); t != NULL;
         t = roz_toml_next(d, t), i++) {
        const roz_toml_node_t *lim = t->type == ROZ_TOML_TABLE ? roz_toml_get(d, t, "limits")
                                                               : NULL;
        const roz_toml_node_t *a = lim != NULL ? roz_toml_first(d, lim) : NULL;
        const roz_toml_node_t *b = a != NULL ? roz_toml_next(d, a) : NULL;
        char where[ROZ_CFG_PROBLEM_LEN];
        place_t cpl = { SEC_COMMANDS, i, where, channel_keys, N_OF(channel_keys) };
        if (lim == NULL || channel_interface(d, t) != ROZ_IF_STIFFNESS ||
            lim->type != ROZ_TOML_ARRAY || roz_toml_count(lim) != 2 || !is_number(a) ||
            !is_number(b))
            continue;
        double lo = number_of(a), hi = number_of(b);
        if (isfinite(lo) && isfinite(hi) && lo < hi && !(lo <= 0.0 && 0.0 <= hi)) {
            channel_where(ck, "commands", i, t, where, sizeof where);
            report(ck, "fall-stiffness", &cpl, "limits",
                   "must include 0 when the manifest has a fall rule (manifest.fall): the "
                   "fallen stop sends zero stiffness", lim, NULL);
        }
    }
}

/* ---- private: document ---------------------------------------------------------------- */

static int robot_id_ok(roz_toml_string_t s)
{
    if (s.len == 0 || !(s.ptr[0] >= 'a' && s.ptr[0] <= 'z'))
        return 0;
    for (uint32_t i = 0; i < s.len; i++) {
        char c = s.ptr[i];
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'))
            return 0;
    }
    return 1;
}

#define BUTTONS "remote.btn.<r1|l1|start|select|r2|l2|f1|f2|a|b|x|y|up|right|down|left>"

/* remote_estop: an array of the remote's buttons, each once, at least one;
 * the mask of their bits (ROZ_REMOTE_KEY), or 0 after a problem (reported
 * when @p ck is not NULL). */
static uint16_t remote_estop(checker_t *ck, const roz_toml_doc_t *d, const place_t *pl,
                             const roz_toml_node_t *v)
{
    uint16_t mask = 0;
    int bad = 0;
    uint32_t i = 0;

    if (v->type != ROZ_TOML_ARRAY) {
        if (ck != NULL)
            report(ck, "type", pl, "remote_estop", "expected an array of strings", v, NULL);
        return 0;
    }
    if (roz_toml_count(v) == 0) {
        if (ck != NULL)
            report(ck, "remote-estop", pl, "remote_estop",
                   "at least one button (" BUTTONS "): an empty chord is no e-stop", v, NULL);
        return 0;
    }
    for (const roz_toml_node_t *b = roz_toml_first(d, v); b != NULL; b = roz_toml_next(d, b), i++) {
        char key[40];
        roz_operator_field_t f;
        const char *what = NULL;
        snprintf(key, sizeof key, "remote_estop[%lu]", (unsigned long)i);
        if (b->type != ROZ_TOML_STRING || has_nul(b->as.str)) {
            what = "expected the name of a button (" BUTTONS ")";
        } else if (roz_operator_field_parse(b->as.str.ptr, b->as.str.len, &f) != ROZ_OK ||
                   f < ROZ_OPERATOR_REMOTE_BTN_R1 || f > ROZ_OPERATOR_REMOTE_BTN_LEFT) {
            what = "not a button of the remote (" BUTTONS ")";
        } else if ((mask & ROZ_REMOTE_KEY(f)) != 0u) {
            what = "listed twice";
        } else {
            mask = (uint16_t)(mask | ROZ_REMOTE_KEY(f));
        }
        if (what != NULL) {
            bad = 1;
            if (ck != NULL)
                report(ck, b->type == ROZ_TOML_STRING ? "remote-estop" : "type", pl, key, what,
                       b, "remote_estop");
        }
    }
    return bad ? 0u : mask;
}

static void check_manifest(checker_t *ck, const roz_toml_node_t *t)
{
    place_t pl = { SEC_MANIFEST, 0, "manifest", manifest_keys, N_OF(manifest_keys) };
    const roz_toml_node_t *id, *cls, *commands, *states, *inputs;
    int64_t rate;
    int commands_ok, states_ok, inputs_ok;
    char what[128];

    unknown_keys(ck, &pl, t);
    if (check_string(ck, &pl, t, "robot_id", 1, &id)) {
        if (!robot_id_ok(id->as.str)) {
            report(ck, "robot-id", &pl, "robot_id",
                   "must match [a-z][a-z0-9_]* (it names C symbols and files)", id, NULL);
        } else if (id->as.str.len > ROBOT_ID_MAX) {
            snprintf(what, sizeof what, "%lu characters, more than the maximum of %d",
                     (unsigned long)id->as.str.len, ROBOT_ID_MAX);
            report(ck, "robot-id", &pl, "robot_id", what, id, NULL);
        } else {
            ck->robot_id = id;
        }
    }
    (void)check_string(ck, &pl, t, "robot_class", 0, &cls);
    if (check_integer(ck, ck->doc, &pl, t, "control_rate_hz", DEFAULT_RATE, &rate) &&
        !(rate >= 1 && rate <= RATE_MAX)) {
        snprintf(what, sizeof what, "must be in 1..%d", RATE_MAX);
        report(ck, "control-rate", &pl, "control_rate_hz", what,
               roz_toml_get(ck->doc, t, "control_rate_hz"), NULL);
    }
    commands = check_tables(ck, &pl, t, "commands", 1, &commands_ok);
    states = check_tables(ck, &pl, t, "states", 0, &states_ok);
    inputs = check_tables(ck, &pl, t, "inputs", 0, &inputs_ok);
    if (commands_ok) {
        if (roz_toml_count(commands) == 0)
            report(ck, "no-commands", &pl, "commands", "at least one command is required", NULL,
                   NULL);
        check_count(ck, &pl, "commands", roz_toml_count(commands), ck->max.commands,
                    "ROZ_CFG_MAX_COMMANDS");
    }
    if (states_ok)
        check_count(ck, &pl, "states", roz_toml_count(states), ck->max.states,
                    "ROZ_CFG_MAX_STATES");
    if (inputs_ok && states_ok && roz_toml_count(inputs) > 0 &&
        roz_toml_count(states) <= ck->max.states)
        check_count(ck, &pl, "inputs", roz_toml_count(states) + roz_toml_count(inputs),
                    ck->max.states, "ROZ_CFG_MAX_STATES, shared by states and inputs");
    check_channels(ck, SEC_STATES, "states", states_ok ? states : NULL);
    check_channels(ck, SEC_INPUTS, "inputs", inputs_ok ? inputs : NULL);
    check_channels(ck, SEC_COMMANDS, "commands", commands_ok ? commands : NULL);
    if (states_ok && commands_ok)
        check_pairing(ck, commands, states);
    if (states_ok && inputs_ok && inputs != NULL && states != NULL)
        input_names(ck, inputs, states);
    if (inputs_ok && inputs != NULL)
        input_sources(ck, inputs);
    if (roz_toml_get(ck->doc, t, "remote_estop") != NULL)
        (void)remote_estop(ck, ck->doc, &pl, roz_toml_get(ck->doc, t, "remote_estop"));
    const roz_toml_node_t *fall = roz_toml_get(ck->doc, t, "fall");
    if (fall != NULL && fall->type != ROZ_TOML_TABLE)
        report(ck, "type", &pl, "fall", "expected a table", fall, NULL);
    else if (fall != NULL)
        check_fall(ck, fall, states_ok ? states : NULL, commands_ok ? commands : NULL);
}

static void check_hardware(checker_t *ck, const roz_toml_node_t *t)
{
    const roz_toml_doc_t *d = ck->doc;
    place_t pl = { SEC_HARDWARE, 0, "hardware", hardware_keys, N_OF(hardware_keys) };
    place_t ppl = { SEC_HARDWARE, 1, "hardware.params", NULL, 0 };
    const roz_toml_node_t *port, *joints, *params;

    unknown_keys(ck, &pl, t);
    (void)check_string(ck, &pl, t, "port", 1, &port);

    joints = roz_toml_get(d, t, "joints");
    if (joints != NULL && joints->type != ROZ_TOML_ARRAY) {
        report(ck, "type", &pl, "joints", "expected an array of strings", joints, NULL);
    } else if (joints != NULL) {
        uint32_t i = 0;
        for (const roz_toml_node_t *j = roz_toml_first(d, joints); j != NULL;
             j = roz_toml_next(d, j), i++) {
            char key[32], what[64];
            snprintf(key, sizeof key, "joints[%lu]", (unsigned long)i);
            if (j->type != ROZ_TOML_STRING) {
                report(ck, "type", &pl, key, "expected a string", j, "joints");
            } else if (j->as.str.len == 0) {
                report(ck, "joint-name", &pl, key, "must not be empty", j, "joints");
            } else if (has_nul(j->as.str)) {
                report(ck, "nul-char", &pl, key, "must not contain a NUL character", j, "joints");
            } else {
                /* among the first ROZ_CFG_MAX_JOINTS only: more joints than
                 * that are refused ("storage"), and comparing every pair of a
                 * long list would take quadratic time */
                uint32_t k = 0;
                for (const roz_toml_node_t *o = roz_toml_first(d, joints);
                     o != j && k < (uint32_t)ROZ_CFG_MAX_JOINTS; o = roz_toml_next(d, o), k++) {
                    if (o->type == ROZ_TOML_STRING && o->as.str.len > 0 && !has_nul(o->as.str) &&
                        str_eq2(o->as.str, j->as.str)) {
                        snprintf(what, sizeof what, "duplicate of joints[%lu]", (unsigned long)k);
                        report(ck, "duplicate-joint", &pl, key, what, j, "joints");
                        break;
                    }
                }
            }
        }
    }

    params = roz_toml_get(d, t, "params");
    if (params != NULL && params->type != ROZ_TOML_TABLE) {
        report(ck, "type", &pl, "params", "expected a table of strings", params, NULL);
    } else if (params != NULL) {
        for (const roz_toml_node_t *v = roz_toml_first(d, params); v != NULL;
             v = roz_toml_next(d, v)) {
            char key[ROZ_CFG_PROBLEM_LEN];
            roz_text_t kb;
            roz_text_init(&kb, key, sizeof key);
            put_key(&kb, v->key);
            roz_text_finish(&kb);
            if (v->type != ROZ_TOML_STRING)
                report(ck, "type", &ppl, key, "expected a string", v, NULL);
            else if (has_nul(v->key))
                report(ck, "nul-char", &ppl, key, "must not contain a NUL character", NULL, NULL);
            else if (has_nul(v->as.str))
                report(ck, "nul-char", &ppl, key, "must not contain a NUL character", v, NULL);
        }
    }
}

static void check_document(checker_t *ck)
{
    const roz_toml_node_t *root = roz_toml_root(ck->doc), *m, *hw;
    place_t top = { SEC_TOP, 0, "", top_keys, N_OF(top_keys) };

    unknown_keys(ck, &top, root);
    m = roz_toml_get(ck->doc, root, "manifest");
    if (m == NULL)
        report(ck, "missing-key", &top, "manifest", "required key is missing", NULL, NULL);
    else if (m->type != ROZ_TOML_TABLE)
        report(ck, "type", &top, "manifest", "expected a table", m, NULL);
    else
        check_manifest(ck, m);
    hw = roz_toml_get(ck->doc, root, "hardware");
    if (hw != NULL && hw->type == ROZ_TOML_TABLE)
        check_hardware(ck, hw);
    else if (hw != NULL)
        report(ck, "type", &top, "hardware", "expected a table", hw, NULL);
}

/* ---- private: building ------------------------------------------------------------------ */

/* Copies a checked string (no NUL inside) into the storage's name arena. */
static const char *intern(roz_manifest_storage_t *st, roz_toml_string_t s)
{
    char *at;
    if ((size_t)s.len + 1u > sizeof st->arena - st->arena_used)
        return NULL;
    at = &st->arena[st->arena_used];
    if (s.len > 0)
        memcpy(at, s.ptr, s.len);
    at[s.len] = '\0';
    st->arena_used += (size_t)s.len + 1u;
    return at;
}

static const char *intern_key(roz_manifest_storage_t *st, const roz_toml_doc_t *d,
                              const roz_toml_node_t *t, const char *key)
{
    return intern(st, roz_toml_get(d, t, key)->as.str);
}

static int build_channels(roz_manifest_storage_t *st, const roz_toml_doc_t *d,
                          const roz_toml_node_t *list, roz_channel_t *out,
                          roz_input_rule_t *rules)
{
    size_t i = 0;
    for (const roz_toml_node_t *t = roz_toml_first(d, list); t != NULL;
         t = roz_toml_next(d, t), i++) {
        const roz_toml_node_t *lim = roz_toml_get(d, t, "limits");
        const roz_toml_node_t *rate = roz_toml_get(d, t, "max_rate_of_change");
        const roz_toml_node_t *pair = roz_toml_get(d, t, "position_state_index");
        const roz_toml_node_t *margin = roz_toml_get(d, t, "limit_margin");
        const roz_toml_node_t *safe = roz_toml_get(d, t, "safe_default");
        const roz_toml_node_t *stale = roz_toml_get(d, t, "stale_after_ms");
        const roz_toml_node_t *source = roz_toml_get(d, t, "source");
        const roz_toml_node_t *scale = roz_toml_get(d, t, "scale");
        roz_channel_t *c = &out[i];
        c->name = intern_key(st, d, t, "name");
        c->unit = intern_key(st, d, t, "unit");
        if (c->name == NULL || c->unit == NULL)
            return ROZ_ENOSPC;
        c->type = (roz_interface_t)channel_interface(d, t);
        c->min = number_of(roz_toml_first(d, lim));
        c->max = number_of(roz_toml_next(d, roz_toml_first(d, lim)));
        c->default_value = number_of(roz_toml_get(d, t, "default"));
        c->max_rate = rate != NULL ? number_of(rate) : 0.0;
        c->position_state = pair != NULL ? (int16_t)pair->as.integer : ROZ_CHANNEL_UNPAIRED;
        c->limit_margin = margin != NULL ? number_of(margin) : 0.0; /* 0: the default */
        c->safe_default = safe != NULL && str_eq(safe->as.str, "hold") ? ROZ_SAFE_HOLD
                                                                             : ROZ_SAFE_FOLLOW;
        if (rules != NULL) { /* an input */
            roz_input_rule_t *r = &rules[i];
            r->stale_after_ms = stale != NULL ? (uint32_t)stale->as.integer : 0u;
            r->source = ROZ_OPERATOR_NONE;
            r->scale = 0.0; /* no source: no scale */
            if (source != NULL &&
                roz_operator_field_parse(source->as.str.ptr, source->as.str.len, &r->source) ==
                    ROZ_OK)
                r->scale = scale != NULL ? number_of(scale) : 1.0;
        }
    }
    return ROZ_OK;
}

/* Builds the checked document into @st; a limit of this build is a
 * "storage" problem. */
static int build(checker_t *ck, roz_manifest_storage_t *st)
{
    const roz_toml_doc_t *d = ck->doc;
    const roz_toml_node_t *root = roz_toml_root(d);
    const roz_toml_node_t *m = roz_toml_get(d, root, "manifest");
    const roz_toml_node_t *hw = roz_toml_get(d, root, "hardware");
    const roz_toml_node_t *cls = roz_toml_get(d, m, "robot_class");
    const roz_toml_node_t *rate = roz_toml_get(d, m, "control_rate_hz");
    const roz_toml_node_t *commands = roz_toml_get(d, m, "commands");
    const roz_toml_node_t *states = roz_toml_get(d, m, "states");
    const roz_toml_node_t *inputs = roz_toml_get(d, m, "inputs");
    roz_manifest_t *man = &st->manifest;
    int rc;

    st->arena_used = 0;
    memset(man, 0, sizeof *man);
    if (hw != NULL) {
        const roz_toml_node_t *joints = roz_toml_get(d, hw, "joints");
        const roz_toml_node_t *params = roz_toml_get(d, hw, "params");
        if (roz_toml_count(joints) > ROZ_CFG_MAX_JOINTS) {
            report_raw(ck, "storage", ": hardware: joints: %lu joints, more than the maximum of "
                                      "%d (ROZ_CFG_MAX_JOINTS)",
                       (unsigned long)roz_toml_count(joints), ROZ_CFG_MAX_JOINTS);
            return ROZ_ENOSPC;
        }
        if (roz_toml_count(params) > ROZ_CFG_MAX_PARAMS) {
            report_raw(ck, "storage", ": hardware.params: %lu parameters, more than the maximum "
                                      "of %d (ROZ_CFG_MAX_PARAMS)",
                       (unsigned long)roz_toml_count(params), ROZ_CFG_MAX_PARAMS);
            return ROZ_ENOSPC;
        }
    }
    if (roz_toml_count(inputs) > ROZ_CFG_MAX_INPUTS) {
        report_raw(ck, "storage", ": manifest: inputs: %lu inputs, more than the maximum of %d "
                                  "(ROZ_CFG_MAX_INPUTS)",
                   (unsigned long)roz_toml_count(inputs), ROZ_CFG_MAX_INPUTS);
        return ROZ_ENOSPC;
    }

    man->robot_id = intern_key(st, d, m, "robot_id");
    man->robot_class = cls != NULL ? intern(st, cls->as.str) : "generic";
    rc = man->robot_id != NULL && man->robot_class != NULL ? ROZ_OK : ROZ_ENOSPC;
    man->control_rate_hz = rate != NULL ? (uint32_t)rate->as.integer : DEFAULT_RATE;
    const roz_toml_node_t *chord = roz_toml_get(d, m, "remote_estop");
    man->remote_estop = chord != NULL ? remote_estop(NULL, d, NULL, chord) : 0u;
    man->commands = st->commands;
    man->n_commands = (uint16_t)roz_toml_count(commands);
    man->states = roz_toml_count(states) > 0 ? st->states : NULL;
    man->n_states = (uint16_t)roz_toml_count(states);
    if (rc == ROZ_OK)
        rc = build_channels(st, d, commands, st->commands, NULL);
    if (rc == ROZ_OK && states != NULL)
        rc = build_channels(st, d, states, st->states, NULL);
    man->inputs = roz_toml_count(inputs) > 0 ? st->inputs : NULL;
    man->input_rules = roz_toml_count(inputs) > 0 ? st->input_rules : NULL;
    man->n_inputs = (uint16_t)roz_toml_count(inputs);
    if (rc == ROZ_OK && inputs != NULL)
        rc = build_channels(st, d, inputs, st->inputs, st->input_rules);
    const roz_toml_node_t *fall = roz_toml_get(d, m, "fall");
    if (rc == ROZ_OK && fall != NULL) {
        const roz_toml_node_t *o = roz_toml_get(d, fall, "orientation"), *t;
        roz_fall_rule_t *r = &st->fall;
        r->orientation = intern(st, o->as.str);
        rc = r->orientation != NULL ? ROZ_OK : ROZ_ENOSPC;
        for (int k = 0; k < 4; k++)
            r->quaternion[k] = (int32_t)fall_state(ck, states, o->as.str, fall_axes[k], &t);
        r->max_tilt = number_of(roz_toml_get(d, fall, "max_tilt_rad"));
        r->for_ms = (uint32_t)roz_toml_get(d, fall, "for_ms")->as.integer;
        man->fall = r;
    }

    if (rc == ROZ_OK && hw != NULL) {
        const roz_toml_node_t *joints = roz_toml_get(d, hw, "joints");
        const roz_toml_node_t *params = roz_toml_get(d, hw, "params");
        roz_hardware_t *h = &st->hardware;
        size_t i = 0;
        memset(h, 0, sizeof *h);
        h->port = intern_key(st, d, hw, "port");
        if (h->port == NULL)
            rc = ROZ_ENOSPC;
        for (const roz_toml_node_t *j = roz_toml_first(d, joints); j != NULL && rc == ROZ_OK;
             j = roz_toml_next(d, j), i++) {
            st->joints[i] = intern(st, j->as.str);
            rc = st->joints[i] != NULL ? ROZ_OK : ROZ_ENOSPC;
        }
        h->joints = st->joints;
        h->n_joints = (uint16_t)i;
        i = 0;
        for (const roz_toml_node_t *v = roz_toml_first(d, params); v != NULL && rc == ROZ_OK;
             v = roz_toml_next(d, v), i++) {
            /* sorted by key, as the generated tables have them */
            roz_param_t p = { intern(st, v->key), intern(st, v->as.str) };
            size_t k = i;
            if (p.key == NULL || p.value == NULL) {
                rc = ROZ_ENOSPC;
                break;
            }
            while (k > 0 && strcmp(st->params[k - 1].key, p.key) > 0) {
                st->params[k] = st->params[k - 1];
                k--;
            }
            st->params[k] = p;
        }
        h->params = i > 0 ? st->params : NULL;
        h->n_params = (uint16_t)i;
        man->hardware = h;
    }
    if (rc != ROZ_OK) {
        report_raw(ck, "storage", ": manifest: names, units and [hardware] strings need more than "
                                  "the %lu bytes of ROZ_CFG_NAME_ARENA_BYTES",
                   (unsigned long)sizeof st->arena);
        st->arena_used = 0;
    }
    return rc;
}

/* ---- public ------------------------------------------------------------------------------ */

int roz_manifest_toml_load(roz_manifest_storage_t *storage, roz_toml_doc_t *doc,
                           const char *text, size_t len, roz_manifest_toml_problem_t *problems,
                           size_t max_problems, size_t *n_found)
{
    return roz_manifest_toml_load_for(storage, doc, text, len, NULL, problems, max_problems,
                                      n_found);
}

int roz_manifest_toml_load_for(roz_manifest_storage_t *storage, roz_toml_doc_t *doc,
                               const char *text, size_t len,
                               const roz_manifest_toml_maxima_t *maxima,
                               roz_manifest_toml_problem_t *problems, size_t max_problems,
                               size_t *n_found)
{
    static const roz_manifest_toml_maxima_t this_build = {
        ROZ_CFG_MAX_COMMANDS, ROZ_CFG_MAX_STATES, ROZ_CFG_MAX_NAME_LEN
    };
    checker_t ck;
    roz_toml_error_t err;
    int rc;

    memset(&ck, 0, sizeof ck);
    ck.doc = doc;
    ck.out = problems;
    ck.cap = problems != NULL ? max_problems : 0u;
    ck.max = maxima != NULL ? *maxima : this_build;
    if (n_found != NULL)
        *n_found = 0;
    if (storage == NULL || doc == NULL || ck.max.commands < 1u ||
        ck.max.commands > ROZ_CFG_MAX_COMMANDS || ck.max.states < 1u ||
        ck.max.states > ROZ_CFG_MAX_STATES || ck.max.name_len < 1u ||
        ck.max.name_len > ROZ_MANIFEST_TOML_MAX_NAME_LEN)
        return ROZ_EINVAL;

    rc = roz_toml_parse(doc, text, len, &err);
    if (rc != ROZ_OK) {
        switch (err.kind) {
        case ROZ_TOML_ERR_UTF8:
            report_raw(&ck, "utf8", ": cannot read: %s", err.message);
            break;
        case ROZ_TOML_ERR_UNSUPPORTED:
            report_raw(&ck, "toml-syntax", ":%lu:%lu: unsupported TOML: %s",
                       (unsigned long)err.line, (unsigned long)err.column, err.message);
            break;
        case ROZ_TOML_ERR_NODES:
        case ROZ_TOML_ERR_ARENA:
            report_raw(&ck, "storage", ":%lu:%lu: cannot read: %s", (unsigned long)err.line,
                       (unsigned long)err.column, err.message);
            break;
        default:
            report_raw(&ck, "toml-syntax", ":%lu:%lu: invalid TOML: %s", (unsigned long)err.line,
                       (unsigned long)err.column, err.message);
            break;
        }
    } else {
        check_document(&ck);
        if (ck.found == 0)
            rc = build(&ck, storage);
        else
            rc = ROZ_EINVAL;
    }
    sort_kept(&ck);
    if (n_found != NULL)
        *n_found = ck.found;
    return rc;
}

int roz_manifest_toml_read_file(const char *path, char *buf, size_t cap, size_t *len,
                                roz_manifest_toml_problem_t *problem)
{
    FILE *f;
    size_t n;
    int failed;

    if (path == NULL || buf == NULL || len == NULL)
        return ROZ_EINVAL;
    *len = 0;
    f = fopen(path, "rb");
    if (f != NULL) {
        n = fread(buf, 1, cap, f);
        failed = ferror(f);
        if (!failed && n == cap && fgetc(f) != EOF) {
            fclose(f);
            if (problem != NULL) {
                problem->rule = "storage";
                snprintf(problem->text, sizeof problem->text,
                         ": cannot read: larger than the %lu bytes of the buffer",
                         (unsigned long)cap);
                memset(problem->order, 0, sizeof problem->order);
            }
            return ROZ_ENOSPC;
        }
        if (!failed) {
            fclose(f);
            *len = n;
            return ROZ_OK;
        }
    }
    /* errno is the C library's only word on why; translated here, once */
    if (problem != NULL) {
        problem->rule = "io-error";
        snprintf(problem->text, sizeof problem->text, ": cannot read: %s", strerror(errno));
        memset(problem->order, 0, sizeof problem->order);
    }
    if (f != NULL)
        fclose(f);
    return ROZ_EIO;
}

int roz_manifest_toml_load_file(const char *path, char *buf, size_t cap,
                                roz_manifest_storage_t *storage, roz_toml_doc_t *doc,
                                roz_manifest_toml_problem_t *problems, size_t max_problems,
                                size_t *n_found)
{
    roz_manifest_toml_problem_t p;
    size_t len = 0;
    int rc = roz_manifest_toml_read_file(path, buf, cap, &len, &p);
    if (rc != ROZ_OK) {
        if (problems != NULL && max_problems > 0)
            problems[0] = p;
        if (n_found != NULL)
            *n_found = rc == ROZ_EINVAL ? 0u : 1u;
        return rc;
    }
    return roz_manifest_toml_load(storage, doc, buf, len, problems, max_problems, n_found);
}
