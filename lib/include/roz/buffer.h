/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/buffer.h
 * @brief Wait-free latest-value buffer (triple buffer) for state and command
 *        frames between one producer thread and one consumer thread.
 *
 * Three slots of n doubles each. The producer owns the back slot, the
 * consumer owns the front slot, and the middle slot changes hands through one
 * atomic exchange, so neither side ever blocks or waits, and the consumer
 * never sees a torn frame: it sees the whole of the most recently committed
 * frame or the whole of the one it had. Each frame carries a sequence number
 * (1, 2, ... per commit) and a time stamp set by the producer, so the
 * consumer can tell a fresh frame from the one it already had (staleness).
 * Who writes which field: roz_buffer_t.
 */
#ifndef ROZ_BUFFER_H
#define ROZ_BUFFER_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/error.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The exchanged word: slot index (bits 0-1) and a "fresh" flag (bit 2). */
typedef struct roz_buffer_xchg {
    ROZ_ATOMIC(uint_fast32_t) ROZ_PRIVATE(word);
} roz_buffer_xchg_t;

/** A latest-value buffer; storage is the caller's (see ROZ_BUFFER_DEFINE);
 *  fields private (roz/private.h). Who writes them: slots and n are set by
 *  roz_buffer_init(), then read-only; seq[] and stamp_ns[] are written by
 *  the producer in its back slot only; back and produced by the producer
 *  only; front and consumed_seq by the consumer only; middle by both,
 *  through atomic exchange only (wrapped in a struct so plain access does
 *  not compile). */
typedef struct roz_buffer {
    double           *ROZ_PRIVATE(slots);      /* 3 * n doubles */
    uint32_t          ROZ_PRIVATE(n);          /* values per frame */
    uint64_t          ROZ_PRIVATE(seq)[3];     /* sequence of the frame in each slot */
    uint64_t          ROZ_PRIVATE(stamp_ns)[3];/* producer's time stamp per slot */
    uint32_t          ROZ_PRIVATE(back);       /* producer's slot */
    uint64_t          ROZ_PRIVATE(produced);   /* frames committed so far (producer) */
    uint32_t          ROZ_PRIVATE(front);      /* consumer's slot */
    uint64_t          ROZ_PRIVATE(consumed_seq); /* seq of the consumer's frame, 0 = none */
    roz_buffer_xchg_t ROZ_PRIVATE(middle);     /* the slot in between, plus fresh flag */
} roz_buffer_t;

/** What roz_buffer_read() gives the consumer. */
typedef struct roz_buffer_frame {
    const double *values;   /**< n values; valid until the next read */
    uint64_t      seq;      /**< 1.. ; 0 when nothing was ever committed */
    uint64_t      stamp_ns; /**< the producer's stamp of this frame */
    int           fresh;    /**< 1 if this frame is newer than the last read */
} roz_buffer_frame_t;

/**
 * @brief Static storage for a buffer of @p n_values doubles per frame, and
 *        the buffer itself: `ROZ_BUFFER_DEFINE(state_buf, 97);` then
 *        `roz_buffer_init(&state_buf, state_buf_slots, 97)`.
 */
#define ROZ_BUFFER_DEFINE(name, n_values)                                     \
    _Static_assert((n_values) > 0, "ROZ_BUFFER_DEFINE: n_values must be > 0"); \
    static double name##_slots[3u * (n_values)];                              \
    static roz_buffer_t name

/**
 * @brief Prepare a buffer over caller storage of 3 * n doubles, all slots
 *        zero, nothing committed.
 * Context: before either thread uses it; not thread-safe.
 */
void roz_buffer_init(roz_buffer_t *b, double *slots, uint32_t n);

/**
 * @brief The producer's slot to fill (n doubles). Its previous content is a
 *        stale frame: write every value before committing.
 * Context: producer thread only; wait-free; RT-safe.
 */
double *roz_buffer_write_begin(roz_buffer_t *b);

/**
 * @brief Publish the slot returned by roz_buffer_write_begin().
 * @param[in] stamp_ns the producer's time stamp for this frame
 * @return the frame's sequence number (1, 2, ...)
 * Context: producer thread only; wait-free (one atomic exchange); RT-safe.
 */
uint64_t roz_buffer_write_commit(roz_buffer_t *b, uint64_t stamp_ns);

/**
 * @brief Copy-free publish of a whole frame: write_begin, copy n values,
 *        commit.
 * Context: producer thread only; wait-free; RT-safe.
 */
uint64_t roz_buffer_write(roz_buffer_t *b, const double *values, uint64_t stamp_ns);

/**
 * @brief Take the most recent frame.
 * @param[out] out the frame; out->fresh tells whether it is new
 * @retval 1          a fresh frame (newer than the last read)
 * @retval 0          no newer frame: out is the same frame as last time
 * @retval ROZ_ENOENT nothing was ever committed (out->seq is 0)
 * Context: consumer thread only; wait-free; RT-safe.
 */
int roz_buffer_read(roz_buffer_t *b, roz_buffer_frame_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_BUFFER_H */
