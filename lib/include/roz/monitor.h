/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/monitor.h
 * @brief Latency and jitter monitor: counters and
 *        histograms in static memory, warnings only when a threshold is
 *        exceeded, throttled to one per second per kind.
 *
 * One monitor per thread that records into it (single writer). Reading the
 * figures from another thread while it records gives approximate values;
 * read them after the writer stopped, or from the writer itself.
 */
#ifndef ROZ_MONITOR_H
#define ROZ_MONITOR_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/log.h"

#ifdef __cplusplus
extern "C" {
#endif

/** What is measured. */
typedef enum roz_monitor_kind {
    ROZ_MON_READ = 0,        /**< port read, default threshold 100 us */
    ROZ_MON_WRITE,           /**< port write, 100 us */
    ROZ_MON_STATE_HANDLER,   /**< a port's state callback, 200 us */
    ROZ_MON_COMMAND_WRITER,  /**< a port's command writer pass, 200 us */
    ROZ_MON_JITTER,          /**< |actual - expected| start of a periodic activity, 500 us */
    ROZ_MON_PROCESS,         /**< controller process() call; threshold = the tick budget */
    ROZ_MON_TICK,            /**< one whole tick; threshold = the period */
    ROZ_MON_KIND_COUNT_
} roz_monitor_kind_t;

/** Histogram: 8 sub-buckets per power of two of nanoseconds (12.5 % resolution). */
#define ROZ_MONITOR_SUB_BUCKETS 8
#define ROZ_MONITOR_BUCKETS (64 * ROZ_MONITOR_SUB_BUCKETS)

/** Figures of one kind. */
typedef struct roz_monitor_stat {
    uint64_t count;        /**< samples */
    uint64_t exceeded;     /**< samples above the threshold */
    uint64_t warned;       /**< warnings issued (throttled) */
    uint64_t max_ns;
    uint64_t sum_ns;
    uint64_t last_warn_ns; /**< clock time of the last warning */
    uint32_t hist[ROZ_MONITOR_BUCKETS];
} roz_monitor_stat_t;

/** A threshold warning, as numbers: called instead of formatting one when
 *  set (roz_monitor_set_warn()), so a real-time writer can queue it and a
 *  non-real-time thread format it (roz_monitor_format_warning()). */
typedef void (*roz_monitor_warn_fn)(void *ctx, roz_monitor_kind_t kind, uint64_t ns,
                                    uint64_t threshold_ns, uint64_t exceeded);

/** A monitor; caller-owned storage. */
typedef struct roz_monitor {
    const char        *name;           /**< prefix of warnings, e.g. "runtime" */
    uint64_t           threshold_ns[ROZ_MON_KIND_COUNT_];
    roz_monitor_stat_t stat[ROZ_MON_KIND_COUNT_];
    roz_log_fn         log;
    void              *log_ctx;
    roz_monitor_warn_fn warn;          /**< set: called instead of log, no text */
    void              *warn_ctx;
    uint64_t           period_ns;      /**< expected period for jitter, 0 = none */
    uint64_t           last_start_ns;  /**< previous periodic start, 0 = none */
} roz_monitor_t;

/**
 * @brief Zero a monitor and set the default thresholds (roz_monitor_kind_t)
 *        (PROCESS and TICK default to @p period_ns).
 * Context: start-up; no I/O.
 */
void roz_monitor_init(roz_monitor_t *m, const char *name, uint64_t period_ns,
                      roz_log_fn log, void *log_ctx);

/**
 * @brief Send warnings as numbers to @p warn instead of formatting them for
 *        the log callback (NULL: back to the log callback).
 * Context: start-up.
 */
void roz_monitor_set_warn(roz_monitor_t *m, roz_monitor_warn_fn warn, void *ctx);

/**
 * @brief The text of a threshold warning, as the log callback gets it.
 * @return snprintf's result
 * Context: any; formats text (not for a real-time thread).
 */
int roz_monitor_format_warning(char *buf, size_t len, const char *name, roz_monitor_kind_t kind,
                               uint64_t ns, uint64_t threshold_ns, uint64_t exceeded);

/**
 * @brief Record one sample; warn (through the warn hook when set, else the
 *        log callback) if it exceeds the threshold and the last warning of
 *        that kind is a second old or more.
 * @param[in] now_ns the clock now, for throttling
 * Context: the monitor's writer thread; RT-safe; O(1).
 */
void roz_monitor_record(roz_monitor_t *m, roz_monitor_kind_t kind, uint64_t ns,
                        uint64_t now_ns);

/**
 * @brief Mark the start of one periodic activation at @p start_ns; records
 *        the jitter against the configured period.
 * Context: writer thread; RT-safe.
 */
void roz_monitor_periodic(roz_monitor_t *m, uint64_t start_ns);

/**
 * @brief Approximate percentile (0..100) of a kind, in ns (upper edge of its
 *        histogram bucket, capped at the max seen); 0 without samples.
 */
uint64_t roz_monitor_percentile(const roz_monitor_t *m, roz_monitor_kind_t kind, double pct);

/** @brief Name of a kind ("read", "write", ...). */
const char *roz_monitor_kind_name(roz_monitor_kind_t kind);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_MONITOR_H */
