/* SPDX-License-Identifier: Apache-2.0 */
#define _GNU_SOURCE
#include "alloc_ticks.h"

#include <errno.h>
#include <malloc.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>
#include <time.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/runtime.h"
#include "support.h"

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

typedef struct {
    int         ticks;
    _Atomic int done;
} run_t;

static void *tick_main(void *arg)
{
    run_t *r = arg;
    int rc = roz_runtime_tick(&rt); /* the controller's swap-in, before counting */
    on_tick = 1;
    for (int t = 0; t < r->ticks; t++) {
        rc = roz_runtime_tick(&rt); /* ROZ_EFAULT once a fault latched */
        atomic_store_explicit(&r->done, t + 1, memory_order_release);
    }
    on_tick = 0;
    (void)rc;
    return NULL;
}

static void sleep_1ms(void)
{
    struct timespec ts = { 0, 1000000L };
    while (nanosleep(&ts, &ts) != 0)
        ;
}

void roz_alloc_run(const roz_alloc_case_t *c)
{
    static run_t r;
    roz_runtime_config_t cfg;
    roz_alloc_port_counts_t c0, c1;
    pthread_t th;
    size_t len;

    const uint8_t *w = roz_test_controller(c->controller, &len);
    roz_runtime_config_default(&cfg);
    cfg.manifest = c->m;
    cfg.port = c->port;
    cfg.stale_ticks = 10u * (uint32_t)c->ticks; /* back to back: most reads are not fresh */
    cfg.monitor_jitter = 0;
    assert_int_equal(roz_runtime_init(&rt, &cfg), ROZ_OK);
    assert_int_equal(roz_runtime_load(&rt, w, len, NULL), ROZ_OK);
    assert_int_equal(roz_runtime_start(&rt), ROZ_OK);
    /* the robot's samples arrive */
    for (int i = 0; i < 10000; i++) {
        c->counters(&c0);
        if (c0.received >= 10)
            break;
        sleep_1ms();
    }
    assert_true(c0.received >= 10);

    /* the counters themselves: an allocation made while ticking is seen */
    atomic_store(&tick_allocations, 0u);
    atomic_store(&tick_frees, 0u);
    on_tick = 1;
    void *volatile probe = malloc(8);
    free(probe);
    on_tick = 0;
    assert_int_equal(atomic_load(&tick_allocations), 1);
    assert_int_equal(atomic_load(&tick_frees), 1);

    r.ticks = c->ticks;
    atomic_store(&r.done, 0);
    atomic_store(&tick_allocations, 0u);
    atomic_store(&tick_frees, 0u);
    atomic_store(&other_allocations, 0u);
    assert_int_equal(pthread_create(&th, NULL, tick_main, &r), 0);
    while (atomic_load_explicit(&r.done, memory_order_acquire) < c->ticks / 2)
        sleep_1ms();
    c->midway();
    assert_int_equal(pthread_join(th, NULL), 0);

    uint64_t allocs = atomic_load(&tick_allocations), frees = atomic_load(&tick_frees);
    uint64_t others = atomic_load(&other_allocations);
    c->counters(&c1);
    print_message("%s through %s: %d ticks: %llu allocations and %llu frees on the tick thread; "
                  "%llu elsewhere (Cyclone's threads, the test); %llu frames in, %llu "
                  "published\n",
                  c->m->robot_id, c->port.ops->name, c->ticks, (unsigned long long)allocs,
                  (unsigned long long)frees, (unsigned long long)others,
                  (unsigned long long)(c1.frames - c0.frames), (unsigned long long)c1.published);
    assert_int_equal(allocs, 0);
    assert_int_equal(frees, 0);
    /* the port was busy meanwhile, and so was Cyclone */
    assert_true(c1.frames - c0.frames > 10);
    assert_true(c1.writes >= (uint64_t)c->ticks);
    assert_true(c1.published > 100);
    assert_true(others > 0);
    roz_runtime_stats_t rs;
    assert_int_equal(roz_runtime_stats(&rt, &rs), ROZ_OK);
    assert_true(rs.runtime.controller_ticks > (uint64_t)c->ticks / 4);
    assert_true(roz_runtime_faults(&rt) & c->fault);
    roz_runtime_deinit(&rt);
}
