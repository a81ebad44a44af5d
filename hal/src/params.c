/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/hal/params.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "roz/format.h"

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

int roz_params_check_known(const roz_params_t *p, const char *const *known, const char *port,
                           char *err, size_t errlen)
{
    if (p == NULL)
        return ROZ_OK;
    for (size_t i = 0; i < p->n; i++) {
        int found = 0;
        for (const char *const *k = known; *k != NULL && !found; k++)
            found = strcmp(*k, p->items[i].key) == 0;
        if (!found) {
            size_t used = (size_t)roz_format(err, errlen,
                                             "unknown parameter \"%s\" for port %s (known:",
                                             p->items[i].key, port);
            for (const char *const *k = known; *k != NULL && used < errlen; k++)
                used += (size_t)roz_format(err + used, errlen - used, " %s", *k);
            if (used < errlen)
                roz_format(err + used, errlen - used, ")");
            return ROZ_ENOENT;
        }
    }
    return ROZ_OK;
}

int roz_params_get_u32(const roz_params_t *p, const char *key, uint32_t def, uint32_t min,
                       uint32_t max, uint32_t *out, char *err, size_t errlen)
{
    const char *v = roz_params_find(p, key);
    char *end = NULL;
    unsigned long long x;

    if (v == NULL) {
        *out = def;
        return ROZ_OK;
    }
    /* strtoull accepts a sign and leading blanks; a parameter may not. */
    if (v[0] < '0' || v[0] > '9')
        goto bad;
    errno = 0; /* strtoull reports overflow only through errno */
    x = strtoull(v, &end, 10);
    if (errno != 0 || end == v || *end != '\0' || x < min || x > max)
        goto bad;
    *out = (uint32_t)x;
    return ROZ_OK;
bad:
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

int roz_params_get_bool(const roz_params_t *p, const char *key, int def, int *out, char *err,
                        size_t errlen)
{
    static const char *const yes[] = { "true", "1", "yes", "on" };
    static const char *const no[] = { "false", "0", "no", "off" };
    const char *v = roz_params_find(p, key);

    if (v == NULL) {
        *out = def;
        return ROZ_OK;
    }
    for (size_t i = 0; i < 4; i++) {
        if (strcmp(v, yes[i]) == 0) {
            *out = 1;
            return ROZ_OK;
        }
        if (strcmp(v, no[i]) == 0) {
            *out = 0;
            return ROZ_OK;
        }
    }
    roz_format(err, errlen, "parameter %s = \"%s\": expected true or false", key, v);
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
