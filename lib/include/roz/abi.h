/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/abi.h
 * @brief The controller ABI, engine-neutral.
 *
 * Each import a controller may use is a plain C function over a roz_abi_t
 * context; an engine (wasm3 today) only marshals arguments into these, and
 * links them from roz_abi_imports[], refusing anything else. The imports,
 * their meaning and the optional bulk pair (state.get_all, command.set_all,
 * bounds-checked against the module's memory before a byte moves) and the
 * neural-network pair (nn.matvec, nn.act; roz_abi_nn_matvec()):
 * docs/controllers.md and docs/policies.md.
 */
#ifndef ROZ_ABI_H
#define ROZ_ABI_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/private.h"
#include "roz/manifest.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Return codes of command.set. */
#define ROZ_ABI_SET_TAKEN    0   /**< value taken as given */
#define ROZ_ABI_SET_CLAMPED  1   /**< value clamped to the channel's limits */
#define ROZ_ABI_SET_REFUSED (-1) /**< bad index or non-finite value */

/** One emitted metric. */
typedef struct roz_metric {
    int64_t tick;
    double  value;
} roz_metric_t;

/** Wait-free single-producer (tick) single-consumer (any thread) ring;
 *  fields private (roz/private.h). */
typedef struct roz_metric_ring {
    roz_metric_t         ROZ_PRIVATE(items)[ROZ_CFG_TELEMETRY_RING];
    ROZ_ATOMIC(uint_fast32_t) ROZ_PRIVATE(head); /* written by the tick only */
    ROZ_ATOMIC(uint_fast32_t) ROZ_PRIVATE(tail); /* written by the consumer only */
    ROZ_ATOMIC(uint32_t) ROZ_PRIVATE(dropped);   /* written by the tick only */
} roz_metric_ring_t;

/** Counters of the ABI, per controller instance. */
typedef struct roz_abi_counters {
    uint64_t sets;             /**< command.set calls */
    uint64_t set_clamped;      /**< ... that returned 1 */
    uint64_t set_bad_index;    /**< ... refused for a bad index */
    uint64_t set_nonfinite;    /**< ... refused for NaN/Inf (channel sent to its default) */
    uint64_t get_bad_index;    /**< state.get / limit_* with a bad index */
    uint64_t estop_requests;   /**< safety.request_estop calls */
    uint64_t metrics;          /**< telemetry.emit_metric calls */
    uint64_t nn_calls;         /**< nn.matvec and nn.act calls, refused ones included */
    uint64_t nn_refused;       /**< ... refused: nothing written */
} roz_abi_counters_t;

/** Wall-clock source: nanoseconds from an arbitrary epoch. */
typedef uint64_t (*roz_clock_fn)(void *ctx);

/**
 * The context every import works on. The runtime points it at this tick's
 * snapshot and the controller's target array before each process() call.
 * Fields are private (roz/private.h); a controller sees them only through
 * the imports.
 */
typedef struct roz_abi {
    const roz_manifest_t *ROZ_PRIVATE(manifest);
    double               *ROZ_PRIVATE(target);   /* n_commands targets; persist across ticks */
    const double         *ROZ_PRIVATE(state);    /* n_states values of this tick's snapshot */
    int64_t               ROZ_PRIVATE(tick);     /* the tick being processed */
    uint64_t              ROZ_PRIVATE(period_ns);/* 1e9 / control_rate_hz */
    roz_clock_fn          ROZ_PRIVATE(clock);    /* wall clock, for timing.now_ns; may be NULL */
    void                 *ROZ_PRIVATE(clock_ctx);
    int                   ROZ_PRIVATE(estop_requested); /* set by safety.request_estop */
    roz_abi_counters_t    ROZ_PRIVATE(counters);
    roz_metric_ring_t    *ROZ_PRIVATE(metrics);  /* may be NULL: metrics are counted, not kept */
} roz_abi_t;

/** One entry of the import table. Signatures use one letter per value:
 *  i = i32, I = i64, F = f64, v = none, written "ret(args)": command.set is
 *  "i(iF)". */
typedef struct roz_abi_import {
    const char *module;
    const char *name;
    const char *signature;
    /** NULL, or the ROZ_CFG_* option that left this import out of the
     *  build (roz/config.h): a module importing it is refused at load. */
    const char *left_out;
} roz_abi_import_t;

/** Every import a controller may use, and their count. */
extern const roz_abi_import_t roz_abi_imports[];
extern const size_t roz_abi_import_count;

/**
 * @brief Look up an import by module and name.
 * @return the table entry, or NULL when roz has no such import.
 * Context: load time.
 */
const roz_abi_import_t *roz_abi_find_import(const char *module, const char *name);

/**
 * @brief Point a context at a manifest and target storage; targets start at
 *        the manifest defaults, counters at zero.
 * Context: start-up or controller (re)start; RT-safe.
 */
void roz_abi_init(roz_abi_t *abi, const roz_manifest_t *m, double *target,
                  roz_metric_ring_t *metrics);

/** @brief Reset targets to the defaults and clear estop_requested. RT-safe.
 *  Context: the thread that runs the controller. */
void roz_abi_reset(roz_abi_t *abi);

/**
 * @brief Point the context at this tick's snapshot before a process() call.
 * Context: the thread that runs the controller; RT-safe.
 */
void roz_abi_begin_tick(roz_abi_t *abi, int64_t tick, const double *state);

/** @brief Set the clock timing.now_ns reads, and the control period
 *  (0 keeps the manifest's). Context: start-up or controller (re)start. */
void roz_abi_set_clock(roz_abi_t *abi, roz_clock_fn clock, void *clock_ctx,
                       uint64_t period_ns);

/** @brief 1 if safety.request_estop was called since the last reset.
 *  Context: the thread that runs the controller. */
int roz_abi_estop_requested(const roz_abi_t *abi);

/** @brief The context's counters. Context: the thread that runs the
 *  controller (a runtime's: roz_runtime_stats() from any thread). */
void roz_abi_counters_get(const roz_abi_t *abi, roz_abi_counters_t *out);

/* ---- the imports; Context: inside process(), RT-safe, O(1) ------------- */

/** command.set: 0 taken, 1 clamped, -1 refused (bad index; NaN/Inf, which
 *  also sends the channel to its safe default). */
int32_t roz_abi_command_set(roz_abi_t *abi, int32_t index, double value);
/** command.count */
int32_t roz_abi_command_count(const roz_abi_t *abi);
/** command.limit_min: NaN for a bad index. */
double roz_abi_command_limit_min(roz_abi_t *abi, int32_t index);
/** command.limit_max: NaN for a bad index. */
double roz_abi_command_limit_max(roz_abi_t *abi, int32_t index);
/** state.get: NaN for a bad index. */
double roz_abi_state_get(roz_abi_t *abi, int32_t index);
/** state.count */
int32_t roz_abi_state_count(const roz_abi_t *abi);
/** math.sin */
double roz_abi_math_sin(double x);
/** math.cos */
double roz_abi_math_cos(double x);
/** safety.request_estop */
void roz_abi_safety_request_estop(roz_abi_t *abi);
/** timing.now_ns: the wall clock, 0 without one. */
int64_t roz_abi_timing_now_ns(const roz_abi_t *abi);
/** timing.sim_time_ns: tick * period. */
int64_t roz_abi_timing_sim_time_ns(const roz_abi_t *abi);
/** telemetry.emit_metric: into the ring, dropped (and counted) when full. */
void roz_abi_telemetry_emit_metric(roz_abi_t *abi, double value);

/* ---- fuel of the imports, engine-neutral ---------------------------------- */

/* Every engine charges a call's own units (the call instruction's, the same
 * for every import) in the caller's code, and these on top, inside the
 * import, before any work: the same units on every engine, so a controller's
 * fuel per tick does not depend on the engine that runs it (docs/budget.md). */

/** timing.now_ns: a clock read, charged the same with or without a clock
 *  (fuel never depends on the target). */
#define ROZ_ABI_NOW_UNITS 48u

/** @brief Units math.sin / math.cos charge for @p x. Context: any. */
uint64_t roz_abi_math_units(double x);

/** @brief Units state.get_all charges for @p count values (0 for a count it
 *  refuses anyway). Context: any. */
uint64_t roz_abi_state_get_all_units(int32_t count);

/** @brief Units command.set_all charges for @p count values (0 for a count
 *  it refuses anyway). Context: any. */
uint64_t roz_abi_command_set_all_units(int32_t count);

/* ---- the bulk extension; Context: inside process(), RT-safe, O(count) ---- */

/** Largest count a bulk import accepts: the larger channel maximum. */
#define ROZ_ABI_BULK_MAX                                                                   \
    (ROZ_CFG_MAX_COMMANDS > ROZ_CFG_MAX_STATES ? ROZ_CFG_MAX_COMMANDS : ROZ_CFG_MAX_STATES)

/**
 * @brief state.get_all (i32 ptr, i32 count) -> i32: copies state channels
 *        0..count-1 of this tick's snapshot to the controller's memory at
 *        @p ptr, 8 bytes each, little-endian.
 * @param[in] mem     the controller's linear memory (its engine's view)
 * @param[in] mem_len its size in bytes
 * @param[in] ptr     the wasm address (an unsigned i32)
 * @param[in] count   values to copy, 0..n_states
 * @retval count  copied
 * @retval -1     refused, nothing written: count negative or above
 *                n_states, [ptr, ptr + 8 count) not inside the memory, or
 *                no snapshot; counted as get_bad_index
 * Context: inside process(); RT-safe.
 */
int32_t roz_abi_state_get_all(roz_abi_t *abi, uint8_t *mem, size_t mem_len, uint32_t ptr,
                              int32_t count);

/**
 * @brief command.set_all (i32 ptr, i32 count) -> i32: command channel i
 *        takes the f64 at @p ptr + 8 i for i in 0..count-1, each exactly as
 *        command.set(i, value) would (clamped, or refused when non-finite,
 *        which sends that channel to its safe default; every counter as for
 *        count separate calls). Channels from count on keep their targets.
 * @param[in] mem, mem_len, ptr  as for roz_abi_state_get_all()
 * @param[in] count   values to submit, 0..n_commands
 * @retval >=0  how many values were not taken as given (clamped or refused)
 * @retval -1   refused as a whole, no target changed: count negative or
 *              above n_commands, or the range not inside the memory;
 *              counted as one set refused for a bad index
 * Context: inside process(); RT-safe.
 */
int32_t roz_abi_command_set_all(roz_abi_t *abi, const uint8_t *mem, size_t mem_len,
                                uint32_t ptr, int32_t count);

/* ---- the neural-network extension; Context: inside process(), RT-safe ----- */

/** nn.matvec flags. */
#define ROZ_ABI_NN_BIAS       1 /**< add b; without it b is not read */
#define ROZ_ABI_NN_ACCUMULATE 2 /**< y += W x (+ b), else y = W x (+ b) */

/** nn.act kinds (each element by roz_math.h's float function of that name). */
typedef enum roz_abi_nn_act {
    ROZ_ABI_NN_RELU = 0,    /**< roz_math_reluf */
    ROZ_ABI_NN_TANH = 1,    /**< roz_math_tanhf */
    ROZ_ABI_NN_SIGMOID = 2, /**< roz_math_sigmoidf */
    ROZ_ABI_NN_ELU = 3,     /**< roz_math_eluf (alpha 1) */
    ROZ_ABI_NN_EXP = 4,     /**< roz_math_expf */
    ROZ_ABI_NN_ACT_COUNT = 5
} roz_abi_nn_act_t;

/** Fuel of the NN imports, charged before the work on top of the call's own
 *  units, from the counts alone (measured per unit in docs/policies.md):
 *  nn.matvec rows * cols * MAC + rows * ROW; nn.act count * the kind's. */
#define ROZ_ABI_NN_UNITS_PER_MAC 1u
#define ROZ_ABI_NN_UNITS_PER_ROW 2u
#define ROZ_ABI_NN_UNITS_RELU    2u
#define ROZ_ABI_NN_UNITS_CURVE   24u /**< tanh, sigmoid, elu, exp: per element */

/** Largest memory any module can have, bytes: counts that need more are
 *  refused before any fuel is charged. */
#define ROZ_ABI_NN_MAX_BYTES ((uint64_t)ROZ_CFG_WASM_MAX_PAGES * 65536u)

/**
 * @brief nn.matvec (i32 w, i32 x, i32 b, i32 y, i32 rows, i32 cols,
 *        i32 flags) -> i32: y[i] (=|+=) sum_j W[i cols + j] x[j] (+ b[i]),
 *        float32 little-endian at any alignment, W row-major.
 *
 * Each output in exactly this order, in float arithmetic without fused
 * multiply-add: s = 0; s = s + W[i,j] * x[j] for j = 0, 1, ..., cols - 1;
 * s = s + b[i] (BIAS); y[i] = y[i] + s (ACCUMULATE) or s. Outputs are
 * computed side by side, never a sum reordered, so the result is the same
 * bits on every target and equal to that plain loop. Every value read
 * (W, x, b, y) is first roz_math_nn_inputf()'s (roz_math.h): zero of its
 * sign below 2^-51, subnormals included, so that no product or sum is ever
 * subnormal (a CPU's slow path, which fuel would not bound).
 * @retval 0   done
 * @retval -1  refused, nothing written (counted as nn_refused): rows or
 *             cols negative, flags unknown, W (4 rows cols bytes), x, b
 *             (with BIAS) or y outside the memory, y overlapping W, x or b,
 *             or no memory
 */
#if ROZ_CFG_NN_IMPORTS /* the four functions of the extension */
int32_t roz_abi_nn_matvec(roz_abi_t *abi, uint8_t *mem, size_t mem_len, uint32_t w,
                          uint32_t x, uint32_t b, uint32_t y, int32_t rows, int32_t cols,
                          int32_t flags);

/**
 * @brief nn.act (i32 kind, i32 ptr, i32 count) -> i32: v[i] = f(v[i]) for
 *        the count float32 values at ptr, f the kind's (roz_abi_nn_act_t),
 *        as roz_math_nn_actf(): each value read as nn.matvec reads it, and
 *        exp and sigmoid +0 where their result would be subnormal.
 * @retval count  done
 * @retval -1     refused, nothing written (nn_refused): unknown kind, count
 *                negative, the range outside the memory, or no memory
 */
int32_t roz_abi_nn_act(roz_abi_t *abi, uint8_t *mem, size_t mem_len, int32_t kind, uint32_t ptr,
                       int32_t count);

/** @brief Fuel units an engine charges for nn.matvec before the call: 0
 *  for counts refused whatever the pointers. Context: any. */
uint64_t roz_abi_nn_matvec_units(int32_t rows, int32_t cols);

/** @brief Fuel units for nn.act: 0 for a kind or count refused whatever
 *  the pointer. Context: any. */
uint64_t roz_abi_nn_act_units(int32_t kind, int32_t count);
#endif /* ROZ_CFG_NN_IMPORTS */

/**
 * @brief Take the oldest metric from a ring.
 * @retval 1 one metric taken into @p out
 * @retval 0 the ring is empty
 * Context: any one consumer thread; wait-free.
 */
int roz_metric_ring_pop(roz_metric_ring_t *ring, roz_metric_t *out);

/** @brief Metrics lost to a full ring since init. Context: any thread. */
uint32_t roz_metric_ring_dropped(const roz_metric_ring_t *ring);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_ABI_H */
