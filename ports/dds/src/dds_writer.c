/* SPDX-License-Identifier: Apache-2.0 */
/* The command writer: a topic, a writer, and a thread that publishes the
 * port's latest command periodically (absolute deadlines, jitter against
 * the period) or when woken (event-driven). */
#define _GNU_SOURCE /* sem_clockwait */
#include "dds_internal.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <semaphore.h>
#include <string.h>
#include <time.h>

#include "roz/hal/clock.h"

#define NS_PER_S 1000000000ull

_Static_assert(sizeof(pthread_t) <= sizeof(unsigned long), "pthread_t must fit the opaque field");
_Static_assert(sizeof(sem_t) <= sizeof(((roz_dds_writer_t *)0)->wake.bytes),
               "sem_t must fit the opaque field");
_Static_assert(_Alignof(sem_t) <= _Alignof(long double), "sem_t alignment");

/* ---- private ------------------------------------------------------------- */

static sem_t *wake_sem(roz_dds_writer_t *w)
{
    return (sem_t *)(void *)w->wake.bytes;
}

/* One pass: the port fills the zeroed sample, roz publishes it. */
static int pass(roz_dds_writer_t *w, roz_dds_fill_fn fill, void *ctx, uint64_t now_ns)
{
    int rc = 1;

    memset(w->sample, 0, w->sample_size);
    atomic_fetch_add_explicit(&w->passes, 1u, memory_order_relaxed);
    if (!fill(ctx, w->sample, now_ns)) {
        rc = 0;
    } else if (dds_write(w->writer, w->sample) != DDS_RETCODE_OK) {
        atomic_fetch_add_explicit(&w->errors, 1u, memory_order_relaxed);
        rc = ROZ_EIO;
    } else {
        atomic_fetch_add_explicit(&w->published, 1u, memory_order_relaxed);
    }
    atomic_fetch_add_explicit(&w->done, 1u, memory_order_release);
    return rc;
}

/* The watchdog's clock now (roz_dds_writer_watch()), given the monotonic
 * clock's @p mono: the same reading where the watchdog counts on it. */
static uint64_t watch_now(const roz_dds_writer_t *w, uint64_t mono)
{
    return w->clock == roz_clock_monotonic_ns ? mono : w->clock(w->clock_ctx);
}

static void timed_pass(roz_dds_writer_t *w)
{
    uint64_t t0 = roz_clock_monotonic_ns(NULL);
    w->last_pass_ns = watch_now(w, t0);
    (void)pass(w, w->fill, w->ctx, t0);
    if (w->monitor != NULL) {
        uint64_t t1 = roz_clock_monotonic_ns(NULL);
        roz_monitor_record(w->monitor, ROZ_MON_COMMAND_WRITER, t1 - t0, t1);
    }
}

static struct timespec to_timespec(uint64_t ns)
{
    struct timespec ts = { (time_t)(ns / NS_PER_S), (long)(ns % NS_PER_S) };
    return ts;
}

/* Periodic: wait for the deadline on the semaphore, so a stop wakes the
 * thread at once; a post in periodic mode only comes from stop. */
static void run_periodic(roz_dds_writer_t *w)
{
    uint64_t next = roz_clock_monotonic_ns(NULL) + w->period_ns;

    while (!atomic_load_explicit(&w->stop, memory_order_acquire)) {
        struct timespec ts = to_timespec(next);
        int rc = sem_clockwait(wake_sem(w), CLOCK_MONOTONIC, &ts);
        if (rc == 0 || errno == EINTR)
            continue; /* stop (or a stray post): look at the flag */
        uint64_t woke = roz_clock_monotonic_ns(NULL);
        if (w->monitor != NULL)
            roz_monitor_periodic(w->monitor, woke);
        timed_pass(w);
        next += w->period_ns;
        uint64_t done = roz_clock_monotonic_ns(NULL);
        if (done > next + w->period_ns) {
            /* far behind: count it and go on from now, no burst */
            atomic_fetch_add_explicit(&w->missed, 1u, memory_order_relaxed);
            next = done + w->period_ns;
        }
    }
}

/* When an event-driven writer must pass without a post, on the watchdog's
 * clock: the watchdog's expiry of the last frame sent, or the safe
 * command's next repeat while tripped; UINT64_MAX: not before a post. A
 * deadline a wait already timed out at (a pass that did not judge a frame
 * leaves it as it was) is not waited for again. */
static uint64_t next_due(roz_dds_writer_t *w)
{
    if (w->watchdog == NULL)
        return UINT64_MAX;
    uint64_t due = roz_cmd_watchdog_next_ns(w->watchdog);
    if (due == 0)
        return w->last_pass_ns + w->repeat_ns;
    return due == w->fired_due ? UINT64_MAX : due;
}

