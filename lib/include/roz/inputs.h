/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/inputs.h
 * @brief Operator inputs: a manifest's [[manifest.inputs]], the latest value
 *        each source set, turned once per tick into the values a controller
 *        reads as states n_states + k (docs/controllers.md).
 *
 * A source (a scripted operator, a gamepad, a remote) calls
 * roz_inputs_set() from any thread: it claims the input's sequence number
 * (one compare-and-swap: odd while it writes), stores the value as two
 * 32-bit words (lock-free on every target roz runs on, Cortex-M included)
 * and releases it; no lock, no heap; the latest value wins, and a set that
 * finds another set of the same input in progress is dropped (ROZ_ESTATE).
 * The tick takes a value only when the sequence number is even and did not
 * change while it read (else it takes it at the next tick). The tick calls roz_inputs_tick() and applies the rules:
 *  - a non-finite value is refused and counted; the input keeps its value;
 *  - a value outside the limits is clamped and counted;
 *  - an input without a fresh value for its stale_after_ms (by the tick's
 *    clock) returns to its default; counted once per episode;
 *  - every change is capped at max_rate_of_change per tick (the manifest
 *    requires it above 0): an input never jumps.
 * Before its first value an input reads its default.
 */
#ifndef ROZ_INPUTS_H
#define ROZ_INPUTS_H

#include <stdint.h>

#include "roz/atomic.h"
#include "roz/manifest.h"
#include "roz/operator.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One input: written by sources (the atomics) and the tick (the rest). */
typedef struct roz_input_slot {
    ROZ_ATOMIC(uint32_t) lo, hi; /**< the latest value set: its IEEE 754 bits */
    ROZ_ATOMIC(uint32_t) seq;    /**< odd while a set writes; +2 a set */
    uint32_t seen;             /**< tick: the seq last taken */
    int      fresh;            /**< tick: a value was taken and is not yet stale */
    uint64_t taken_ns;         /**< tick: when the last value was taken */
    double   target;           /**< tick: the value the input moves towards */
    double   value;            /**< tick: the value a controller reads */
} roz_input_slot_t;

/** Counters, written by the tick only. */
typedef struct roz_inputs_counters {
    uint64_t clamped;   /**< values outside the limits, clamped */
    uint64_t nonfinite; /**< NaN or infinite values, refused */
    uint64_t stale;     /**< times an input went stale */
    uint64_t rate_caps; /**< ticks an input's change was capped */
} roz_inputs_counters_t;

/** The inputs of one manifest. */
typedef struct roz_inputs {
    const roz_channel_t  *ch; /**< the manifest's inputs */
    const roz_input_rule_t *rule; /**< and their rules (staleness, source) */
    uint16_t              n;
    roz_inputs_counters_t counters;
    roz_input_slot_t      slot[ROZ_CFG_MAX_INPUTS > 0 ? ROZ_CFG_MAX_INPUTS : 1];
} roz_inputs_t;

/**
 * @brief Set up @p in for @p m's inputs, each at its default.
 * Context: start-up, before any roz_inputs_set() or roz_inputs_tick().
 */
void roz_inputs_init(roz_inputs_t *in, const roz_manifest_t *m);

/**
 * @brief A source's latest value for input @p k (any value: the tick
 *        judges it).
 * @retval ROZ_OK     stored
 * @retval ROZ_EINVAL @p k is not an input of the manifest
 * @retval ROZ_ESTATE another set of input @p k was in progress: dropped
 * Context: any thread; wait-free (no loop); RT-safe.
 */
int roz_inputs_set(roz_inputs_t *in, uint32_t k, double value);

/**
 * @brief A frame of an operator device: roz_inputs_set(k, scale * field)
 *        for every input k whose source is a field of that device.
 * @retval ROZ_OK     all stored
 * @retval ROZ_ESTATE at least one was dropped (a set of it in progress)
 * Context: any thread; wait-free (O(inputs), no loop on contention); RT-safe.
 */
int roz_inputs_remote(roz_inputs_t *in, const roz_operator_remote_t *r);

/** @brief As roz_inputs_remote(), for a twist. Context: as roz_inputs_remote(). */
int roz_inputs_twist(roz_inputs_t *in, const roz_operator_twist_t *t);

/**
 * @brief One tick: takes each input's latest value, applies the rules and
 *        writes the values to @p out[0, n).
 * @param now_ns  the tick's time (the clock staleness is judged by)
 * Context: the tick's thread only; O(n); no heap.
 */
void roz_inputs_tick(roz_inputs_t *in, uint64_t now_ns, double *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_INPUTS_H */
