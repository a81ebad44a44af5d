/* SPDX-License-Identifier: Apache-2.0 */
/* Between the runtime and the recorder (private to the core): the tick
 * pushes its record (the drain words a fault with fault_text.h, as the
 * runtime's readers do). The recorder knows nothing of the runtime: the
 * runtime hands it the first fault's numbers when it asks for them. */
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

/* The tick: 1 when a record of faults @p faults would carry the first
 * fault (they differ from the last record's), so that the caller passes it
 * to roz__recorder_push(). */
int roz__recorder_wants_fault(const roz_recorder_t *r, uint32_t faults);

/* The tick: push @p rec (its arrays are copied) if decimation or a change
 * says so; @p first, the first fault's numbers and text (NULL: none), is
 * copied only when the faults differ from the last record's
 * (roz__recorder_wants_fault()). Wait-free; a full ring drops and counts. */
void roz__recorder_push(roz_recorder_t *r, const roz_record_t *rec,
                        const roz__fault_raw_t *first);

#endif /* ROZ_RECORDER_PUSH_H */
