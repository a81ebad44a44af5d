/* SPDX-License-Identifier: Apache-2.0 */
/* The monitor: warnings only above a threshold, throttled to one per second
 * per kind, kept as numbers by the recording thread and passed to the log
 * callback only by roz_monitor_drain() (never by roz_monitor_record());
 * counters, histogram percentiles and jitter against the period. Time is
 * given, never read. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/monitor.h"
#include "support.h"
#include "support_stats.h"

static int warnings;
static char last[256];

static void sink(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    assert_int_equal(level, ROZ_LOG_WARN);
    warnings++;
    strncpy(last, msg, sizeof last - 1);
}

static roz_monitor_t mon;

#define MS 1000000ull
#define S 1000000000ull

static void test_monitor_defaults(void **st)
{
    (void)st;
    roz_monitor_init(&mon, "t", 2 * MS, sink, NULL);
    assert_int_equal(roz_monitor_threshold(&mon, ROZ_MON_READ), 100000);
    assert_int_equal(roz_monitor_threshold(&mon, ROZ_MON_WRITE), 100000);
    assert_int_equal(roz_monitor_threshold(&mon, ROZ_MON_STATE_HANDLER), 200000);
    assert_int_equal(roz_monitor_threshold(&mon, ROZ_MON_COMMAND_WRITER), 200000);
    assert_int_equal(roz_monitor_threshold(&mon, ROZ_MON_JITTER), 500000);
    assert_int_equal(roz_monitor_threshold(&mon, ROZ_MON_TICK), 2 * MS);
    assert_string_equal(roz_monitor_kind_name(ROZ_MON_COMMAND_WRITER), "command writer");
    assert_string_equal(roz_monitor_kind_name(ROZ_MON_KIND_COUNT_), "?");
}

static void test_monitor_threshold_and_throttle(void **st)
{
    (void)st;
    warnings = 0;
    roz_monitor_init(&mon, "port", 2 * MS, sink, NULL);
    /* at or below the threshold: silent */
    for (int i = 0; i < 100; i++)
        roz_monitor_record(&mon, ROZ_MON_READ, 100000, 10 * S + (uint64_t)i);
    assert_int_equal(warnings, 0);
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_READ).exceeded, 0);
    /* above: one warning, then silence for a second */
    roz_monitor_record(&mon, ROZ_MON_READ, 150000, 20 * S);
    assert_int_equal(warnings, 0); /* the recording thread never calls the log */
    assert_int_equal(roz_monitor_drain(&mon), 1);
    assert_int_equal(warnings, 1);
    assert_non_null(strstr(last, "port: read took 150 us, threshold 100 us"));
    assert_int_equal(roz_monitor_drain(&mon), 0); /* passed on once */
    for (int i = 1; i <= 50; i++)
        roz_monitor_record(&mon, ROZ_MON_READ, 150000, 20 * S + (uint64_t)i * 10 * MS);
    assert_int_equal(roz_monitor_drain(&mon), 0);
    assert_int_equal(warnings, 1);
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_READ).exceeded, 51);
    /* another kind has its own throttle */
    roz_monitor_record(&mon, ROZ_MON_WRITE, 150000, 20 * S + 1);
    assert_int_equal(roz_monitor_drain(&mon), 1);
    assert_int_equal(warnings, 2);
    /* a second later: the next warning, with the running count */
    roz_monitor_record(&mon, ROZ_MON_READ, 300000, 21 * S);
    assert_int_equal(warnings, 2);
    assert_int_equal(roz_monitor_drain(&mon), 1);
    assert_int_equal(warnings, 3);
    assert_non_null(strstr(last, "read took 300 us"));
    assert_non_null(strstr(last, "(52 times so far)"));
    /* two warnings between drains: the latest is passed on, with its count */
    roz_monitor_record(&mon, ROZ_MON_READ, 400000, 22 * S);
    roz_monitor_record(&mon, ROZ_MON_READ, 500000, 23 * S);
    assert_int_equal(roz_monitor_drain(&mon), 1);
    assert_non_null(strstr(last, "read took 500 us, threshold 100 us (54 times so far)"));
    /* a threshold set while the writer runs is used from its next sample */
    roz_monitor_set_threshold(&mon, ROZ_MON_WRITE, 1);
    roz_monitor_record(&mon, ROZ_MON_WRITE, 2, 30 * S);
    assert_int_equal(roz_monitor_drain(&mon), 1);
    assert_non_null(strstr(last, "write took 0 us, threshold 0 us"));
    warnings = 3;
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_READ).warned, 4);
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_READ).count, 154);
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_READ).max_ns, 500000);
    /* without a sink: counted, silent */
    roz_monitor_init(&mon, "quiet", 2 * MS, NULL, NULL);
    roz_monitor_record(&mon, ROZ_MON_READ, 999999, S);
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_READ).exceeded, 1);
    roz_monitor_record(&mon, ROZ_MON_KIND_COUNT_, 1, S); /* ignored */
}

