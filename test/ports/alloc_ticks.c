/* SPDX-License-Identifier: Apache-2.0 */
#define _GNU_SOURCE
#include "alloc_ticks.h"

#include <errno.h>
#include <malloc.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>
#include <time.h>

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

typedef struct {
    roz_runtime_t *rt;
    int            ticks;
    _Atomic int    done;
} run_t;

static void *tick_main(void *arg)
{
    run_t *r = arg;
    int rc = roz_runtime_tick(r->rt); /* the controller's swap-in, before counting */
    on_tick = 1;
    for (int t = 0; t < r->ticks; t++) {
        rc = roz_runtime_tick(r->rt); /* ROZ_EFAULT once a fault latched */
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

int roz_alloc_ticks(roz_runtime_t *rt, int ticks, void (*midway)(void *ctx), void *ctx,
                    roz_alloc_counts_t *out)
{
    static run_t r;
    pthread_t th;

    r.rt = rt;
    r.ticks = ticks;
    atomic_store(&r.done, 0);
    atomic_store(&tick_allocations, 0u);
    atomic_store(&tick_frees, 0u);
    atomic_store(&other_allocations, 0u);
    if (pthread_create(&th, NULL, tick_main, &r) != 0)
        return -1;
    while (atomic_load_explicit(&r.done, memory_order_acquire) < ticks / 2)
        sleep_1ms();
    midway(ctx);
    (void)pthread_join(th, NULL);
    out->tick_allocations = atomic_load(&tick_allocations);
    out->tick_frees = atomic_load(&tick_frees);
    out->other_allocations = atomic_load(&other_allocations);
    return 0;
}
