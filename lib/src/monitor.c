/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/monitor.h"

#include <stdio.h>
#include <string.h>

/* ---- private ------------------------------------------------------------- */

#define NS_PER_S 1000000000ull

static const char *const kind_names[ROZ_MON_KIND_COUNT_] = {
    [ROZ_MON_READ] = "read",
    [ROZ_MON_WRITE] = "write",
    [ROZ_MON_STATE_HANDLER] = "state handler",
    [ROZ_MON_COMMAND_WRITER] = "command writer",
    [ROZ_MON_JITTER] = "jitter",
    [ROZ_MON_PROCESS] = "process",
    [ROZ_MON_TICK] = "tick",
};

/* Bucket of a value: below 8 ns one bucket per ns; above, the power of two
 * and the next three bits below the leading one. */
static unsigned bucket_of(uint64_t ns)
{
    if (ns < ROZ_MONITOR_SUB_BUCKETS)
        return (unsigned)ns;
    unsigned lead = 63u - (unsigned)__builtin_clzll(ns);
    unsigned sub = (unsigned)(ns >> (lead - 3u)) & (ROZ_MONITOR_SUB_BUCKETS - 1u);
    return (lead - 2u) * ROZ_MONITOR_SUB_BUCKETS + sub;
}

/* Upper edge (exclusive) of a bucket. */
static uint64_t bucket_top(unsigned b)
{
    if (b < ROZ_MONITOR_SUB_BUCKETS)
        return b + 1u;
    unsigned lead = b / ROZ_MONITOR_SUB_BUCKETS + 2u;
    unsigned sub = b % ROZ_MONITOR_SUB_BUCKETS;
    uint64_t base = 1ull << lead;
    return base + ((uint64_t)(sub + 1u) << (lead - 3u));
}

/* ---- public -------------------------------------------------------------- */

void roz_monitor_init(roz_monitor_t *m, const char *name, uint64_t period_ns,
                      roz_log_fn log, void *log_ctx)
{
    memset(m, 0, sizeof *m);
    m->name = name != NULL ? name : "roz";
    m->period_ns = period_ns;
    m->log = log;
    m->log_ctx = log_ctx;
    m->threshold_ns[ROZ_MON_READ] = 100000;
    m->threshold_ns[ROZ_MON_WRITE] = 100000;
    m->threshold_ns[ROZ_MON_STATE_HANDLER] = 200000;
    m->threshold_ns[ROZ_MON_COMMAND_WRITER] = 200000;
    m->threshold_ns[ROZ_MON_JITTER] = 500000;
    m->threshold_ns[ROZ_MON_PROCESS] = period_ns;
    m->threshold_ns[ROZ_MON_TICK] = period_ns;
}

void roz_monitor_record(roz_monitor_t *m, roz_monitor_kind_t kind, uint64_t ns, uint64_t now_ns)
{
    roz_monitor_stat_t *s;

    if ((unsigned)kind >= (unsigned)ROZ_MON_KIND_COUNT_)
        return;
    s = &m->stat[kind];
    s->count++;
    s->sum_ns += ns;
    if (ns > s->max_ns)
        s->max_ns = ns;
    s->hist[bucket_of(ns)]++;
    if (m->threshold_ns[kind] == 0 || ns <= m->threshold_ns[kind])
        return;
    s->exceeded++;
    if (s->warned != 0 && now_ns - s->last_warn_ns < NS_PER_S)
        return;
    s->warned++;
    s->last_warn_ns = now_ns;
    if (m->warn != NULL) {
        m->warn(m->warn_ctx, kind, ns, m->threshold_ns[kind], s->exceeded);
    } else if (m->log != NULL) {
        char msg[160];
        roz_monitor_format_warning(msg, sizeof msg, m->name, kind, ns, m->threshold_ns[kind],
                                   s->exceeded);
        m->log(m->log_ctx, ROZ_LOG_WARN, msg);
    }
}

void roz_monitor_set_warn(roz_monitor_t *m, roz_monitor_warn_fn warn, void *ctx)
{
    m->warn = warn;
    m->warn_ctx = ctx;
}

int roz_monitor_format_warning(char *buf, size_t len, const char *name, roz_monitor_kind_t kind,
                               uint64_t ns, uint64_t threshold_ns, uint64_t exceeded)
{
    return snprintf(buf, len, "%s: %s took %llu us, threshold %llu us (%llu times so far)",
                    name != NULL ? name : "roz", roz_monitor_kind_name(kind),
                    (unsigned long long)(ns / 1000u), (unsigned long long)(threshold_ns / 1000u),
                    (unsigned long long)exceeded);
}

void roz_monitor_periodic(roz_monitor_t *m, uint64_t start_ns)
{
    if (m->period_ns != 0 && m->last_start_ns != 0) {
        uint64_t interval = start_ns - m->last_start_ns;
        uint64_t jitter = interval > m->period_ns ? interval - m->period_ns
                                                  : m->period_ns - interval;
        roz_monitor_record(m, ROZ_MON_JITTER, jitter, start_ns);
    }
    m->last_start_ns = start_ns;
}

uint64_t roz_monitor_percentile(const roz_monitor_t *m, roz_monitor_kind_t kind, double pct)
{
    const roz_monitor_stat_t *s;
    uint64_t want, seen = 0;

    if ((unsigned)kind >= (unsigned)ROZ_MON_KIND_COUNT_)
        return 0;
    s = &m->stat[kind];
    if (s->count == 0)
        return 0;
    if (!(pct > 0.0))
        pct = 0.0;
    if (pct > 100.0)
        pct = 100.0;
    want = (uint64_t)((double)s->count * pct / 100.0 + 0.5);
    if (want == 0)
        want = 1;
    for (unsigned b = 0; b < ROZ_MONITOR_BUCKETS; b++) {
        seen += s->hist[b];
        if (seen >= want) {
            uint64_t top = bucket_top(b);
            return top < s->max_ns ? top : s->max_ns;
        }
    }
    return s->max_ns;
}

const char *roz_monitor_kind_name(roz_monitor_kind_t kind)
{
    if ((unsigned)kind >= (unsigned)ROZ_MON_KIND_COUNT_)
        return "?";
    return kind_names[kind];
}
