/* SPDX-License-Identifier: Apache-2.0 */
/* No heap on the tick thread, with a hardware port's threads and Cyclone's
 * busy around it: alloc_ticks.c defines malloc, calloc, realloc, free and
 * the aligned allocators over glibc's own (__libc_*), so every allocation
 * of the process is seen, Cyclone's in its shared library included, and
 * counts those made on the tick thread while it ticks. Cyclone's own
 * threads may allocate; the tick thread may not. (Not in the sanitizer
 * builds, whose runtimes own malloc.) */
#ifndef ROZ_TEST_ALLOC_TICKS_H
#define ROZ_TEST_ALLOC_TICKS_H

#include <stdint.h>

#include "roz/runtime.h"

typedef struct roz_alloc_counts {
    uint64_t tick_allocations; /* on the tick thread while it ticked */
    uint64_t tick_frees;
    uint64_t other_allocations; /* every other thread meanwhile */
} roz_alloc_counts_t;

/* Runs @p ticks ticks of @p rt back to back on a thread of its own, after
 * one uncounted tick (the controller's swap-in); half-way, calls
 * @p midway(@p ctx) from the caller's thread. The counts of the run; 0, or
 * -1 when no thread could be made. */
int roz_alloc_ticks(roz_runtime_t *rt, int ticks, void (*midway)(void *ctx), void *ctx,
                    roz_alloc_counts_t *out);

#endif /* ROZ_TEST_ALLOC_TICKS_H */
