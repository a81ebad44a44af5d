/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun's trace: rows of doubles handed from the tick to a writer thread
 * through a wait-free single-producer single-consumer ring, written as CSV.
 * A full ring drops the row and counts it; the tick never blocks on I/O. */
#ifndef ROZRUN_TRACE_H
#define ROZRUN_TRACE_H

#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>

#include "roz/manifest.h"

typedef struct rozrun_trace {
    FILE                *out;
    const roz_manifest_t *m;
    size_t               width;    /* doubles per row */
    size_t               capacity; /* rows, a power of two */
    double              *rows;     /* capacity * width, allocated at open */
    atomic_size_t        head;     /* producer */
    atomic_size_t        tail;     /* consumer */
    uint64_t             dropped;  /* producer */
    uint64_t             written;  /* consumer */
} rozrun_trace_t;

/* Opens path and writes the header; allocates the ring. 0 or -1 (errno-free
 * message in err). */
int rozrun_trace_open(rozrun_trace_t *t, const char *path, const roz_manifest_t *m, char *err,
                      size_t errlen);
/* Producer: one row: tick, time, targets (NaN without a controller),
 * applied commands, state. */
void rozrun_trace_push(rozrun_trace_t *t, uint64_t tick, double time_s, const double *targets,
                       const double *applied, const double *state);
/* Consumer: writes every queued row. */
void rozrun_trace_drain(rozrun_trace_t *t);
/* Drains, closes, frees. */
int rozrun_trace_close(rozrun_trace_t *t);

#endif /* ROZRUN_TRACE_H */
