/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/monitor.h"

#include <stdatomic.h>
#include <string.h>

#include "roz/format.h"

#include "seqlock.h"

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

/* Index of the highest set bit of ns != 0: the compiler's count of
 * leading zeros where there is one (one instruction on Cortex-M3 and up,
 * x86-64, AArch64), else a binary search of six steps (also with
 * ROZ_MONITOR_PORTABLE_CLZ defined: test_monitor_portable runs the
 * monitor's tests on it). */
static unsigned lead_bit(uint64_t ns)
{
#if (defined(__GNUC__) || defined(__clang__)) && !defined(ROZ_MONITOR_PORTABLE_CLZ)
    return 63u - (unsigned)__builtin_clzll(ns);
#else
    unsigned lead = 0;
    for (unsigned step = 32; step != 0; step /= 2u) {
        if ((ns >> step) != 0u) {
            ns >>= step;
            lead += step;
        }
    }
    return lead;
#endif
}

/* Bucket of a value: below 8 ns one bucket per ns; above, the power of two
 * and the next three bits below the leading one, up to the last bucket,
 * which holds the rest. */
static unsigned bucket_of(uint64_t ns)
{
    if (ns < ROZ_MONITOR_SUB_BUCKETS)
        return (unsigned)ns;
    unsigned lead = lead_bit(ns);
    unsigned sub = (unsigned)(ns >> (lead - 3u)) & (ROZ_MONITOR_SUB_BUCKETS - 1u);
    unsigned b = (lead - 2u) * ROZ_MONITOR_SUB_BUCKETS + sub;
    return b < ROZ_MONITOR_BUCKETS ? b : ROZ_MONITOR_BUCKETS - 1u;
}

/* Upper edge (exclusive) of a bucket; the last one has none. */
static uint64_t bucket_top(unsigned b)
{
    if (b >= ROZ_MONITOR_BUCKETS - 1u)
        return UINT64_MAX;
    if (b < ROZ_MONITOR_SUB_BUCKETS)
        return b + 1u;
    unsigned lead = b / ROZ_MONITOR_SUB_BUCKETS + 2u;
    unsigned sub = b % ROZ_MONITOR_SUB_BUCKETS;
    uint64_t base = 1ull << lead;
    return base + ((uint64_t)(sub + 1u) << (lead - 3u));
}

/* The published words of a cell: 64-bit values as lo, hi. */
enum { W_COUNT = 0, W_EXCEEDED = 2, W_WARNED = 4, W_MAX = 6, W_SUM = 8, W_LAST = 10,
       W_LAST_EXCEEDED = 12, W_WORDS = 14 };

/* Writer side: the only writer of a cell reads its own words relaxed. */
static uint64_t ld64(const roz_monitor_cell_t *c, unsigned w)
{
    return (uint64_t)atomic_load_explicit(&c->w[w], memory_order_relaxed) |
           (uint64_t)atomic_load_explicit(&c->w[w + 1u], memory_order_relaxed) << 32;
}

static void st64(roz_monitor_cell_t *c, unsigned w, uint64_t v)
{
    atomic_store_explicit(&c->w[w], (uint32_t)v, memory_order_relaxed);
    atomic_store_explicit(&c->w[w + 1u], (uint32_t)(v >> 32), memory_order_relaxed);
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
    roz_monitor_set_threshold(m, ROZ_MON_READ, 100000);
    roz_monitor_set_threshold(m, ROZ_MON_WRITE, 100000);
    roz_monitor_set_threshold(m, ROZ_MON_STATE_HANDLER, 200000);
    roz_monitor_set_threshold(m, ROZ_MON_COMMAND_WRITER, 200000);
    roz_monitor_set_threshold(m, ROZ_MON_JITTER, 500000);
    roz_monitor_set_threshold(m, ROZ_MON_PROCESS, period_ns);
    roz_monitor_set_threshold(m, ROZ_MON_TICK, period_ns);
}

void roz_monitor_set_threshold(roz_monitor_t *m, roz_monitor_kind_t kind, uint64_t ns)
{
    if ((unsigned)kind >= (unsigned)ROZ_MON_KIND_COUNT_)
        return;
    atomic_store_explicit(&m->cell[kind].threshold[0], (uint32_t)ns, memory_order_relaxed);
    atomic_store_explicit(&m->cell[kind].threshold[1], (uint32_t)(ns >> 32), memory_order_relaxed);
}

uint64_t roz_monitor_threshold(const roz_monitor_t *m, roz_monitor_kind_t kind)
{
    if ((unsigned)kind >= (unsigned)ROZ_MON_KIND_COUNT_)
        return 0;
    const roz_monitor_cell_t *c = &m->cell[kind];
    return (uint64_t)atomic_load_explicit(&c->threshold[0], memory_order_relaxed) |
           (uint64_t)atomic_load_explicit(&c->threshold[1], memory_order_relaxed) << 32;
}

