/* SPDX-License-Identifier: Apache-2.0 */
/* No heap on the tick thread, with a hardware port's threads and Cyclone's
 * busy around it: every allocation of the process is seen (libc_heap.h),
 * Cyclone's in its shared library included, and those made on the tick
 * thread while it ticks are counted. Cyclone's own threads may allocate;
 * the tick thread may not. (Not in the sanitizer builds, whose runtimes
 * own malloc.) */
#ifndef ROZ_TEST_ALLOC_TICKS_H
#define ROZ_TEST_ALLOC_TICKS_H

#include <stdint.h>

#include "roz/manifest.h"
#include "roz/port.h"

/* What a port counted (read through its own counters). */
typedef struct roz_alloc_port_counts {
    uint64_t received;  /* state samples or frames taken in by its receive path */
    uint64_t frames;    /* fresh frames read by the tick */
    uint64_t writes;    /* write() calls */
    uint64_t published; /* command samples or passes published */
} roz_alloc_port_counts_t;

/* One run: @p ticks ticks of @p controller on @p m through @p port (opened
 * and active, against a robot that publishes by itself), back to back on a
 * thread of their own after one uncounted tick (the controller's swap-in),
 * once the port has received 10 samples; half-way, @p midway() from the
 * caller's thread, which must latch @p fault. Asserted: no allocation and no
 * free on the tick thread while it ticked; the port and Cyclone's threads
 * busy meanwhile; the controller ran; @p fault latched. The caller closes
 * the port. */
typedef struct roz_alloc_case {
    const roz_manifest_t *m;
    roz_port_t            port;
    const char           *controller;
    int                   ticks;
    void                (*counters)(roz_alloc_port_counts_t *out);
    void                (*midway)(void);
    uint32_t              fault;
} roz_alloc_case_t;

void roz_alloc_run(const roz_alloc_case_t *c);

#endif /* ROZ_TEST_ALLOC_TICKS_H */
