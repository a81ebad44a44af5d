/* SPDX-License-Identifier: Apache-2.0 */
/* No heap on the tick thread with a ROS 2 port active: 100,000 ticks of the
 * robot's stand controller through engineai/PM01 (and agibot/X2) against
 * the fake robot (publishing every state topic every 2 ms), the port's
 * writer event-driven (every write wakes it) and Cyclone's threads
 * receiving and sending meanwhile, the samples' sequences and strings
 * filled in place. Half-way the robot restarts (the PM01: LINK, the hold
 * again) or reports an error state (the X2: ROBOT), so the fault paths run
 * too.
 *
 * malloc, calloc, realloc, free and the aligned allocators are defined
 * here, over glibc's own (__libc_*), so every allocation of the process is
 * seen, Cyclone's in its shared library included; those made on the tick
 * thread while it ticks are counted. Cyclone's own threads may allocate;
 * the tick thread may not. (Not in the sanitizer builds, whose runtimes own
 * malloc.) The ticks run back to back, not at 500 Hz: most read no fresh
 * frame, so stale_ticks is set past the run. */
#define _GNU_SOURCE
#include <errno.h>
#include <malloc.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../support.h"
#include "engineai_pm01_manifest.h"
#include "port_fixture.h"
#include "ros2_fixture.h"
#include "roz/runtime.h"
#ifdef ROZ_TEST_HAVE_AGIBOT_X2
#include "agibot_x2_manifest.h"
#endif

#define TICKS 100000

/* ---- every allocation of the process ------------------------------------------ */

void *__libc_malloc(size_t n);
void *__libc_calloc(size_t n, size_t size);
void *__libc_realloc(void *p, size_t n);
void *__libc_memalign(size_t align, size_t n);
void __libc_free(void *p);

static _Thread_local int on_tick; /* this thread is the tick, ticking */
static _Atomic uint64_t tick_allocations, tick_frees, other_allocations;

static void count(void)
{
    if (on_tick)
        atomic_fetch_add_explicit(&tick_allocations, 1u, memory_order_relaxed);
    else
        atomic_fetch_add_explicit(&other_allocations, 1u, memory_order_relaxed);
}

void *malloc(size_t n)
{
    count();
    return __libc_malloc(n);
}

void *calloc(size_t n, size_t size)
{
    count();
    return __libc_calloc(n, size);
}

void *realloc(void *p, size_t n)
{
    count();
    return __libc_realloc(p, n);
}

void *memalign(size_t align, size_t n)
{
    count();
    return __libc_memalign(align, n);
}

void *aligned_alloc(size_t align, size_t n)
{
    count();
    return __libc_memalign(align, n);
}

int posix_memalign(void **out, size_t align, size_t n)
{
    count();
    void *p = __libc_memalign(align, n);
    if (p == NULL)
        return ENOMEM;
    *out = p;
    return 0;
}

void free(void *p)
{
    if (on_tick && p != NULL)
        atomic_fetch_add_explicit(&tick_frees, 1u, memory_order_relaxed);
    __libc_free(p);
}

/* ---- the run -------------------------------------------------------------------- */

static roz_runtime_t rt;
static _Atomic int ticks_done;

static void *tick_main(void *arg)
{
    (void)arg;
    int rc = roz_runtime_tick(&rt); /* the controller's swap-in, before counting */
    on_tick = 1;
    for (int t = 0; t < TICKS; t++) {
        rc = roz_runtime_tick(&rt); /* ROZ_EFAULT once a fault latched */
        atomic_store_explicit(&ticks_done, t + 1, memory_order_release);
    }
    on_tick = 0;
    (void)rc;
    return NULL;
}

/* @p midway: the fake's request half-way; @p fault: what it latches. */
static void run(const roz_port_fixture_t *fx, const roz_manifest_t *m, const char *controller,
                const char *midway, unsigned fault)
{
    roz_runtime_config_t cfg;
    roz_port_t port;
    pthread_t th;
    size_t len;
    char err[300] = "";

    atomic_store(&tick_allocations, 0u);
    atomic_store(&tick_frees, 0u);
    atomic_store(&ticks_done, 0);
    static const char *const periodic[] = { "--period-us", "2000", NULL };
    roz_ros2fx_set_fake_args(periodic);
    if (fx->open(m, NULL, &port, err, sizeof err) != ROZ_OK)
        fail_msg("open: %s", err);

    const uint8_t *w = roz_test_controller(controller, &len);
    roz_runtime_config_default(&cfg);
    cfg.manifest = m;
    cfg.port = port;
    cfg.stale_ticks = 10u * TICKS; /* back to back: most reads are not fresh */
    cfg.monitor_jitter = 0;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    roz_ros2_counters_t c0;
    for (int i = 0; i < 10000; i++) {
        roz_ros2_counters(roz_ros2fx_bridge(), &c0);
        if (c0.topic[0].samples >= 10)
            break;
        roz_fake_sleep_ms(1);
    }
    assert_true(c0.topic[0].samples >= 10);

    assert_int_equal(pthread_create(&th, NULL, tick_main, NULL), 0);
    while (atomic_load_explicit(&ticks_done, memory_order_acquire) < TICKS / 2)
        roz_fake_sleep_ms(1);
    roz_ros2fx_ask("%s", midway);
    assert_int_equal(pthread_join(th, NULL), 0);

    roz_ros2_counters_t c;
    roz_ros2_counters(roz_ros2fx_bridge(), &c);
    print_message("%s: %d ticks: %llu allocations and %llu frees on the tick thread; %llu "
                  "elsewhere (Cyclone's threads, the test); %llu frames in, %llu passes out\n",
                  m->robot_id, TICKS, (unsigned long long)atomic_load(&tick_allocations),
                  (unsigned long long)atomic_load(&tick_frees),
                  (unsigned long long)atomic_load(&other_allocations),
                  (unsigned long long)(c.frames - c0.frames), (unsigned long long)c.published);
    assert_int_equal(atomic_load(&tick_allocations), 0);
    assert_int_equal(atomic_load(&tick_frees), 0);
    /* the port was busy meanwhile, and so was Cyclone */
    assert_true(c.frames - c0.frames > 10);
    assert_true(c.writes >= TICKS);
    assert_true(c.published > 100);
    assert_true(atomic_load(&other_allocations) > 0);
    roz_runtime_stats_t rs;
    assert_int_equal(roz_runtime_stats(&rt, &rs), ROZ_OK);
    assert_true(rs.runtime.controller_ticks > TICKS / 4);
    assert_true(roz_runtime_faults(&rt) & fault);
    roz_runtime_deinit(&rt);
    fx->close();
}

static void test_alloc_engineai_pm01(void **st)
{
    (void)st;
    run(&roz_fixture_engineai_pm01, &roz_manifest_engineai_pm01, "pm01_stand", "restart",
        ROZ_FAULT_LINK);
}

#ifdef ROZ_TEST_HAVE_AGIBOT_X2
static void test_alloc_agibot_x2(void **st)
{
    (void)st;
    run(&roz_fixture_agibot_x2, &roz_manifest_agibot_x2, "x2_stand", "error arm 1",
        ROZ_FAULT_ROBOT);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alloc_engineai_pm01),
#ifdef ROZ_TEST_HAVE_AGIBOT_X2
        cmocka_unit_test(test_alloc_agibot_x2),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
