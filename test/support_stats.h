/* SPDX-License-Identifier: Apache-2.0 */
/* Reading a runtime's figures in tests, through the public accessors. */
#ifndef ROZ_TEST_SUPPORT_STATS_H
#define ROZ_TEST_SUPPORT_STATS_H

#include <stdio.h>
#include <stdlib.h>

#include "roz/runtime.h"

static inline roz_runtime_stats_t roz_test_stats(const roz_runtime_t *rt)
{
    roz_runtime_stats_t st;
    if (roz_runtime_stats(rt, &st) != ROZ_OK) {
        fprintf(stderr, "roz_runtime_stats failed\n");
        abort();
    }
    return st;
}

static inline roz_filter_channel_counters_t roz_test_channel(const roz_runtime_t *rt, size_t ch)
{
    roz_filter_channel_counters_t c;
    if (roz_runtime_channel_counters(rt, ch, &c) != ROZ_OK) {
        fprintf(stderr, "roz_runtime_channel_counters(%zu) failed\n", ch);
        abort();
    }
    return c;
}

static inline roz_monitor_stat_t roz_test_monitor(const roz_monitor_t *m, roz_monitor_kind_t k)
{
    roz_monitor_stat_t s;
    if (roz_monitor_snapshot(m, k, &s) != ROZ_OK) {
        fprintf(stderr, "roz_monitor_snapshot(%d) failed\n", (int)k);
        abort();
    }
    return s;
}

/* One tick whose result the test does not need (it reads the faults
 * itself); roz_runtime_tick() is ROZ_NODISCARD. */
static inline void roz_test_tick(roz_runtime_t *rt)
{
    int rc = roz_runtime_tick(rt);
    (void)rc;
}

/* rt: a pointer to a runtime; field: a member of the part, e.g. faults[1] */
#define RT_COUNT(rt, field)     (roz_test_stats(rt).runtime.field)
#define FILTER_COUNT(rt, field) (roz_test_stats(rt).filter.field)
#define ABI_COUNT(rt, field)    (roz_test_stats(rt).abi.field)

#endif /* ROZ_TEST_SUPPORT_STATS_H */
