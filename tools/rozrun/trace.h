/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun's trace: rows of doubles handed from the tick to a writer thread
 * through a wait-free single-producer single-consumer ring, written as CSV.
 * A full ring drops the row and counts it; the tick never blocks on I/O.
 *
 * Columns: tick, time_s, target:<command>... (roz_runtime_last_targets():
 * what drove the tick, the deploy stage's commands or the controller's
 * targets, as the recording's /roz/target; NaN with neither),
 * applied:<command>..., state:<state>..., input:<input>... (the operator's
 * inputs as the controller read them), when the port has a simulator's
 * floating base's truth (roz_port_truth()) truth:base.x, .y, .z (m), .roll, .pitch, .yaw
 * (rad), then faults (the latched roz_fault_t
 * bits after the tick, a decimal integer), events (what happened at this
 * tick, tokens separated by spaces, empty if nothing: the ROZRUN_EV_* names
 * below, and fault:<name> / cleared:<name> when a fault bit latched or was
 * cleared, <name> being roz_fault_name() with '-' for spaces). */
#ifndef ROZRUN_TRACE_H
#define ROZRUN_TRACE_H

#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>

#include "roz/manifest.h"
#include "roz/port.h"

/* Events of a tick (bits), and their names in the trace. */
enum rozrun_event {
    ROZRUN_EV_ESTOP = 1u << 0,          /* "estop": the e-stop input was pressed */
    ROZRUN_EV_ESTOP_RELEASE = 1u << 1,  /* "estop-release": and released */
    ROZRUN_EV_SWAP = 1u << 2,           /* "swap": another controller drives from here */
    ROZRUN_EV_LOAD_REFUSED = 1u << 3,   /* "load-refused": a swap's module failed to load */
    ROZRUN_EV_VERIFY_REFUSED = 1u << 4, /* "verify-refused": it failed verification */
    ROZRUN_EV_CLEAR = 1u << 5,          /* "clear": the latched faults were cleared */
    ROZRUN_EV_CLEAR_PRESSED = 1u << 6,  /* "clear-while-pressed": all but the e-stop */
    ROZRUN_EV_CLEAR_REFUSED = 1u << 7,  /* "clear-refused": nothing was cleared */
    ROZRUN_EV_REBUILD = 1u << 8,        /* "rebuild": a fresh instance of the controller
                                           that trapped drives from here */
};
#define ROZRUN_EV_COUNT 9

/* The truth columns: base x, y, z (m, world), roll, pitch, yaw (rad). */
#define ROZRUN_TRUTH_VALUES 6

/* The port's truth about a floating base into @p out (ROZRUN_TRUTH_VALUES):
 * 1, or 0 when the port has no truth or the robot no floating base. No heap,
 * no text: the tick calls it. */
int rozrun_trace_truth(const roz_port_t *port, double out[ROZRUN_TRUTH_VALUES]);

typedef struct rozrun_trace {
    FILE                *out;
    const char          *path;
    const roz_manifest_t *m;
    size_t               width;    /* doubles per row */
    int                  truth;    /* 1: the rows carry the truth columns */
    size_t               capacity; /* rows, a power of two */
    double              *rows;     /* capacity * width, allocated at open */
    atomic_size_t        head;     /* producer */
    atomic_size_t        tail;     /* consumer */
    uint64_t             dropped;  /* producer: rows the full ring had no room for */
    uint64_t             written;  /* consumer: rows handed to the file */
    uint64_t             lost;     /* consumer: rows not written after a write failed */
    unsigned             faults;   /* consumer: the previous row's faults */
    char                 error[160]; /* consumer: the first write error, "" none */
} rozrun_trace_t;

/* Opens path and writes the header, with the truth columns when @p truth;
 * allocates the ring. 0 or -1 (errno-free message in err). */
int rozrun_trace_open(rozrun_trace_t *t, const char *path, const roz_manifest_t *m, int truth,
                      char *err, size_t errlen);
/* Producer: one row: tick, time, targets (NaN without a controller),
 * applied commands, state, the truth (ROZRUN_TRUTH_VALUES; NaN when
 * NULL), the latched faults, the tick's events. */
void rozrun_trace_push(rozrun_trace_t *t, uint64_t tick, double time_s, const double *targets,
                       const double *applied, const double *state, const double *truth,
                       unsigned faults, unsigned events);
/* Consumer: writes every queued row. 0, or -1 once a write failed (the
 * first failure is in t->error; rows after it are counted as lost). */
int rozrun_trace_drain(rozrun_trace_t *t);
/* Drains, flushes, closes, frees. 0, or -1 when any write failed (the
 * reason in t->error). */
int rozrun_trace_close(rozrun_trace_t *t);

#endif /* ROZRUN_TRACE_H */
