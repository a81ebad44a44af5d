/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/recorder.h
 * @brief The flight recorder: what every tick did, in a fixed ring the tick
 *        writes and another thread drains.
 *
 * docs/recording.md says what a record holds, how the ring stays off the
 * tick (single producer, single consumer, 32-bit atomics, records dropped
 * and counted when it is full), and decimation (replay needs 1). Storage is
 * the caller's, sized with roz_recorder_slot_bytes().
 */
#ifndef ROZ_RECORDER_H
#define ROZ_RECORDER_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/error.h"
#include "roz/manifest.h"
#include "roz/port.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Flags of a record (roz_record_t.flags). */
enum roz_record_flag {
    ROZ_RECORD_FRESH = 1u << 0,       /**< a fresh state frame was taken this tick */
    ROZ_RECORD_RAN = 1u << 1,         /**< the controller's process() ran */
    ROZ_RECORD_WROTE = 1u << 2,       /**< commands went to the port (a state was known) */
    ROZ_RECORD_TARGETS = 1u << 3,     /**< a controller is installed: target[] is its
                                           targets (else target[] is NaN) */
    ROZ_RECORD_ESTOP_LEVEL = 1u << 4, /**< the e-stop input was pressed at this tick */
    ROZ_RECORD_ESTOP_PRESS = 1u << 5, /**< a press arrived since the last tick */
    ROZ_RECORD_CLEAR = 1u << 6,       /**< a clear was applied (cleared: the bits) */
    ROZ_RECORD_SWAP = 1u << 7,        /**< another controller drives from this tick */
    ROZ_RECORD_FAULT_CHANGED = 1u << 8, /**< the faults differ from the last record's:
                                           fault_message is set */
    ROZ_RECORD_TRUTH = 1u << 9,       /**< the port is a simulator with a truth sample
                                           of this tick: truth is set */
    ROZ_RECORD_STAGE = 1u << 10,      /**< the deploy sequence's stage changed at this
                                           tick, or the tick took a stage request
                                           (stage_request) */
};

/** One tick as the recorder hands it to a drain callback. The pointers are
 *  valid during the callback only. */
typedef struct roz_record {
    uint64_t      tick;            /**< roz_runtime_tick() call, from 0 */
    int64_t       controller_tick; /**< the tick number process() saw; -1: it did not run */
    uint64_t      sim_ns;          /**< tick x the control period */
    uint64_t      wall_ns;         /**< the runtime's clock at the tick's start; 0 none */
    uint64_t      fuel;            /**< fuel process() used (0 when it did not run) */
    uint64_t      process_ns;      /**< process() time, wall clock (0 when it did not run) */
    uint64_t      tick_ns;         /**< the whole tick, wall clock */
    uint64_t      controller_hash; /**< FNV-1a 64 of the driving module's bytes; 0 none */
    uint32_t      faults;          /**< latched roz_fault_t bits after the tick */
    uint32_t      cleared;         /**< the bits a clear cleared at this tick */
    int32_t       read_rc;         /**< the port's read() result (1 fresh, 0, ROZ_E*) */
    uint32_t      flags;           /**< roz_record_flag bits */
    /* the safety filter's counters after this tick, totals since init, as
     * rozrun's summary counts them */
    uint64_t      clamps;          /**< values moved into [min, max], at command.set or
                                        by the filter */
    uint64_t      rate_caps;       /**< values held back by max_rate */
    uint64_t      limit_stops;     /**< values held back by position-limit enforcement */
    uint64_t      nonfinite;       /**< non-finite targets replaced by the safe default */
    const double *state;           /**< n_states: the state the controller and filter saw */
    const double *target;          /**< n_commands: the controller's targets */
    const double *applied;         /**< n_commands: what the filter handed the port */
    const char   *fault_message;   /**< with ROZ_RECORD_FAULT_CHANGED: the first fault's
                                        message ("" when none is latched); else NULL */
    const roz_port_truth_t *truth; /**< with ROZ_RECORD_TRUTH: the simulator's truth
                                        after this tick's read(); else NULL */
    const double *inputs;          /**< n_inputs: the operator's inputs as the controller
                                        read them (states n_states + k), after their
                                        rules; NULL when the manifest has none */
    int32_t       stage;           /**< the deploy sequence's stage after the tick
                                        (roz_stage_t; ROZ_STAGE_NONE without one) */
    int32_t       stage_request;   /**< the stage request (roz_runtime_stage_request())
                                        the tick took, allowed or refused; -1 none */
} roz_record_t;

