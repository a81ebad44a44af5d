/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/runner.h
 * @brief Periodic thread for hosts: calls a tick function at absolute
 *        deadlines (clock_nanosleep on CLOCK_MONOTONIC, TIMER_ABSTIME), so
 *        the period does not drift with the tick's own duration.
 *
 * Optional real-time set-up: SCHED_FIFO at a priority, and mlockall(). When
 * the process may not do either, roz_runner_start() warns through the log
 * callback (on the caller's thread) and carries on without it. A deadline
 * missed by more than a whole period is counted and the schedule skips
 * ahead (no burst of catch-up ticks). The runner's thread never calls the
 * log: its jitter warnings wait in @c monitor for roz_monitor_drain() (or
 * roz_runtime_watch_monitor()).
 */
#ifndef ROZ_RUNNER_H
#define ROZ_RUNNER_H

#include "roz/config.h"

#include <stdint.h>

#include "roz/atomic.h"
#include "roz/log.h"
#include "roz/monitor.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Called once per period; a non-zero return stops the runner. */
typedef int (*roz_runner_tick_fn)(void *ctx);

typedef struct roz_runner_config {
    uint64_t   period_ns;    /**< > 0 */
    uint64_t   max_ticks;    /**< stop after this many ticks; 0 = until stopped */
    int        realtime_priority; /**< SCHED_FIFO priority 1..99; 0 = normal scheduling */
    int        lock_memory;  /**< mlockall(MCL_CURRENT | MCL_FUTURE) before starting */
    uint64_t   cpus;         /**< the CPUs the thread may run on, bit i CPU i; 0: any */
    uint32_t   stack_kib;    /**< its stack, KiB (roz/hal/thread.h's
                                  ROZ_THREAD_STACK_MIN_KIB..ROZ_THREAD_STACK_MAX_KIB);
                                  0: the system's default */
    roz_log_fn log;          /**< start-up warnings, and roz_monitor_drain() of @c monitor */
    void      *log_ctx;
} roz_runner_config_t;

/** A runner; caller-owned. Counters are written by the runner thread and
 *  final after roz_runner_join(). */
typedef struct roz_runner {
    roz_runner_config_t cfg;
    roz_runner_tick_fn  fn;
    void               *ctx;
    ROZ_ATOMIC(int)     stop;
    ROZ_ATOMIC(int)     finished; /**< 1 once the thread has ended */
    uint64_t            ticks;
    uint64_t            missed;   /**< deadlines missed by more than a period */
    uint64_t            deadline; /**< the deadline (monotonic ns) the current tick woke
                                       for; written by the runner thread before each tick,
                                       so the tick function may read it (wake-up latency) */
    int                 realtime; /**< 1 if SCHED_FIFO was granted */
    int                 locked;   /**< 1 if mlockall succeeded */
    roz_monitor_t       monitor;  /**< jitter of each wake-up against the period */
    unsigned long       thread;   /* pthread_t, kept opaque */
    int                 started;
} roz_runner_t;

/**
 * @brief Start the periodic thread.
 * @retval ROZ_OK     running
 * @retval ROZ_EINVAL bad configuration
 * @retval ROZ_EIO    the thread could not be created
 * Context: start-up.
 */
int roz_runner_start(roz_runner_t *r, const roz_runner_config_t *cfg, roz_runner_tick_fn fn,
                     void *ctx);

/** @brief Ask the thread to stop after its current tick. Any thread.
 *  Context: any thread; wait-free. */
void roz_runner_stop(roz_runner_t *r);

/** @brief Wait for the thread to end (after stop, max_ticks or a non-zero
 *  tick return). Idempotent.
 * Context: the thread that started the runner; blocks until it ends.
 */
void roz_runner_join(roz_runner_t *r);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_RUNNER_H */
