/* SPDX-License-Identifier: Apache-2.0 */
/* The process's allocator, counted (libc_heap.h). */
#define _GNU_SOURCE
#include "libc_heap.h"

#include <errno.h>
#include <malloc.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>

void *__libc_malloc(size_t n);
void *__libc_calloc(size_t n, size_t size);
void *__libc_realloc(void *p, size_t n);
void *__libc_memalign(size_t align, size_t n);
void __libc_free(void *p);

static _Thread_local int on_thread; /* this thread counts */
static _Atomic int on_all;          /* every thread counts */
static _Atomic uint64_t allocations, frees, others, total;

static int counting(void)
{
    return on_thread || atomic_load_explicit(&on_all, memory_order_relaxed);
}

static void count(void)
{
    atomic_fetch_add_explicit(&total, 1u, memory_order_relaxed);
    if (counting())
        atomic_fetch_add_explicit(&allocations, 1u, memory_order_relaxed);
    else
        atomic_fetch_add_explicit(&others, 1u, memory_order_relaxed);
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
    if (p != NULL && counting())
        atomic_fetch_add_explicit(&frees, 1u, memory_order_relaxed);
    __libc_free(p);
}

void roz_libc_heap_count_thread(int on)
{
    on_thread = on;
}

void roz_libc_heap_count_all(int on)
{
    atomic_store(&on_all, on);
}

void roz_libc_heap_reset(void)
{
    atomic_store(&allocations, 0u);
    atomic_store(&frees, 0u);
    atomic_store(&others, 0u);
}

roz_libc_heap_counts_t roz_libc_heap_counts(void)
{
    roz_libc_heap_counts_t c;
    c.allocations = atomic_load(&allocations);
    c.frees = atomic_load(&frees);
    c.others = atomic_load(&others);
    c.total = atomic_load(&total);
    return c;
}