void roz_monitor_record(roz_monitor_t *m, roz_monitor_kind_t kind, uint64_t ns, uint64_t now_ns)
{
    roz_monitor_cell_t *c;
    uint64_t exceeded = 0, threshold;
    int warn = 0;

    if ((unsigned)kind >= (unsigned)ROZ_MON_KIND_COUNT_)
        return;
    c = &m->cell[kind];
    threshold = roz_monitor_threshold(m, kind);
    unsigned b = bucket_of(ns);
    roz__seq_begin(&c->seq);
    st64(c, W_COUNT, ld64(c, W_COUNT) + 1u);
    st64(c, W_SUM, ld64(c, W_SUM) + ns);
    if (ns > ld64(c, W_MAX))
        st64(c, W_MAX, ns);
    atomic_store_explicit(&c->hist[b], atomic_load_explicit(&c->hist[b], memory_order_relaxed) + 1u,
                          memory_order_relaxed);
    if (threshold != 0 && ns > threshold) {
        uint64_t warned = ld64(c, W_WARNED);
        exceeded = ld64(c, W_EXCEEDED) + 1u;
        st64(c, W_EXCEEDED, exceeded);
        if (warned == 0 || now_ns - c->last_warn_ns >= NS_PER_S) {
            st64(c, W_WARNED, warned + 1u);
            st64(c, W_LAST, ns);
            st64(c, W_LAST_EXCEEDED, exceeded);
            c->last_warn_ns = now_ns;
            warn = 1;
        }
    }
    roz__seq_end(&c->seq);
    /* Without a hook the warning stays in the figures just published, for
     * roz_monitor_drain(): this thread may be the only one that puts
     * commands on the wire, so it never calls into the application. */
    if (warn && m->warn != NULL)
        m->warn(m->warn_ctx, kind, ns, threshold, exceeded);
}

size_t roz_monitor_drain(roz_monitor_t *m)
{
    size_t n = 0;

    if (m == NULL)
        return 0;
    for (unsigned k = 0; k < (unsigned)ROZ_MON_KIND_COUNT_; k++) {
        roz_monitor_cell_t *c = &m->cell[k];
        uint32_t w[W_WORDS];
        unsigned tries = 0;
        for (; tries < 1000u; tries++) {
            uint32_t q = roz__seq_read_begin(&c->seq);
            roz__seq_load(w, c->w, W_WORDS);
            if (roz__seq_read_ok(&c->seq, q))
                break;
        }
        if (tries == 1000u)
            continue; /* the writer kept updating it: next drain */
        uint64_t warned = (uint64_t)w[W_WARNED] | (uint64_t)w[W_WARNED + 1] << 32;
        if (warned == c->drained)
            continue;
        c->drained = warned;
        if (m->log == NULL)
            continue;
        char msg[160];
        roz_monitor_format_warning(msg, sizeof msg, m->name, (roz_monitor_kind_t)k,
                                   (uint64_t)w[W_LAST] | (uint64_t)w[W_LAST + 1] << 32,
                                   roz_monitor_threshold(m, (roz_monitor_kind_t)k),
                                   (uint64_t)w[W_LAST_EXCEEDED] |
                                       (uint64_t)w[W_LAST_EXCEEDED + 1] << 32);
        m->log(m->log_ctx, ROZ_LOG_WARN, msg);
        n++;
    }
    return n;
}

void roz_monitor_set_warn(roz_monitor_t *m, roz_monitor_warn_fn warn, void *ctx)
{
    m->warn = warn;
    m->warn_ctx = ctx;
}

int roz_monitor_format_warning(char *buf, size_t len, const char *name, roz_monitor_kind_t kind,
                               uint64_t ns, uint64_t threshold_ns, uint64_t exceeded)
{
    return roz_format(buf, len, "%s: %s took %llu us, threshold %llu us (%llu times so far)",
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

int roz_monitor_snapshot(const roz_monitor_t *m, roz_monitor_kind_t kind, roz_monitor_stat_t *out)
{
    if (m == NULL || out == NULL || (unsigned)kind >= (unsigned)ROZ_MON_KIND_COUNT_)
        return ROZ_EINVAL;
    const roz_monitor_cell_t *c = &m->cell[kind];
    for (unsigned tries = 0; tries < 1000u; tries++) {
        uint32_t q = roz__seq_read_begin(&c->seq), w[W_WORDS];
        roz__seq_load(w, c->w, W_WORDS);
        roz__seq_load(out->hist, c->hist, ROZ_MONITOR_BUCKETS);
        if (!roz__seq_read_ok(&c->seq, q))
            continue;
        out->count = (uint64_t)w[W_COUNT] | (uint64_t)w[W_COUNT + 1] << 32;
        out->exceeded = (uint64_t)w[W_EXCEEDED] | (uint64_t)w[W_EXCEEDED + 1] << 32;
        out->warned = (uint64_t)w[W_WARNED] | (uint64_t)w[W_WARNED + 1] << 32;
        out->max_ns = (uint64_t)w[W_MAX] | (uint64_t)w[W_MAX + 1] << 32;
        out->sum_ns = (uint64_t)w[W_SUM] | (uint64_t)w[W_SUM + 1] << 32;
        return ROZ_OK;
    }
    memset(out, 0, sizeof *out);
    return ROZ_ESTATE;
}

uint64_t roz_monitor_stat_percentile(const roz_monitor_stat_t *s, double pct)
{
    uint64_t want, seen = 0;

    if (s == NULL || s->count == 0)
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

uint64_t roz_monitor_stat_mean(const roz_monitor_stat_t *s)
{
    return s != NULL && s->count != 0 ? s->sum_ns / s->count : 0;
}

uint64_t roz_monitor_percentile(const roz_monitor_t *m, roz_monitor_kind_t kind, double pct)
{
    roz_monitor_stat_t s;
    if (roz_monitor_snapshot(m, kind, &s) != ROZ_OK)
        return 0;
    return roz_monitor_stat_percentile(&s, pct);
}

const char *roz_monitor_kind_name(roz_monitor_kind_t kind)
{
    if ((unsigned)kind >= (unsigned)ROZ_MON_KIND_COUNT_)
        return "?";
    return kind_names[kind];
}
