/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/controller.h
 * @brief One instance of a WebAssembly controller: load, link, call process().
 *
 * The engine is wasm3 (linked PRIVATE; no wasm3 type appears here). What a
 * module must be to load: docs/controllers.md. The budget every process()
 * call runs on (fuel, the deadline, the C stack): docs/budget.md.
 *
 * Load and unload allocate (wasm3's heap, or its fixed heap on firmware):
 * do them outside the tick. The module bytes must outlive the instance
 * (wasm3 keeps pointers into them).
 */
#ifndef ROZ_CONTROLLER_H
#define ROZ_CONTROLLER_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/abi.h"
#include "roz/private.h"
#include "roz/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A budget field that is off: fuel unmetered, or no deadline. Zero is
 *  never "off": a budget of 0 allows nothing and is refused. */
#define ROZ_BUDGET_OFF UINT64_MAX

/** Per-call budget of a controller instance. */
typedef struct roz_budget {
    uint64_t     fuel;        /**< units per process() call, >= 1; ROZ_BUDGET_OFF = unmetered */
    uint64_t     deadline_ns; /**< wall-clock time per call, >= 1; ROZ_BUDGET_OFF = none */
    roz_clock_fn clock;       /**< monotonic clock for the deadline (needed with one) */
    void        *clock_ctx;
} roz_budget_t;

/** A controller instance. Fields are private to controller.c. */
typedef struct roz_controller {
    roz_budget_t ROZ_PRIVATE(budget);
    uint64_t   ROZ_PRIVATE(fuel_used);  /* units the last process() call used */
    size_t     ROZ_PRIVATE(stack_used); /* deepest C stack of the last call, bytes */
    uint64_t   ROZ_PRIVATE(meter_used);     /* the running call: units charged before this slice */
    uint64_t   ROZ_PRIVATE(meter_slice);    /* units of the current slice */
    uint64_t   ROZ_PRIVATE(meter_deadline); /* absolute clock time, 0 = none */
    uintptr_t  ROZ_PRIVATE(stack_base);     /* the C stack where the call entered the engine */
    int        ROZ_PRIVATE(unmetered);      /* compiled without fuel charges (benchmarks only) */
    int        ROZ_PRIVATE(spent);      /* stopped by its budget: must be reloaded */
    void      *ROZ_PRIVATE(env);       /* engine handles, NULL when not loaded */
    void      *ROZ_PRIVATE(runtime);
    void      *ROZ_PRIVATE(module);
    void      *ROZ_PRIVATE(process);
    roz_abi_t *ROZ_PRIVATE(abi);       /* the context the imports run on */
    /* the engine that loaded it (wasm3, or the ahead-of-time engine of
     * roz/aot.h), NULL when not loaded: its call, which returns the trap
     * (NULL: none) and where its fuel is, and its unload. Through these the
     * rest of controller.c never names an engine, so an image that loads
     * only compiled controllers links no interpreter. */
    const char *(*ROZ_PRIVATE(engine_call))(struct roz_controller *c, int64_t tick,
                                            int64_t slice, int64_t **fuel);
    void       (*ROZ_PRIVATE(engine_unload))(struct roz_controller *c);
    const void *ROZ_PRIVATE(aot_module); /* its roz_aot_module_t */
    unsigned    ROZ_PRIVATE(aot_slot);   /* the instance it runs in */
    int64_t    *ROZ_PRIVATE(aot_fuel);   /* the instance's fuel global */
    void       *ROZ_PRIVATE(aot_memory); /* its memory object, NULL without one */
    uint64_t   ROZ_PRIVATE(calls);     /* process() calls since load */
    char       ROZ_PRIVATE(error)[ROZ_CFG_ERROR_LEN]; /* last load or trap message */
} roz_controller_t;

/**
 * @brief Bytes of scratch memory roz's module validator works in while a
 *        controller loads (its operand and control stacks, the module's
 *        type, function and global tables, the export names it sorts), from
 *        its limits in roz/config.h (ROZ_CFG_WASM_MAX_TYPES, _FUNCS,
 *        _GLOBALS, _LOCALS, _EXPORTS, _BLOCK_DEPTH): 22656 with the defaults.
 *
 * The scratch is the caller's: roz_controller_load() puts it on the calling
 * thread's stack (only while it validates, before the engine compiles), and
 * roz_controller_load_in() takes storage the caller owns, e.g. one static
 * buffer on a firmware that loads one controller at a time. No thread-local
 * storage is involved (bare-metal C libraries have none).
 */
#define ROZ_CONTROLLER_SCRATCH_BYTES                                                         \
    ((128u + 4u * ROZ_CFG_WASM_MAX_TYPES + 2u * ROZ_CFG_WASM_MAX_FUNCS +                      \
      2u * ROZ_CFG_WASM_MAX_GLOBALS +                                                         \
      ROZ__SCRATCH_MAX(ROZ_CFG_WASM_MAX_LOCALS + 1056u + 8u * (ROZ_CFG_WASM_MAX_BLOCK_DEPTH + 1u), \
                       8u * ROZ_CFG_WASM_MAX_EXPORTS) + 7u) & ~7u)
#define ROZ__SCRATCH_MAX(a, b) ((a) > (b) ? (a) : (b))

/** The validator's scratch (see ROZ_CONTROLLER_SCRATCH_BYTES); one load at a
 *  time may use it. Its contents are meaningless between loads. */
typedef struct roz_load_scratch {
    union {
        uint64_t      ROZ_PRIVATE(align);
        void         *ROZ_PRIVATE(align_ptr);
        unsigned char ROZ_PRIVATE(bytes)[ROZ_CONTROLLER_SCRATCH_BYTES];
    } ROZ_PRIVATE(u);
} roz_load_scratch_t;

/** @brief Zero an instance (not loaded). Context: any; no I/O. */
void roz_controller_init(roz_controller_t *c);

/**
 * @brief Check, load, link and compile a module; the imports will run on @p abi.
 * @param[in] wasm  the module bytes; must outlive the instance
 * @param[in] len   their length, at most ROZ_CFG_WASM_MAX_MODULE_BYTES
 * @param[in] abi   the context; must outlive the instance
 * @retval ROZ_OK     loaded
 * @retval ROZ_EINVAL refused; roz_controller_error() names the import,
 *                    export or problem
 * @retval ROZ_ENOMEM the engine could not allocate
 * @retval ROZ_ESTATE already loaded
 * Context: outside the tick; allocates; the validator's scratch takes
 * ROZ_CONTROLLER_SCRATCH_BYTES of the calling thread's stack while it runs.
 */
ROZ_NODISCARD int roz_controller_load(roz_controller_t *c, const uint8_t *wasm, size_t len,
                                      roz_abi_t *abi);

/**
 * @brief As roz_controller_load(), with the validator's scratch in
 *        @p scratch (the caller's storage; one load at a time uses it).
 * Context: outside the tick; allocates.
 */
ROZ_NODISCARD int roz_controller_load_in(roz_controller_t *c, const uint8_t *wasm, size_t len,
                                         roz_abi_t *abi, roz_load_scratch_t *scratch);

/**
 * @brief Set the budget of every following process() call (the default,
 *        after init, is unmetered with no deadline).
 * @retval ROZ_OK     set
 * @retval ROZ_EINVAL a fuel or deadline of 0, or a deadline without a clock;
 *                    the budget is unchanged
 * Context: outside the tick, or from the tick thread between calls.
 */
ROZ_NODISCARD int roz_controller_set_budget(roz_controller_t *c, const roz_budget_t *budget);

/** @brief Fuel units the last process() call used.
 *  Context: the thread that runs the controller. */
uint64_t roz_controller_fuel_used(const roz_controller_t *c);

/** @brief The deepest C stack the last process() call reached, bytes, as
 *  seen at its wasm calls and loop entries (ROZ_CFG_NATIVE_STACK_BYTES).
 * Context: the thread that runs the controller.
 */
size_t roz_controller_stack_used(const roz_controller_t *c);

/**
 * @brief Call process(tick) once, within the budget.
 * @retval ROZ_OK        returned normally
 * @retval ROZ_ETRAP     the controller trapped (in wasm, or past
 *                       ROZ_CFG_NATIVE_STACK_BYTES of C stack);
 *                       roz_controller_error() says why
 * @retval ROZ_ETIMEDOUT fuel or deadline ran out; the instance is spent
 * @retval ROZ_ESTATE    not loaded, or spent by an earlier overrun (a trapped
 *                       instance may be called again; its memory is as the
 *                       trap left it: roz_runtime never does)
 * Context: the tick; RT-safe (no allocation, no compilation).
 */
ROZ_NODISCARD int roz_controller_process(roz_controller_t *c, int64_t tick);

/**
 * @brief roz_controller_process() with the start already read: the deadline
 *        counts from @p start_ns, a reading of the budget's clock taken just
 *        before the call, instead of a reading of its own (roz_runtime
 *        passes the reading it times process() from: one clock read a tick
 *        less). Ignored without a deadline.
 * @return as roz_controller_process()
 * Context: the tick; RT-safe.
 */
ROZ_NODISCARD int roz_controller_process_from(roz_controller_t *c, int64_t tick,
                                              uint64_t start_ns);

/** @brief Free the instance; idempotent. Context: outside the tick. */
void roz_controller_unload(roz_controller_t *c);

/** @brief 1 if loaded.
 *  Context: the thread that loads and runs the controller. */
int roz_controller_loaded(const roz_controller_t *c);

/** @brief 1 if the instance was stopped by its budget: it must be reloaded
 *  before it runs again. Context: the thread that runs it. */
int roz_controller_spent(const roz_controller_t *c);

/** @brief process() calls since load. Context: the thread that runs it. */
uint64_t roz_controller_calls(const roz_controller_t *c);

/** @brief The last load or trap message ("" if none).
 *  Context: the thread that loads and runs the controller. */
const char *roz_controller_error(const roz_controller_t *c);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_CONTROLLER_H */
