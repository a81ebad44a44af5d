/* SPDX-License-Identifier: Apache-2.0 */
/* Between the runtime and the recorder (private to the core): the tick
 * pushes its record (the drain words a fault with fault_text.h, as the
 * runtime's readers do). */
#ifndef ROZ_RECORDER_PUSH_H
#define ROZ_RECORDER_PUSH_H

#include <stddef.h>
#include <stdint.h>

#include "roz/recorder.h"

/* The first fault's numbers as the runtime keeps them (runtime.c). */
typedef struct roz__fault_raw {
    unsigned    bit;
    uint32_t    num[4];
    const char *text; /* the controller's or port's text, "" none */
} roz__fault_raw_t;

struct roz_runtime_fault_rec;

/* The tick: push @p rec (its arrays are copied) if decimation or a change
 * says so; the runtime's first-fault record @p first (the tick is its only
 * writer) is copied only when the faults differ from the last record's.
 * Wait-free; a full ring drops and counts. */
void roz__recorder_push(roz_recorder_t *r, const roz_record_t *rec,
                        const struct roz_runtime_fault_rec *first);

#endif /* ROZ_RECORDER_PUSH_H */
