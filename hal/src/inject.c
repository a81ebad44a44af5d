/* SPDX-License-Identifier: Apache-2.0 */
/* The simulators' fault-injection grammar (roz/hal/inject.h). Each message
 * says what is wrong with the value as given ("FROM 300 after TO 100"),
 * quoting the user's text rather than a number it was converted to. */
#include "roz/hal/inject.h"

#include <string.h>

#include "roz/error.h"
#include "roz/format.h"
#include "roz/hal/params.h"

enum { BAD = ROZ_INJECT_BAD, SYNTAX = ROZ_INJECT_SYNTAX };

/* Longest entry (the text between two ';'), with its NUL. */
#define ENTRY_MAX (ROZ_INJECT_HEAD_MAX + 96)

static const struct {
    const char *key;
    const char *form;
    const char *head; /* what comes before '@', NULL: nothing */
} kinds[ROZ_INJECT_KIND_END] = {
    [ROZ_INJECT_DROP] = { "drop", "FROM:TO", NULL },
    [ROZ_INJECT_DELAY] = { "delay", "K@FROM:TO", "K" },
    [ROZ_INJECT_FREEZE] = { "freeze", "FROM[:TO]", NULL },
    [ROZ_INJECT_NAN] = { "nan", "CHANNEL@FROM:TO", "CHANNEL" },
    [ROZ_INJECT_RANGE] = { "range", "CHANNEL@FROM:TO", "CHANNEL" },
    [ROZ_INJECT_DUPLICATE] = { "duplicate", "FROM:TO", NULL },
    [ROZ_INJECT_CORRUPT] = { "corrupt", "FROM:TO", NULL },
    [ROZ_INJECT_CORRUPT_CMD] = { "corrupt_cmd", "FROM:TO", NULL },
    [ROZ_INJECT_RESTART] = { "restart", "FROM:TO", NULL },
    [ROZ_INJECT_PUSH] = { "push", "FX,FY,FZ@BODY@FROM:TO (N, world frame)", "FX,FY,FZ@BODY" },
    [ROZ_INJECT_GANTRY] = { "gantry", "FROM[:TO]", NULL },
};

static int known(roz_inject_kind_t kind)
{
    return kind >= ROZ_INJECT_DROP && kind < ROZ_INJECT_KIND_END;
}

/* A tick number at *s: digits only (no sign, no space), no overflow.
 * Advances *s past it. */
static int parse_tick(const char **s, const char *what, uint64_t *out, char *why, size_t whylen)
{
    const char *p = *s;
    uint64_t v = 0;

    if (*p < '0' || *p > '9') {
        roz_format(why, whylen, "%s is missing or not a tick number", what);
        return SYNTAX;
    }
    for (; *p >= '0' && *p <= '9'; p++) {
        unsigned d = (unsigned)(*p - '0');
        if (v > (UINT64_MAX - d) / 10u) {
            size_t n = strspn(*s, "0123456789");
            roz_format(why, whylen, "%s %.*s is too large (at most %llu)", what,
                       n > 40 ? 40 : (int)n, *s, (unsigned long long)UINT64_MAX);
            return BAD;
        }
        v = v * 10u + d;
    }
    *out = v;
    *s = p;
    return 0;
}

/* "FROM:TO", "FROM:" or "FROM"; TO empty = forever (to = 0). */
static int parse_range(const char *s, roz_inject_entry_t *e, char *why, size_t whylen)
{
    int rc, have_to = 0;

    e->to = 0; /* 0: forever, when TO is left out (never when it is written) */
    if ((rc = parse_tick(&s, "FROM", &e->from, why, whylen)) != 0)
        return rc;
    if (*s == ':') {
        s++;
        if (*s != '\0') {
            if ((rc = parse_tick(&s, "TO", &e->to, why, whylen)) != 0)
                return rc;
            have_to = 1;
        }
    }
    if (*s != '\0') {
        roz_format(why, whylen, "unexpected \"%s\" after the ticks", s);
        return SYNTAX;
    }
    if (have_to && e->to < e->from) {
        roz_format(why, whylen, "FROM %llu after TO %llu", (unsigned long long)e->from,
                   (unsigned long long)e->to);
        return BAD;
    }
    if (have_to && e->to == e->from) {
        roz_format(why, whylen, "FROM %llu equals TO: the ticks [FROM, TO) are none",
                   (unsigned long long)e->from);
        return BAD;
    }
    if (!have_to && e->kind == ROZ_INJECT_RESTART) {
        roz_format(why, whylen, "no TO: the robot boots again at TO");
        return SYNTAX;
    }
    return 0;
}