/* Whether the tick posted a frame the writer has not passed for. */
static int posted(roz_dds_writer_t *w)
{
    return atomic_load_explicit(&w->posts, memory_order_acquire) != w->handled;
}

static int heads_up(roz_dds_writer_t *w)
{
    return atomic_load_explicit(&w->expects, memory_order_acquire) != w->expected;
}

/* The monotonic deadline to sleep until for @p due on the watchdog's clock:
 * @p due itself where the watchdog counts on the monotonic clock; else as
 * far off in real time as @p due is on that clock now (a test's clock,
 * which stands still, is looked at again that late, or when the test
 * wakes the writer after moving it: roz_dds_writer_nudge()). */
static uint64_t real_deadline(const roz_dds_writer_t *w, uint64_t due)
{
    if (due == UINT64_MAX || w->clock == roz_clock_monotonic_ns)
        return due;
    uint64_t now = w->clock(w->clock_ctx), mono = roz_clock_monotonic_ns(NULL);
    uint64_t left = due > now ? due - now : 0;
    return left > UINT64_MAX - 1u - mono ? UINT64_MAX - 1u : mono + left;
}

/* Sleep on the semaphore until a post, a heads-up or @p due (UINT64_MAX:
 * no deadline; else on the monotonic clock: real_deadline()). `sleeping`
 * is set before the last look at the counters and the wakers add before
 * they look at it (both sequentially consistent), so a post is never slept
 * through. */
static void sleep_until(roz_dds_writer_t *w, uint64_t due)
{
    atomic_store(&w->sleeping, 1);
    if (atomic_load(&w->posts) == w->handled && atomic_load(&w->expects) == w->expected &&
        !atomic_load(&w->stop)) {
        if (due == UINT64_MAX) {
            while (sem_wait(wake_sem(w)) != 0)
                ; /* EINTR */
        } else {
            struct timespec ts = to_timespec(due);
            while (sem_clockwait(wake_sem(w), CLOCK_MONOTONIC, &ts) != 0 && errno == EINTR)
                ;
        }
    }
    atomic_store(&w->sleeping, 0);
    while (sem_trywait(wake_sem(w)) == 0)
        ; /* posts that piled up: the counters say what is new */
}

/* Whether @p due (the watchdog's clock) has come, given the monotonic
 * clock's @p mono. */
static int is_due(const roz_dds_writer_t *w, uint64_t due, uint64_t mono)
{
    return due != UINT64_MAX && watch_now(w, mono) >= due;
}

/* Event-driven: each new post is a frame to publish; posts that piled up
 * while a pass ran are one pass (it publishes the latest frame). With a
 * watchdog, a pass is also due when the watchdog is (on its clock: only
 * the sleeps are on the monotonic one), however the writer got there
 * (asleep, or spinning on heads-ups that keep coming while the tick is
 * silent). With spin_ns, a heads-up (a state frame arrived: the
 * tick's command follows) wakes the writer while the tick runs, and it
 * spins, yielding the CPU, until the post comes, spin_ns passes or the
 * watchdog is due, so the tick's post costs no wake-up. */
static void run_events(roz_dds_writer_t *w)
{
    for (;;) {
        uint64_t due = next_due(w);
        if (!posted(w))
            sleep_until(w, real_deadline(w, due));
        if (atomic_load_explicit(&w->stop, memory_order_acquire))
            return;
        if (!posted(w) && heads_up(w)) {
            w->expected = atomic_load_explicit(&w->expects, memory_order_acquire);
            uint64_t mono = roz_clock_monotonic_ns(NULL), until = mono + w->spin_ns;
            while (!posted(w) && !atomic_load_explicit(&w->stop, memory_order_relaxed) &&
                   mono < until && !is_due(w, due, mono)) {
                sched_yield();
                mono = roz_clock_monotonic_ns(NULL);
            }
        }
        if (posted(w))
            w->handled = atomic_load_explicit(&w->posts, memory_order_acquire);
        else if (is_due(w, due, roz_clock_monotonic_ns(NULL)))
            w->fired_due = due; /* the watchdog's pass */
        else
            continue; /* a heads-up with no command after it, or a stray post */
        timed_pass(w);
    }
}

static void *writer_main(void *arg)
{
    roz_dds_writer_t *w = arg;
    if (w->period_ns != 0)
        run_periodic(w);
    else
        run_events(w);
    return NULL;
}

/* ---- public -------------------------------------------------------------- */

