/* SPDX-License-Identifier: Apache-2.0 */
#include "support_heap.h"

#include <stdatomic.h>
#include <stdlib.h>

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);
void *__wrap_malloc(size_t n);
void *__wrap_calloc(size_t n, size_t size);
void *__wrap_realloc(void *p, size_t n);
void __wrap_free(void *p);

static _Atomic int counting;
static _Atomic uint64_t allocations, frees;

void *__wrap_malloc(size_t n)
{
    if (atomic_load(&counting))
        atomic_fetch_add(&allocations, 1u);
    return __real_malloc(n);
}

void *__wrap_calloc(size_t n, size_t size)
{
    if (atomic_load(&counting))
        atomic_fetch_add(&allocations, 1u);
    return __real_calloc(n, size);
}

void *__wrap_realloc(void *p, size_t n)
{
    if (atomic_load(&counting))
        atomic_fetch_add(&allocations, 1u);
    return __real_realloc(p, n);
}

void __wrap_free(void *p)
{
    if (p != NULL && atomic_load(&counting))
        atomic_fetch_add(&frees, 1u);
    __real_free(p);
}

void roz_heap_count_start(void)
{
    atomic_store(&allocations, 0u);
    atomic_store(&frees, 0u);
    atomic_store(&counting, 1);
}

void roz_heap_count_stop(void)
{
    atomic_store(&counting, 0);
}

uint64_t roz_heap_allocations(void)
{
    return atomic_load(&allocations);
}

uint64_t roz_heap_frees(void)
{
    return atomic_load(&frees);
}