static void test_monitor_percentiles(void **st)
{
    (void)st;
    roz_monitor_init(&mon, "p", 2 * MS, NULL, NULL);
    assert_int_equal(roz_monitor_percentile(&mon, ROZ_MON_TICK, 50), 0);
    /* 1..1000 us, one each */
    for (uint64_t us = 1; us <= 1000; us++)
        roz_monitor_record(&mon, ROZ_MON_TICK, us * 1000, S);
    uint64_t p50 = roz_monitor_percentile(&mon, ROZ_MON_TICK, 50);
    uint64_t p99 = roz_monitor_percentile(&mon, ROZ_MON_TICK, 99);
    uint64_t p100 = roz_monitor_percentile(&mon, ROZ_MON_TICK, 100);
    /* buckets are 12.5 % wide: the estimate is the bucket's upper edge */
    assert_true(p50 >= 500000 && p50 <= 500000 * 1.13);
    assert_true(p99 >= 990000 && p99 <= 1000000);
    assert_int_equal(p100, 1000000); /* capped at the max seen */
    /* small values are exact */
    roz_monitor_init(&mon, "p", 2 * MS, NULL, NULL);
    for (int i = 0; i < 10; i++)
        roz_monitor_record(&mon, ROZ_MON_WRITE, 3, S);
    assert_int_equal(roz_monitor_percentile(&mon, ROZ_MON_WRITE, 50), 3);
    /* the histogram ends at 2^38 ns: the last bucket holds the rest, and a
     * percentile that falls in it is the largest sample, however long */
    roz_monitor_init(&mon, "p", 2 * MS, NULL, NULL);
    roz_monitor_record(&mon, ROZ_MON_TICK, 100 * S, S);
    roz_monitor_record(&mon, ROZ_MON_TICK, 400 * S, S);
    roz_monitor_record(&mon, ROZ_MON_TICK, UINT64_MAX / 4, S);
    roz_monitor_stat_t s;
    assert_int_equal(roz_monitor_snapshot(&mon, ROZ_MON_TICK, &s), ROZ_OK);
    assert_int_equal(s.hist[ROZ_MONITOR_BUCKETS - 1], 2);
    uint64_t p1 = roz_monitor_percentile(&mon, ROZ_MON_TICK, 1);
    assert_true(p1 >= 100 * S && p1 <= 100 * S * 1.13);
    assert_int_equal(roz_monitor_percentile(&mon, ROZ_MON_TICK, 50), UINT64_MAX / 4);
    assert_int_equal(roz_monitor_percentile(&mon, ROZ_MON_TICK, 100), UINT64_MAX / 4);
}

static void test_monitor_jitter(void **st)
{
    (void)st;
    warnings = 0;
    roz_monitor_init(&mon, "loop", 2 * MS, sink, NULL);
    uint64_t t = 5 * S;
    roz_monitor_periodic(&mon, t); /* the first start has no interval */
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_JITTER).count, 0);
    for (int i = 0; i < 10; i++) {
        t += 2 * MS + (i % 2 ? 100000 : 0); /* 0 or 100 us late */
        roz_monitor_periodic(&mon, t);
    }
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_JITTER).count, 10);
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_JITTER).max_ns, 100000);
    assert_int_equal(warnings, 0);
    t += 2 * MS + 600000; /* 600 us late: above 500 us */
    roz_monitor_periodic(&mon, t);
    assert_int_equal(warnings, 0);
    assert_int_equal(roz_monitor_drain(&mon), 1);
    assert_int_equal(warnings, 1);
    assert_non_null(strstr(last, "jitter took 600 us"));
    t += 2 * MS - 700000; /* early counts too */
    roz_monitor_periodic(&mon, t);
    assert_int_equal(roz_test_monitor(&mon, ROZ_MON_JITTER).exceeded, 2);
}

static void test_monitor_snapshot_api(void **st)
{
    (void)st;
    roz_monitor_stat_t s;
    roz_monitor_init(&mon, "api", 2 * MS, NULL, NULL);
    roz_monitor_set_threshold(&mon, ROZ_MON_READ, 7);
    assert_int_equal(roz_monitor_threshold(&mon, ROZ_MON_READ), 7);
    roz_monitor_set_threshold(&mon, ROZ_MON_KIND_COUNT_, 7); /* ignored */
    assert_int_equal(roz_monitor_threshold(&mon, ROZ_MON_KIND_COUNT_), 0);
    roz_monitor_record(&mon, ROZ_MON_READ, 5, S);
    roz_monitor_record(&mon, ROZ_MON_READ, 9, S);
    roz_monitor_record(&mon, ROZ_MON_READ, 10, S);
    assert_int_equal(roz_monitor_snapshot(&mon, ROZ_MON_READ, &s), ROZ_OK);
    assert_int_equal(s.count, 3);
    assert_int_equal(s.exceeded, 2);
    assert_int_equal(s.sum_ns, 24);
    assert_int_equal(s.max_ns, 10);
    assert_int_equal(roz_monitor_stat_mean(&s), 8);
    assert_int_equal(roz_monitor_snapshot(&mon, ROZ_MON_KIND_COUNT_, &s), ROZ_EINVAL);
    assert_int_equal(roz_monitor_snapshot(NULL, ROZ_MON_READ, &s), ROZ_EINVAL);
    /* counts past 32 bits survive the two-word storage */
    roz_monitor_record(&mon, ROZ_MON_TICK, 5000000000ull, S);
    assert_int_equal(roz_monitor_snapshot(&mon, ROZ_MON_TICK, &s), ROZ_OK);
    assert_int_equal(s.max_ns, 5000000000ull);
    assert_int_equal(s.sum_ns, 5000000000ull);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_monitor_defaults),
              cmocka_unit_test(test_monitor_threshold_and_throttle),
              cmocka_unit_test(test_monitor_percentiles),
              cmocka_unit_test(test_monitor_jitter),
              cmocka_unit_test(test_monitor_snapshot_api))
