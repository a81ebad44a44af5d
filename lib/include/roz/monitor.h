/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/monitor.h
 * @brief Latency and jitter monitor: counters and
 *        histograms in static memory, warnings only when a threshold is
 *        exceeded, throttled to one per second per kind.
 *
 * A warning leaves the recording thread as numbers, never as a call into
 * the application: through the warn hook when one is set (the runtime
 * queues it in its log ring), else kept in the kind's figures until
 * roz_monitor_drain() formats it on the application's thread. A port
 * thread that records never formats text and never calls the log callback
 * (test_port_conformance: blocking_log).
 *
 * Each kind has one writer thread (a monitor may be shared by a port's
 * threads when each records its own kinds). Any thread reads a kind's
 * figures with roz_monitor_snapshot(): the writer publishes each sample
 * under a sequence counter, so a snapshot is consistent (count, sum, max and
 * histogram of the same instant) and never blocks the writer.
 */
#ifndef ROZ_MONITOR_H
#define ROZ_MONITOR_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/error.h"
#include "roz/log.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** What is measured. */
typedef enum roz_monitor_kind {
    ROZ_MON_READ = 0,        /**< port read (from the tick's start), default threshold 100 us */
    ROZ_MON_WRITE,           /**< port write, 100 us */
    ROZ_MON_STATE_HANDLER,   /**< a port's state callback, 200 us */
    ROZ_MON_COMMAND_WRITER,  /**< a port's command writer pass, 200 us */
    ROZ_MON_JITTER,          /**< |actual - expected| start of a periodic activity, 500 us */
    ROZ_MON_PROCESS,         /**< controller process() call; threshold = the tick budget */
    ROZ_MON_TICK,            /**< one whole tick; threshold = the period */
    ROZ_MON_KIND_COUNT_
} roz_monitor_kind_t;

/** Histogram: 8 sub-buckets per power of two of nanoseconds (12.5 %
 *  resolution) up to 2^38 ns (about 275 s); the last bucket also holds
 *  everything longer, and a percentile that falls in it is the largest
 *  sample (max_ns). */
#define ROZ_MONITOR_SUB_BUCKETS 8
#define ROZ_MONITOR_BUCKETS (36 * ROZ_MONITOR_SUB_BUCKETS)

/** Figures of one kind. */
/** The figures of one kind at one instant (roz_monitor_snapshot()). */
typedef struct roz_monitor_stat {
    uint64_t count;        /**< samples */
    uint64_t exceeded;     /**< samples above the threshold */
    uint64_t warned;       /**< warnings issued (throttled) */
    uint64_t max_ns;
    uint64_t sum_ns;
    uint32_t hist[ROZ_MONITOR_BUCKETS]; /**< samples per bucket (roz_monitor_stat_percentile()) */
} roz_monitor_stat_t;

typedef void (*roz_monitor_warn_fn)(void *ctx, roz_monitor_kind_t kind, uint64_t ns,
                                    uint64_t threshold_ns, uint64_t exceeded);

/** One kind's figures as the writer publishes them (private): 64-bit values
 *  as two 32-bit words (no 64-bit atomics on 32-bit MCUs), under @c seq. */
typedef struct roz_monitor_cell {
    ROZ_ATOMIC(uint32_t) ROZ_PRIVATE(seq);      /* odd while the writer updates */
    ROZ_ATOMIC(uint32_t) ROZ_PRIVATE(w)[14];    /* count, exceeded, warned, max, sum, the
                                                   last warned sample and the exceeded
                                                   count then: lo, hi */
    ROZ_ATOMIC(uint32_t) ROZ_PRIVATE(hist)[ROZ_MONITOR_BUCKETS];
    ROZ_ATOMIC(uint32_t) ROZ_PRIVATE(threshold)[2]; /* ns lo, hi: set by any thread */
    uint64_t             ROZ_PRIVATE(last_warn_ns); /* writer only */
    uint64_t             ROZ_PRIVATE(drained);      /* roz_monitor_drain() only: warnings
                                                       passed on */
} roz_monitor_cell_t;

