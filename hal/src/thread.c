/* SPDX-License-Identifier: Apache-2.0 */
/* A thread's parameters (roz/hal/thread.h): parsing only, no OS call. */
#include "roz/hal/thread.h"

#include <string.h>

#include "roz/error.h"
#include "roz/format.h"
#include "roz/hal/params.h"

/* ---- private ------------------------------------------------------------- */

static const char *key_of(char *buf, size_t len, const char *prefix, const char *what)
{
    roz_format(buf, len, "%s_%s", prefix, what);
    return buf;
}

/* "0,2-3": CPUs 0, 2 and 3. */
static int parse_cpus(const char *v, uint64_t *out)
{
    roz_params_span_t rest = roz_params_span(v), e;
    uint64_t mask = 0;

    while (roz_params_list_next(&rest, &e)) {
        roz_params_span_t s = roz_params_trim(e);
        size_t dash = 0;
        uint32_t lo, hi;
        while (dash < s.n && s.s[dash] != '-')
            dash++;
        roz_params_span_t a = { s.s, dash };
        if (roz_params_parse_u32(a, 0, 0, ROZ_THREAD_MAX_CPUS - 1, &lo) != ROZ_OK)
            return ROZ_EINVAL;
        hi = lo;
        if (dash < s.n) {
            roz_params_span_t b = { s.s + dash + 1, s.n - dash - 1 };
            if (roz_params_parse_u32(b, 0, lo, ROZ_THREAD_MAX_CPUS - 1, &hi) != ROZ_OK)
                return ROZ_EINVAL;
        }
        for (uint32_t c = lo; c <= hi; c++)
            mask |= 1ull << c;
    }
    if (mask == 0)
        return ROZ_EINVAL;
    *out = mask;
    return ROZ_OK;
}

/* ---- public -------------------------------------------------------------- */

int roz_thread_params(const roz_params_t *p, const char *prefix, roz_thread_config_t *out,
                      char *err, size_t errlen)
{
    char key[96];
    const char *v;
    int rc;

    v = roz_params_find(p, key_of(key, sizeof key, prefix, "sched"));
    if (v != NULL) {
        roz_params_span_t s = roz_params_trim(roz_params_span(v));
        if (roz_params_span_is(s, "other"))
            out->sched = ROZ_THREAD_OTHER;
        else if (roz_params_span_is(s, "fifo"))
            out->sched = ROZ_THREAD_FIFO;
        else if (roz_params_span_is(s, "rr"))
            out->sched = ROZ_THREAD_RR;
        else {
            roz_format(err, errlen, "parameter %s = \"%s\": expected other, fifo or rr", key, v);
            return ROZ_EINVAL;
        }
    }
    uint32_t prio = (uint32_t)out->priority;
    rc = roz_params_get_u32(p, key_of(key, sizeof key, prefix, "priority"), prio, 1, 99, &prio,
                            err, errlen);
    if (rc != ROZ_OK)
        return rc;
    out->priority = (int)prio;
    if (out->sched == ROZ_THREAD_OTHER) {
        if (roz_params_find(p, key) != NULL) {
            roz_format(err, errlen, "parameter %s: only with %s_sched = fifo or rr", key, prefix);
            return ROZ_EINVAL;
        }
        out->priority = 0;
    } else if (out->priority == 0) {
        roz_format(err, errlen, "parameter %s_sched = %s: needs %s (1..99)", prefix,
                 out->sched == ROZ_THREAD_FIFO ? "fifo" : "rr", key);
        return ROZ_EINVAL;
    }
    v = roz_params_find(p, key_of(key, sizeof key, prefix, "cpus"));
    if (v != NULL && parse_cpus(v, &out->cpus) != ROZ_OK) {
        roz_format(err, errlen,
                 "parameter %s = \"%s\": expected CPUs 0..%d as a list such as 0,2-3", key, v,
                 ROZ_THREAD_MAX_CPUS - 1);
        return ROZ_EINVAL;
    }
    return roz_params_get_u32(p, key_of(key, sizeof key, prefix, "stack_kib"), out->stack_kib,
                              ROZ_THREAD_STACK_MIN_KIB, ROZ_THREAD_STACK_MAX_KIB,
                              &out->stack_kib, err, errlen);
}
