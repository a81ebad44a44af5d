/* SPDX-License-Identifier: Apache-2.0 */
/* Every allocation of the process seen: libc_heap.c defines malloc, calloc,
 * realloc, free and the aligned allocators over glibc's own (__libc_*), so
 * a shared library's calls (Cyclone's, libmujoco's) are seen as well as
 * roz's (test/support_heap.h wraps only what is linked statically). It
 * counts in one of two ways, for the two kinds of test:
 *  - the calling thread while it counts (roz_libc_heap_count_thread()):
 *    the tick thread amid a port's and Cyclone's busy threads
 *    (alloc_ticks.c);
 *  - every thread while counting is on (roz_libc_heap_count_all()): a port
 *    with no threads of its own (test_mujoco_alloc.c).
 * Not in the sanitizer builds, whose runtimes own malloc. */
#ifndef ROZ_TEST_LIBC_HEAP_H
#define ROZ_TEST_LIBC_HEAP_H

#include <stdint.h>

typedef struct roz_libc_heap_counts {
    uint64_t allocations; /* counted malloc, calloc, realloc and aligned calls */
    uint64_t frees;       /* counted free() calls of a pointer (not NULL) */
    uint64_t others;      /* allocations made while not counting */
    uint64_t total;       /* every allocation since the process started */
} roz_libc_heap_counts_t;

/* Count the calling thread's calls from now on (1), or stop (0). */
void roz_libc_heap_count_thread(int on);

/* Count every thread's calls from now on (1), or stop (0). */
void roz_libc_heap_count_all(int on);

/* allocations, frees and others back to 0 (total goes on). */
void roz_libc_heap_reset(void);

roz_libc_heap_counts_t roz_libc_heap_counts(void);

#endif /* ROZ_TEST_LIBC_HEAP_H */
