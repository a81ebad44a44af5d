/* SPDX-License-Identifier: Apache-2.0 */
#define _GNU_SOURCE
#include "roz/runner.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#include "roz/error.h"
#include "roz/format.h"
#include "roz/hal/clock.h"
#include "roz/hal/thread.h"

/* ---- private ------------------------------------------------------------- */

#define NS_PER_S 1000000000ull


static void warn(const roz_runner_t *r, const char *what, int err)
{
    if (r->cfg.log != NULL) {
        char msg[160];
        roz_format(msg, sizeof msg, "runner: %s not permitted (%s); running without it", what,
                   strerror(err));
        r->cfg.log(r->cfg.log_ctx, ROZ_LOG_WARN, msg);
    }
}

static struct timespec to_timespec(uint64_t ns)
{
    struct timespec ts = { (time_t)(ns / NS_PER_S), (long)(ns % NS_PER_S) };
    return ts;
}

static void *runner_main(void *arg)
{
    roz_runner_t *r = arg;
    uint64_t next = roz_clock_monotonic_ns(NULL);

    while (!atomic_load(&r->stop)) {
        struct timespec ts = to_timespec(next);
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
            ;
        uint64_t woke = roz_clock_monotonic_ns(NULL);
        roz_monitor_periodic(&r->monitor, woke);
        r->deadline = next;
        if (r->fn(r->ctx) != 0)
            break;
        r->ticks++;
        if (r->cfg.max_ticks != 0 && r->ticks >= r->cfg.max_ticks)
            break;
        next += r->cfg.period_ns;
        uint64_t done = roz_clock_monotonic_ns(NULL);
        if (done > next + r->cfg.period_ns) {
            /* Far behind: count it and restart the schedule from now. */
            r->missed++;
            next = done + r->cfg.period_ns;
        }
    }
    atomic_store(&r->finished, 1);
    return NULL;
}

/* ---- public -------------------------------------------------------------- */

int roz_runner_start(roz_runner_t *r, const roz_runner_config_t *cfg, roz_runner_tick_fn fn,
                     void *ctx)
{
    if (r == NULL || cfg == NULL || fn == NULL || cfg->period_ns == 0 ||
        cfg->realtime_priority < 0 || cfg->realtime_priority > 99 ||
        (cfg->stack_kib != 0 && (cfg->stack_kib < ROZ_THREAD_STACK_MIN_KIB ||
                                 cfg->stack_kib > ROZ_THREAD_STACK_MAX_KIB)))
        return ROZ_EINVAL;
    memset(r, 0, sizeof *r);
    r->cfg = *cfg;
    r->fn = fn;
    r->ctx = ctx;
    atomic_init(&r->stop, 0);
    atomic_init(&r->finished, 0);
    roz_monitor_init(&r->monitor, "runner", cfg->period_ns, cfg->log, cfg->log_ctx);
    if (cfg->lock_memory) {
        if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0)
            r->locked = 1;
        else
            warn(r, "mlockall", errno);
    }
    /* SCHED_FIFO is asked for at creation, so that a refusal is said here,
     * on the caller's thread: the runner's own thread never calls the log
     * (test_runner: blocking_log) */
    roz_thread_config_t tc = { ROZ_THREAD_OTHER, 0, cfg->cpus, cfg->stack_kib };
    char err[200];
    if (cfg->realtime_priority > 0) {
        tc.sched = ROZ_THREAD_FIFO;
        tc.priority = cfg->realtime_priority;
        if (roz_thread_start(&r->thread, &tc, "runner", runner_main, r, err, sizeof err) ==
            ROZ_OK) {
            r->realtime = 1;
            r->started = 1;
            return ROZ_OK;
        }
        warn(r, "SCHED_FIFO", EPERM);
        tc.sched = ROZ_THREAD_OTHER;
        tc.priority = 0;
    }
    int rc = roz_thread_start(&r->thread, &tc, "runner", runner_main, r, err, sizeof err);
    if (rc != ROZ_OK) {
        if (cfg->log != NULL)
            cfg->log(cfg->log_ctx, ROZ_LOG_ERROR, err);
        return rc;
    }
    r->started = 1;
    return ROZ_OK;
}

void roz_runner_stop(roz_runner_t *r)
{
    atomic_store(&r->stop, 1);
}

void roz_runner_join(roz_runner_t *r)
{
    if (!r->started)
        return;
    roz_thread_join(r->thread);
    r->started = 0;
}