/** A drain callback: one record; return 0 to go on, non-zero to stop the
 *  drain after this record (it is consumed either way). */
typedef int (*roz_record_sink_fn)(void *ctx, const roz_record_t *rec);

/** The recorder. Fields are private. */
typedef struct roz_recorder {
    const roz_manifest_t *ROZ_PRIVATE(m);
    unsigned char        *ROZ_PRIVATE(slots);     /* capacity x slot_bytes, the caller's */
    size_t                ROZ_PRIVATE(slot_bytes);
    uint32_t              ROZ_PRIVATE(capacity);  /* a power of two */
    uint32_t              ROZ_PRIVATE(decimation);
    ROZ_ATOMIC(uint32_t)  ROZ_PRIVATE(head);      /* written by the tick only */
    ROZ_ATOMIC(uint32_t)  ROZ_PRIVATE(tail);      /* written by the drain only */
    ROZ_ATOMIC(uint32_t)  ROZ_PRIVATE(dropped);   /* written by the tick only */
    ROZ_ATOMIC(uint32_t)  ROZ_PRIVATE(recorded);  /* written by the tick only */
    uint32_t              ROZ_PRIVATE(phase);     /* tick: ticks until the next decimated one */
    uint32_t              ROZ_PRIVATE(last_faults); /* tick: faults of the last record */
    uint32_t              ROZ_PRIVATE(last_level);  /* tick: the e-stop input at the last tick */
    int                   ROZ_PRIVATE(any);       /* tick: a record went in */
} roz_recorder_t;

/**
 * @brief Bytes one record of @p m takes in the ring (8-byte aligned).
 * Context: any.
 */
size_t roz_recorder_slot_bytes(const roz_manifest_t *m);

/**
 * @brief Set a recorder up on the caller's storage: as many records as fit,
 *        rounded down to a power of two.
 * @param[in] storage     8-byte aligned, @p bytes long; outlives the recorder
 * @param[in] decimation  record every Nth tick (1: every tick; 0 means 1)
 * @retval ROZ_OK     ready
 * @retval ROZ_EINVAL NULL argument, misaligned storage, or room for fewer
 *                    than 2 records
 * Context: start-up; no I/O, no allocation.
 */
ROZ_NODISCARD int roz_recorder_init(roz_recorder_t *r, const roz_manifest_t *m, void *storage,
                                    size_t bytes, uint32_t decimation);

/** @brief Records the ring holds. Context: any. */
uint32_t roz_recorder_capacity(const roz_recorder_t *r);

/** @brief The decimation it was set up with (1: every tick). Context: any. */
uint32_t roz_recorder_decimation(const roz_recorder_t *r);

/**
 * @brief Hand the queued records, oldest first, to @p sink, at most @p max
 *        of them (0: all that are queued now).
 * @return the number of records drained
 * Context: one consumer thread at a time (never the tick's RT thread; the
 *          firmware's idle loop between ticks is fine); wait-free towards
 *          the tick; formats a fault's message when the faults changed.
 */
size_t roz_recorder_drain(roz_recorder_t *r, roz_record_sink_fn sink, void *ctx, size_t max);

/** @brief Records dropped because the ring was full, since init.
 *  Context: any thread. */
uint32_t roz_recorder_dropped(const roz_recorder_t *r);

/** @brief Records pushed into the ring since init (not dropped).
 *  Context: any thread. */
uint32_t roz_recorder_recorded(const roz_recorder_t *r);

/** @brief FNV-1a 64 of @p len bytes: a controller's hash in the records.
 *  Context: any; linear in @p len (at load, not per tick). */
uint64_t roz_recorder_hash(const void *bytes, size_t len);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_RECORDER_H */
