/* SPDX-License-Identifier: Apache-2.0 */
/* The heap counted: malloc, calloc, realloc and free wrapped at link time
 * (-Wl,--wrap=...; roz_count_heap() in cmake/RozHeapCount.cmake), which
 * covers roz and the statically linked wasm3, and counted while counting is
 * on, on every thread. (Not in the sanitizer builds, whose runtimes own
 * malloc.) */
#ifndef ROZ_TEST_SUPPORT_HEAP_H
#define ROZ_TEST_SUPPORT_HEAP_H

#include <stdint.h>

/* Zero the counts and count from now on. */
void roz_heap_count_start(void);

/* Stop counting; the counts stay as they are. */
void roz_heap_count_stop(void);

/* malloc, calloc and realloc calls counted. */
uint64_t roz_heap_allocations(void);

/* free calls counted (of a pointer, not NULL). */
uint64_t roz_heap_frees(void);

#endif /* ROZ_TEST_SUPPORT_HEAP_H */