int roz_dds_writer_open(roz_dds_writer_t *w, const roz_dds_participant_t *p, const char *topic,
                        const void *descriptor, const roz_dds_qos_t *qos, void *storage,
                        size_t size, char *err, size_t errlen)
{
    memset(w, 0, sizeof *w);
    atomic_init(&w->stop, 0);
    atomic_init(&w->running, 0);
    atomic_init(&w->passes, 0u);
    atomic_init(&w->done, 0u);
    atomic_init(&w->published, 0u);
    atomic_init(&w->errors, 0u);
    atomic_init(&w->missed, 0u);
    atomic_init(&w->posts, 0u);
    atomic_init(&w->expects, 0u);
    atomic_init(&w->sleeping, 0);
    atomic_init(&w->spin_on, 0);
    w->clock = roz_clock_monotonic_ns;
    if (p == NULL || p->participant <= 0 || topic == NULL || descriptor == NULL || qos == NULL ||
        storage == NULL || size == 0) {
        roz__dds_say(err, errlen, topic != NULL ? topic : "?", "writer", DDS_RETCODE_BAD_PARAMETER);
        return ROZ_EINVAL;
    }
    w->sample = storage;
    w->sample_size = size;
    if (sem_init(wake_sem(w), 0, 0) != 0) {
        roz__dds_say(err, errlen, topic, "writer", DDS_RETCODE_OUT_OF_RESOURCES);
        return ROZ_ENOSPC;
    }
    w->wake_ready = 1;
    dds_entity_t t = dds_create_topic(p->participant, descriptor, topic, NULL, NULL);
    if (t < 0) {
        roz__dds_say(err, errlen, topic, "no topic", t);
        roz_dds_writer_close(w);
        return roz__dds_error(t);
    }
    w->topic = t;
    dds_qos_t *q = roz__dds_qos(qos);
    if (q == NULL) {
        roz__dds_say(err, errlen, topic, "writer", DDS_RETCODE_OUT_OF_RESOURCES);
        roz_dds_writer_close(w);
        return ROZ_ENOSPC;
    }
    /* a stopped port's last command must not be disposed under the robot */
    dds_qset_writer_data_lifecycle(q, false);
    dds_entity_t wr = dds_create_writer(p->participant, t, q, NULL);
    dds_delete_qos(q);
    if (wr < 0) {
        roz__dds_say(err, errlen, topic, "no writer", wr);
        roz_dds_writer_close(w);
        return roz__dds_error(wr);
    }
    w->writer = wr;
    return ROZ_OK;
}

int roz_dds_writer_start(roz_dds_writer_t *w, uint32_t period_us, roz_dds_fill_fn fill,
                         void *ctx, roz_monitor_t *monitor)
{
    if (w->writer <= 0 || fill == NULL ||
        (period_us != 0 && (period_us < ROZ_DDS_MIN_PERIOD_US || period_us > ROZ_DDS_MAX_PERIOD_US)))
        return ROZ_EINVAL;
    if (atomic_load(&w->running))
        return ROZ_ESTATE;
    w->fill = fill;
    w->ctx = ctx;
    w->monitor = monitor;
    w->period_ns = (uint64_t)period_us * 1000u;
    w->expected = atomic_load(&w->expects); /* a heads-up from before is no news */
    atomic_store(&w->stop, 0);
    w->thread_err[0] = '\0';
    int rc = roz_thread_start(&w->thread, &w->thread_cfg, "command_writer", writer_main, w,
                              w->thread_err, sizeof w->thread_err);
    if (rc != ROZ_OK)
        return rc;
    atomic_store(&w->running, 1);
    atomic_store_explicit(&w->spin_on, w->period_ns == 0 && w->spin_ns != 0,
                          memory_order_release);
    return ROZ_OK;
}

int roz_dds_writer_spin(roz_dds_writer_t *w, uint32_t spin_us)
{
    if (spin_us > ROZ_DDS_MAX_SPIN_US)
        return ROZ_EINVAL;
    if (atomic_load(&w->running))
        return ROZ_ESTATE;
    w->spin_ns = (uint64_t)spin_us * 1000u;
    return ROZ_OK;
}

int roz_dds_writer_watch(roz_dds_writer_t *w, const roz_cmd_watchdog_t *wd, uint32_t repeat_us,
                         uint64_t (*clock)(void *ctx), void *clock_ctx)
{
    if (wd == NULL || repeat_us == 0)
        return ROZ_EINVAL;
    if (atomic_load(&w->running))
        return ROZ_ESTATE;
    w->watchdog = wd;
    w->repeat_ns = (uint64_t)repeat_us * 1000u;
    w->clock = clock != NULL ? clock : roz_clock_monotonic_ns;
    w->clock_ctx = clock_ctx;
    w->fired_due = 0;
    return ROZ_OK;
}