/* One entry, trimmed, NUL-terminated in @p text (which it may cut). */
static int parse_entry(char *text, roz_inject_entry_t *e, char *why, size_t whylen)
{
    const char *head = kinds[e->kind].head;
    const char *range = text;

    e->head[0] = '\0';
    e->arg = 0;
    if (head != NULL) {
        char *at = strrchr(text, '@');
        size_t n = at != NULL ? (size_t)(at - text) : 0;
        if (n == 0) {
            roz_format(why, whylen, "no %s before '@'", head);
            return SYNTAX;
        }
        if (n >= sizeof e->head) {
            roz_format(why, whylen, "the %s before '@' is longer than %u characters", head,
                       (unsigned)sizeof e->head - 1u);
            return BAD;
        }
        memcpy(e->head, text, n);
        e->head[n] = '\0';
        range = at + 1;
        if (e->kind == ROZ_INJECT_DELAY) {
            if (roz_params_parse_u32(roz_params_span(e->head), 0, 1, ROZ_INJECT_MAX_DELAY,
                                     &e->arg) != ROZ_OK) {
                roz_format(why, whylen, "K %s is not a delay in 1..%d ticks", e->head,
                           ROZ_INJECT_MAX_DELAY);
                return SYNTAX;
            }
            e->head[0] = '\0';
        }
    }
    return parse_range(range, e, why, whylen);
}

/* ---- public -------------------------------------------------------------- */

const char *roz_inject_key(roz_inject_kind_t kind)
{
    return known(kind) ? kinds[kind].key : NULL;
}

roz_inject_kind_t roz_inject_find(const char *key)
{
    for (int k = ROZ_INJECT_DROP; key != NULL && k < ROZ_INJECT_KIND_END; k++) {
        if (strcmp(kinds[k].key, key) == 0)
            return (roz_inject_kind_t)k;
    }
    return (roz_inject_kind_t)0;
}

int roz_inject_parse(roz_inject_kind_t kind, const char *value, roz_inject_fn fn, void *ctx,
                     char *err, size_t errlen)
{
    roz_params_span_t rest;
    char why[192];
    int rc = 0;

    if (value == NULL)
        value = "";
    rest = roz_params_span(value);

    if (!known(kind) || fn == NULL) {
        roz_format(err, errlen, "no such fault injection");
        return ROZ_EINVAL;
    }
    for (;;) {
        const char *semi = memchr(rest.s, ';', rest.n);
        size_t len = semi != NULL ? (size_t)(semi - rest.s) : rest.n;
        roz_params_span_t one = roz_params_trim((roz_params_span_t){ rest.s, len });
        roz_inject_entry_t e;
        char text[ENTRY_MAX];

        memset(&e, 0, sizeof e);
        e.kind = kind;
        if (one.n >= sizeof text) {
            roz_format(why, sizeof why, "an entry is longer than %u characters",
                       (unsigned)sizeof text - 1u);
            rc = BAD;
            break;
        }
        memcpy(text, one.s, one.n);
        text[one.n] = '\0';
        if ((rc = parse_entry(text, &e, why, sizeof why)) != 0)
            break;
        why[0] = '\0';
        if ((rc = fn(ctx, &e, why, sizeof why)) != ROZ_OK) {
            rc = rc == SYNTAX ? SYNTAX : BAD;
            break;
        }
        if (semi == NULL)
            return ROZ_OK;
        rest.n -= len + 1u;
        rest.s = semi + 1;
    }
    if (rc == SYNTAX)
        roz_format(err, errlen, "parameter %s = \"%s\": %s; expected %s (ticks%s, ';' between entries)",
                   kinds[kind].key, value, why, kinds[kind].form,
                   kind == ROZ_INJECT_RESTART ? "" : ", TO empty = forever");
    else
        roz_format(err, errlen, "parameter %s = \"%s\": %s", kinds[kind].key, value, why);
    return ROZ_EINVAL;
}
