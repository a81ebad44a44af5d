/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/hal/params.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "roz/format.h"
#include "roz/text.h"

/* ---- values -------------------------------------------------------------- */

static int is_blank(char c)
{
    return c == ' ' || c == '\t';
}

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

roz_params_span_t roz_params_span(const char *z)
{
    roz_params_span_t sp = { z != NULL ? z : "", z != NULL ? strlen(z) : 0u };
    return sp;
}

roz_params_span_t roz_params_trim(roz_params_span_t s)
{
    while (s.n > 0 && is_blank(s.s[0])) {
        s.s++;
        s.n--;
    }
    while (s.n > 0 && is_blank(s.s[s.n - 1]))
        s.n--;
    return s;
}

int roz_params_span_is(roz_params_span_t s, const char *z)
{
    return strlen(z) == s.n && memcmp(s.s, z, s.n) == 0;
}

int roz_params_list_next(roz_params_span_t *rest, roz_params_span_t *entry)
{
    const char *comma;

    if (rest->s == NULL)
        return 0;
    comma = rest->n > 0 ? memchr(rest->s, ',', rest->n) : NULL;
    entry->s = rest->s;
    entry->n = comma != NULL ? (size_t)(comma - rest->s) : rest->n;
    *entry = roz_params_trim(*entry);
    if (comma != NULL) {
        rest->n -= (size_t)(comma + 1 - rest->s);
        rest->s = comma + 1;
    } else {
        rest->s = NULL; /* used up */
        rest->n = 0;
    }
    return 1;
}

int roz_params_parse_u32(roz_params_span_t s, unsigned flags, uint32_t min, uint32_t max,
                         uint32_t *out)
{
    unsigned base = 10;
    uint64_t v = 0;
    size_t i = 0;

    if ((flags & ROZ_PARAMS_HEX) != 0u && s.n > 2 && s.s[0] == '0' &&
        (s.s[1] == 'x' || s.s[1] == 'X')) {
        base = 16;
        i = 2;
    }
    if (i >= s.n)
        return ROZ_EINVAL;
    for (; i < s.n; i++) {
        char c = s.s[i];
        unsigned d;
        if (is_digit(c))
            d = (unsigned)(c - '0');
        else if (base == 16 && c >= 'a' && c <= 'f')
            d = (unsigned)(c - 'a' + 10);
        else if (base == 16 && c >= 'A' && c <= 'F')
            d = (unsigned)(c - 'A' + 10);
        else
            return ROZ_EINVAL;
        v = v * base + d;
        if (v > UINT32_MAX)
            return ROZ_EINVAL;
    }
    if (v < min || v > max)
        return ROZ_EINVAL;
    *out = (uint32_t)v;
    return ROZ_OK;
}

int roz_params_parse_number(roz_params_span_t s, double *out)
{
    /* the digits without their point, and the exponent moved by as many
     * places: strtod then reads no decimal point, whose character is the
     * locale's ("12.5e3" is read as "125e2") */
    char buf[ROZ_PARAMS_NUMBER_MAX + 16];
    size_t i = 0, digits = 0, n = 0;
    long exp10 = 0, frac = 0;
    int neg_exp = 0;
    double x;

    if (s.n == 0 || s.n > ROZ_PARAMS_NUMBER_MAX)
        return ROZ_EINVAL;
    if (s.s[i] == '+' || s.s[i] == '-')
        buf[n++] = s.s[i++];
    while (i < s.n && is_digit(s.s[i])) {
        buf[n++] = s.s[i++];
        digits++;
    }
    if (i < s.n && s.s[i] == '.') {
        i++;
        while (i < s.n && is_digit(s.s[i])) {
            buf[n++] = s.s[i++];
            digits++;
            frac++;
        }
    }
    if (digits == 0)
        return ROZ_EINVAL;
    if (i < s.n && (s.s[i] == 'e' || s.s[i] == 'E')) {
        size_t exp_digits = 0;
        i++;
        if (i < s.n && (s.s[i] == '+' || s.s[i] == '-'))
            neg_exp = s.s[i++] == '-';
        while (i < s.n && is_digit(s.s[i])) {
            if (exp10 < 1000000L) /* far past any double either way */
                exp10 = exp10 * 10 + (s.s[i] - '0');
            i++;
            exp_digits++;
        }
        if (exp_digits == 0)
            return ROZ_EINVAL;
    }
    if (i != s.n)
        return ROZ_EINVAL;
    exp10 = (neg_exp ? -exp10 : exp10) - frac;
    buf[n] = '\0';
    (void)roz_format(buf + n, sizeof buf - n, "e%ld", exp10);
    x = strtod(buf, NULL);
    if (!isfinite(x))
        return ROZ_EINVAL;
    *out = x;
    return ROZ_OK;
}

