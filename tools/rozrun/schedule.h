/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun's schedule: the interventions given on the command line
 * (--estop-at, --estop-release-at, --stage-at, --clear-at, --swap-at), each
 * at a tick,
 * so every runtime behaviour can be tried without writing a program.
 *
 * Two hands carry them out, as in a real application:
 *  - the e-stop input (press, release) and a stage request (roz/stages.h)
 *    are set by the tick's thread right after tick T-1 (wait-free atomic
 *    stores, as an ISR would), so tick T sees them before its controller
 *    runs;
 *  - clears and swaps run on the loader (rozrun's main thread: they block,
 *    verify and allocate), once tick T-1 is done; each takes effect at the
 *    next tick boundary after it returns.
 * At one tick the e-stop input comes first, then the swap, then the clear
 * (a clear after a swap clears for the new controller instead of rebuilding
 * the old one). In simulated time the loader runs between ticks, so each
 * action takes effect exactly at its tick and a run is deterministic.
 */
#ifndef ROZRUN_SCHEDULE_H
#define ROZRUN_SCHEDULE_H

#include <stddef.h>
#include <stdint.h>

#include "roz/runtime.h"

#define ROZRUN_MAX_ACTIONS 64
/* The longest path rozrun's messages quote whole (Linux's PATH_MAX). */
#define ROZRUN_PATH_MAX 4096

typedef enum rozrun_action_kind {
    /* in the order they are carried out at one tick */
    ROZRUN_ESTOP_PRESS = 0,
    ROZRUN_ESTOP_RELEASE,
    ROZRUN_STAGE, /* --stage-at T:STAGE: roz_runtime_stage_request() */
    ROZRUN_SWAP,
    ROZRUN_CLEAR,
} rozrun_action_kind_t;

typedef struct rozrun_action {
    uint64_t             tick;
    rozrun_action_kind_t kind;
    const char          *file; /* SWAP: the controller's path */
    int                  stage; /* STAGE: the roz_stage_t asked for */
    uint8_t             *wasm; /* SWAP: its bytes, read at start-up */
    size_t               len;
} rozrun_action_t;

/* What the interventions did, for the summary (written by the hand that
 * carries each out: inputs by the tick's thread, the rest by the loader). */
typedef struct rozrun_schedule_counts {
    uint64_t presses, releases, stages;
    uint64_t clears, clears_held, clears_refused;
    uint64_t swaps, swaps_refused, rebuilds;
} rozrun_schedule_counts_t;

typedef struct rozrun_schedule {
    rozrun_action_t a[ROZRUN_MAX_ACTIONS]; /* sorted by tick, then kind */
    size_t          n;
    size_t          next_input;  /* tick's thread: the next e-stop action */
    size_t          next_loader; /* loader: the next clear or swap */
    rozrun_schedule_counts_t in, ld; /* by the tick's thread, by the loader */
    int             simulated;   /* 1: the loader runs between ticks (messages say so) */
} rozrun_schedule_t;

/* Adds one option's value ("TICK", "TICK:FILE" for --swap-at, "TICK:STAGE"
 * for --stage-at: move, run, stop or zero). 0, or
 * -1 with a message on stderr naming the option and value. */
int rozrun_schedule_add(rozrun_schedule_t *s, const char *opt, const char *value);

/* Sorts and checks the whole schedule against a run of @p ticks ticks
 * (0: until interrupted): every tick inside the run, no swap at tick 0, no
 * action twice at a tick, a press only while released and a release only
 * while pressed. 0, or -1 with a message on stderr. */
int rozrun_schedule_check(rozrun_schedule_t *s, uint64_t ticks);

/* Reads every --swap-at controller (start-up: before the robot moves).
 * 0, or -1 with a message on stderr. */
int rozrun_schedule_read_modules(rozrun_schedule_t *s);

/* Tick's thread, after tick T-1 (T = 0: before the first tick): sets the
 * e-stop input for tick T. Returns the trace events (ROZRUN_EV_*). */
unsigned rozrun_schedule_inputs(rozrun_schedule_t *s, roz_runtime_t *rt, uint64_t tick);

/* Loader: whether a clear or swap is due once @p done ticks have run. */
int rozrun_schedule_loader_due(const rozrun_schedule_t *s, uint64_t done);

/* Loader: carries out the clears and swaps due once @p done ticks have
 * run, says on stderr what each did, and returns the trace events. */
unsigned rozrun_schedule_loader(rozrun_schedule_t *s, roz_runtime_t *rt, uint64_t done);

/* Actions not carried out (the run ended or was interrupted first); call
 * once the tick's thread has stopped. */
size_t rozrun_schedule_left(const rozrun_schedule_t *s);

/* A line for the summary ("" when nothing was scheduled). */
void rozrun_schedule_summary(const rozrun_schedule_t *s, char *buf, size_t len);

/* Frees the controllers' bytes (after the runtime let go of them). */
void rozrun_schedule_free(rozrun_schedule_t *s);

#endif /* ROZRUN_SCHEDULE_H */