/** A monitor; caller-owned storage, fields private. */
typedef struct roz_monitor {
    const char        *ROZ_PRIVATE(name);
    roz_monitor_cell_t ROZ_PRIVATE(cell)[ROZ_MON_KIND_COUNT_];
    roz_log_fn         ROZ_PRIVATE(log);
    void              *ROZ_PRIVATE(log_ctx);
    roz_monitor_warn_fn ROZ_PRIVATE(warn);
    void              *ROZ_PRIVATE(warn_ctx);
    uint64_t           ROZ_PRIVATE(period_ns);
    uint64_t           ROZ_PRIVATE(last_start_ns); /* writer of ROZ_MON_JITTER only */
} roz_monitor_t;

/**
 * @brief Zero a monitor and set the default thresholds (roz_monitor_kind_t)
 *        (PROCESS and TICK default to @p period_ns).
 * @param[in] log where roz_monitor_drain() passes the warnings (NULL: none);
 *                never called by roz_monitor_record()
 * Context: start-up; no I/O.
 */
void roz_monitor_init(roz_monitor_t *m, const char *name, uint64_t period_ns,
                      roz_log_fn log, void *log_ctx);

/**
 * @brief Send warnings as numbers to @p warn, on the recording thread,
 *        instead of keeping them for roz_monitor_drain() (NULL: kept).
 *        @p warn must not block (the runtime's queues the numbers).
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
 * @brief Record one sample; warn (through the warn hook when set, else kept
 *        for roz_monitor_drain()) if it exceeds the threshold and the last
 *        warning of that kind is a second old or more.
 * @param[in] now_ns the clock now, for throttling
 * Context: the monitor's writer thread; RT-safe; O(1); formats nothing,
 *          calls no application code but the warn hook.
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
 * @brief Format each kind's warning kept since the last drain (the latest
 *        sample that warned, with how many warnings there were) and pass it
 *        to the log callback given to roz_monitor_init().
 * @return the number of lines passed on
 * Context: one application thread, never the writer's; formats text; the
 *          writer goes on recording meanwhile (it never waits for a drain).
 */
size_t roz_monitor_drain(roz_monitor_t *m);

/**
 * @brief Set the threshold of a kind, in ns (warnings above it); 0 = none.
 * Context: any thread; the writer uses it from its next sample (the two
 *          halves of a threshold above 2^32 ns are stored one at a time).
 */
void roz_monitor_set_threshold(roz_monitor_t *m, roz_monitor_kind_t kind, uint64_t ns);

/** @brief The threshold of a kind in ns (0 none, or a bad kind).
 *  Context: any thread after start-up. */
uint64_t roz_monitor_threshold(const roz_monitor_t *m, roz_monitor_kind_t kind);

/**
 * @brief Copy the figures of one kind, consistently (all of one instant).
 * @retval ROZ_OK     copied
 * @retval ROZ_EINVAL bad kind or NULL
 * @retval ROZ_ESTATE the writer kept updating it (1000 tries); @p out zeroed
 * Context: any thread; never blocks the writer (it retries); copies about
 *          2 KiB.
 */
ROZ_NODISCARD int roz_monitor_snapshot(const roz_monitor_t *m, roz_monitor_kind_t kind,
                                       roz_monitor_stat_t *out);

/**
 * @brief Approximate percentile (0..100) of a snapshot, in ns (upper edge of
 *        its histogram bucket, capped at the max seen); 0 without samples.
 * Context: any; pure.
 */
uint64_t roz_monitor_stat_percentile(const roz_monitor_stat_t *s, double pct);

/** @brief The mean of a snapshot in ns, 0 without samples. Context: any; pure. */
uint64_t roz_monitor_stat_mean(const roz_monitor_stat_t *s);

/**
 * @brief roz_monitor_stat_percentile() of a fresh snapshot of one kind; 0
 *        without samples or when no consistent snapshot could be taken.
 * Context: any thread; copies a snapshot on the caller's stack (about 2 KiB).
 */
uint64_t roz_monitor_percentile(const roz_monitor_t *m, roz_monitor_kind_t kind, double pct);

/** @brief Name of a kind ("read", "write", ...).
 *  Context: any. */
const char *roz_monitor_kind_name(roz_monitor_kind_t kind);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_MONITOR_H */