int roz_params_parse_range(roz_params_span_t s, double *min, double *max)
{
    const char *colon = s.n > 0 ? memchr(s.s, ':', s.n) : NULL;
    roz_params_span_t lo, hi;
    double a, b;

    if (colon == NULL)
        return ROZ_EINVAL;
    lo.s = s.s;
    lo.n = (size_t)(colon - s.s);
    hi.s = colon + 1;
    hi.n = s.n - lo.n - 1;
    if (roz_params_parse_number(roz_params_trim(lo), &a) != ROZ_OK ||
        roz_params_parse_number(roz_params_trim(hi), &b) != ROZ_OK)
        return ROZ_EINVAL;
    *min = a;
    *max = b;
    return ROZ_OK;
}

int roz_params_parse_bool(roz_params_span_t s, int *out)
{
    static const char *const yes[] = { "true", "1", "yes", "on" };
    static const char *const no[] = { "false", "0", "no", "off" };

    for (size_t i = 0; i < 4; i++) {
        if (roz_params_span_is(s, yes[i])) {
            *out = 1;
            return ROZ_OK;
        }
        if (roz_params_span_is(s, no[i])) {
            *out = 0;
            return ROZ_OK;
        }
    }
    return ROZ_EINVAL;
}

int roz_params_ifname_valid(roz_params_span_t s, size_t max, roz_params_ifname_t rule)
{
    if (s.n == 0 || s.n > max)
        return 0;
    for (size_t i = 0; i < s.n; i++) {
        unsigned char c = (unsigned char)s.s[i];
        int ok = rule == ROZ_PARAMS_IFNAME_LINUX
                     ? c > 0x20 && c < 0x7F && c != '/'
                     : (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || is_digit((char)c) ||
                           c == '_' || c == '.' || c == ':' || c == '-';
        if (!ok)
            return 0;
    }
    return 1;
}

int roz_params_ifname_expected(char *buf, size_t len, size_t max, roz_params_ifname_t rule)
{
    int os = rule == ROZ_PARAMS_IFNAME_LINUX;
    return roz_format(buf, len, "expected an interface name%s%u%s", os ? ", 1.." : " (1..",
                      (unsigned)max, os ? " printable bytes without spaces or '/'"
                                        : " characters from A-Z a-z 0-9 _ . : -), such as lo "
                                          "or eth0");
}

/* ---- keys ---------------------------------------------------------------- */

const char *roz_params_find(const roz_params_t *p, const char *key)
{
    const char *v = NULL;
    if (p == NULL || key == NULL)
        return NULL;
    for (size_t i = 0; i < p->n; i++) {
        if (p->items[i].key != NULL && strcmp(p->items[i].key, key) == 0)
            v = p->items[i].value;
    }
    return v;
}

/* The @p i-th known key: of the NULL-terminated list @p known, else of the
 * @p n rows; NULL past the last. */
static const char *known_key(const char *const *known, const roz_port_param_info_t *rows,
                             size_t n, size_t i)
{
    if (known != NULL)
        return known[i];
    return i < n ? rows[i].key : NULL;
}

static int check_known(const roz_params_t *p, const char *const *known,
                       const roz_port_param_info_t *rows, size_t n, const char *port, char *err,
                       size_t errlen)
{
    if (p == NULL)
        return ROZ_OK;
    for (size_t i = 0; i < p->n; i++) {
        int found = 0;
        const char *k;
        for (size_t j = 0; (k = known_key(known, rows, n, j)) != NULL && !found; j++)
            found = strcmp(k, p->items[i].key) == 0;
        if (!found && errlen > 0u) {
            roz_text_t t;
            roz_text_init(&t, err, errlen);
            roz_text_format(&t, "unknown parameter \"%s\" for port %s (known:", p->items[i].key,
                            port);
            for (size_t j = 0; (k = known_key(known, rows, n, j)) != NULL; j++) {
                roz_text_put(&t, " ");
                roz_text_put(&t, k);
            }
            roz_text_put(&t, ")");
        }
        if (!found)
            return ROZ_ENOENT;
    }
    return ROZ_OK;
}

int roz_params_check_known(const roz_params_t *p, const char *const *known, const char *port,
                           char *err, size_t errlen)
{
    return check_known(p, known, NULL, 0, port, err, errlen);
}

int roz_params_check_known_rows(const roz_params_t *p, const roz_port_param_info_t *rows,
                                size_t n, const char *port, char *err, size_t errlen)
{
    return check_known(p, NULL, rows, n, port, err, errlen);
}

void roz_params_report(void *reporter, const char *rule, const char *text)
{
    const roz_params_reporter_t *to = reporter;
    char line[ROZ_CFG_PROBLEM_LEN + 2];
    size_t n = strlen(text);
    int cut = n + 1 >= ROZ_CFG_PROBLEM_LEN;
    roz_format(line, sizeof line, ": %.*s%s", (int)(cut ? n - 3 : n), text, cut ? "..." : "");
    to->report(to->ctx, rule, line);
}

int roz_params_get_u32(const roz_params_t *p, const char *key, uint32_t def, uint32_t min,
                       uint32_t max, uint32_t *out, char *err, size_t errlen)
{
    const char *v = roz_params_find(p, key);

    if (v == NULL) {
        *out = def;
        return ROZ_OK;
    }
    if (roz_params_parse_u32(roz_params_span(v), 0u, min, max, out) == ROZ_OK)
        return ROZ_OK;
    roz_format(err, errlen, "parameter %s = \"%s\": expected an integer in %lu..%lu", key, v,
               (unsigned long)min, (unsigned long)max);
    return ROZ_EINVAL;
}

int roz_params_get_double(const roz_params_t *p, const char *key, double def, double min,
                          double max, double *out, char *err, size_t errlen)
{
    const char *v = roz_params_find(p, key);
    char *end = NULL;
    double x;

    if (v == NULL) {
        *out = def;
        return ROZ_OK;
    }
    x = strtod(v, &end);
    if (end == v || *end != '\0' || !isfinite(x) || x < min || x > max) {
        roz_format(err, errlen, "parameter %s = \"%s\": expected a number in %g..%g", key, v, min,
                   max);
        return ROZ_EINVAL;
    }
    *out = x;
    return ROZ_OK;
}

/* The row of key with the kind asked for, or NULL (err says so). */
static const roz_port_param_info_t *row_of(const roz_port_param_info_t *rows, size_t n,
                                           const char *key, roz_port_param_kind_t kind,
                                           char *err, size_t errlen)
{
    for (size_t i = 0; i < n; i++) {
        if (strcmp(rows[i].key, key) == 0 && rows[i].kind == kind)
            return &rows[i];
    }
    roz_format(err, errlen, "parameter %s: the port's table has no numeric row for it", key);
    return NULL;
}

int roz_params_get_row_u32(const roz_params_t *p, const roz_port_param_info_t *rows, size_t n,
                           const char *key, uint32_t *out, char *err, size_t errlen)
{
    const roz_port_param_info_t *r = row_of(rows, n, key, ROZ_PORT_PARAM_U32, err, errlen);
    if (r == NULL)
        return ROZ_EINVAL;
    return roz_params_get_u32(p, key, (uint32_t)r->dflt, (uint32_t)r->min, (uint32_t)r->max, out,
                              err, errlen);
}

int roz_params_get_row_double(const roz_params_t *p, const roz_port_param_info_t *rows, size_t n,
                              const char *key, double *out, char *err, size_t errlen)
{
    const roz_port_param_info_t *r = row_of(rows, n, key, ROZ_PORT_PARAM_DOUBLE, err, errlen);
    if (r == NULL)
        return ROZ_EINVAL;
    return roz_params_get_double(p, key, r->dflt, r->min, r->max, out, err, errlen);
}

int roz_params_get_bool(const roz_params_t *p, const char *key, int def, int *out, char *err,
                        size_t errlen)
{
    const char *v = roz_params_find(p, key);

    if (v == NULL) {
        *out = def;
        return ROZ_OK;
    }
    if (roz_params_parse_bool(roz_params_span(v), out) == ROZ_OK)
        return ROZ_OK;
    roz_format(err, errlen, "parameter %s = \"%s\": " ROZ_PARAMS_EXPECTED_BOOL, key, v);
    return ROZ_EINVAL;
}

const char *roz_params_get_str(const roz_params_t *p, const char *key, const char *def)
{
    const char *v = roz_params_find(p, key);
    return v != NULL ? v : def;
}

int roz_params_split(char *arg, roz_param_t *out)
{
    char *eq = arg != NULL ? strchr(arg, '=') : NULL;
    if (eq == NULL || eq == arg)
        return ROZ_EINVAL;
    *eq = '\0';
    out->key = arg;
    out->value = eq + 1;
    return ROZ_OK;
}

int roz_params_get_choice(const roz_params_t *p, const char *key, const char *def,
                          const roz_params_word_t *words, size_t n, const char *expected,
                          int *out, char *err, size_t errlen)
{
    const char *v = roz_params_get_str(p, key, def);
    for (size_t i = 0; i < n; i++) {
        if (strcmp(v, words[i].word) == 0) {
            *out = words[i].value;
            return ROZ_OK;
        }
    }
    roz_format(err, errlen, "parameter %s = \"%s\": expected %s", key, v, expected);
    return ROZ_EINVAL;
}

roz_params_t roz_params_hardware(const roz_manifest_t *m)
{
    roz_params_t p = { NULL, 0 };
    if (m->hardware != NULL) {
        p.items = m->hardware->params;
        p.n = m->hardware->n_params;
    }
    return p;
}

int roz_params_merge(const roz_manifest_t *m, const roz_params_t *given, roz_param_t *storage,
                     size_t cap, const char *port, roz_params_t *out, char *err, size_t errlen)
{
    roz_params_t hw = roz_params_hardware(m);
    size_t n = 0, more = given != NULL ? given->n : 0;

    if (hw.n + more > cap) {
        roz_format(err, errlen, "%s: %zu parameters; at most %zu", port, hw.n + more, cap);
        return ROZ_EINVAL;
    }
    for (size_t i = 0; i < hw.n; i++)
        storage[n++] = hw.items[i];
    for (size_t i = 0; i < more; i++)
        storage[n++] = given->items[i];
    out->items = storage;
    out->n = n;
    return ROZ_OK;
}