void roz_dds_writer_wake(roz_dds_writer_t *w)
{
    if (w->period_ns != 0 || !w->wake_ready)
        return;
    atomic_fetch_add(&w->posts, 1u);
    if (atomic_load(&w->sleeping))
        (void)sem_post(wake_sem(w));
}

void roz_dds_writer_nudge(roz_dds_writer_t *w)
{
    if (w->period_ns != 0 || !w->wake_ready)
        return;
    (void)sem_post(wake_sem(w)); /* no post counted: a look at the clock, no frame */
}

void roz_dds_writer_expect(roz_dds_writer_t *w)
{
    /* the receive path may run before the writer starts: one atomic says
     * whether there is a spinning writer to tell */
    if (!atomic_load_explicit(&w->spin_on, memory_order_acquire))
        return;
    atomic_fetch_add(&w->expects, 1u);
    if (atomic_load(&w->sleeping))
        (void)sem_post(wake_sem(w));
}

int roz_dds_writer_publish(roz_dds_writer_t *w, roz_dds_fill_fn fill, void *ctx)
{
    if (atomic_load(&w->running))
        return ROZ_ESTATE;
    if (w->writer <= 0 || fill == NULL)
        return ROZ_EINVAL;
    return pass(w, fill, ctx, roz_clock_monotonic_ns(NULL));
}

int roz_dds_writer_flush(roz_dds_writer_t *w, uint32_t timeout_ms)
{
    if (w->writer <= 0)
        return ROZ_OK;
    dds_return_t rc = dds_wait_for_acks(w->writer, DDS_MSECS((int64_t)timeout_ms));
    return rc == DDS_RETCODE_OK ? ROZ_OK : roz__dds_error(rc);
}

int roz_dds_writer_publish_final(roz_dds_writer_t *w, roz_dds_fill_fn fill, void *ctx)
{
    const unsigned n = ROZ_DDS_SHUTDOWN_REPEAT_MS * 1000u / ROZ_DDS_SHUTDOWN_REPEAT_US;
    uint64_t next = roz_clock_monotonic_ns(NULL);
    int best = ROZ_EIO;

    for (unsigned i = 0; i < n; i++) {
        int rc = roz_dds_writer_publish(w, fill, ctx);
        if (rc == ROZ_ESTATE || rc == ROZ_EINVAL || rc == 0)
            return rc; /* running, not open, or nothing to send: no repeat helps */
        if (rc == 1)
            best = 1;
        next += (uint64_t)ROZ_DDS_SHUTDOWN_REPEAT_US * 1000u;
        struct timespec ts = to_timespec(next);
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
            ;
    }
    if (best == 1)
        (void)roz_dds_writer_flush(w, ROZ_DDS_SHUTDOWN_FLUSH_MS);
    return best;
}

uint32_t roz_dds_writer_matched(const roz_dds_writer_t *w)
{
    dds_publication_matched_status_t st;
    if (w->writer <= 0 || dds_get_publication_matched_status(w->writer, &st) != DDS_RETCODE_OK)
        return 0;
    return st.current_count;
}

void roz_dds_writer_set_thread(roz_dds_writer_t *w, const roz_thread_config_t *cfg)
{
    memset(&w->thread_cfg, 0, sizeof w->thread_cfg);
    if (cfg != NULL)
        w->thread_cfg = *cfg;
}

const char *roz_dds_writer_thread_error(const roz_dds_writer_t *w)
{
    return w->thread_err;
}

int roz_dds_writer_thread(const roz_dds_writer_t *w, roz_thread_config_t *out)
{
    if (!atomic_load(&w->running))
        return ROZ_ESTATE;
    return roz_thread_describe(w->thread, out);
}

void roz_dds_writer_stop(roz_dds_writer_t *w)
{
    if (!atomic_load(&w->running))
        return;
    atomic_store_explicit(&w->spin_on, 0, memory_order_release);
    atomic_store_explicit(&w->stop, 1, memory_order_release);
    (void)sem_post(wake_sem(w));
    roz_thread_join(w->thread);
    atomic_store(&w->running, 0);
}

void roz_dds_writer_close(roz_dds_writer_t *w)
{
    roz_dds_writer_stop(w);
    if (w->writer > 0)
        (void)dds_delete(w->writer);
    if (w->topic > 0)
        (void)dds_delete(w->topic);
    w->writer = 0;
    w->topic = 0;
    if (w->wake_ready)
        (void)sem_destroy(wake_sem(w));
    w->wake_ready = 0;
}
