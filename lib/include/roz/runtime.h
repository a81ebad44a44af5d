/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/runtime.h
 * @brief The tick runtime (shared/DESIGN.md section 5): snapshot the state,
 *        run the controller, filter, hand the commands to the port, record.
 *
 * Firmware calls roz_runtime_tick() from its own timer or RTOS task; hosts
 * drive it from a periodic thread (roz/hal/runner.h). All storage is in
 * roz_runtime_t, which the caller owns (make it static: it is large). After
 * roz_runtime_start() the tick never allocates.
 *
 * Threads: roz_runtime_tick() runs on one thread (the tick). Controller load,
 * swap and fault clearing run on another (or the same, between ticks) and
 * hand over through atomics at the next tick boundary; roz_runtime_estop()
 * may be called from any thread or an ISR.
 *
 * Faults latch (shared/DESIGN.md section 4): a trap, an overrun of the
 * tick's time budget, a stale state stream, the e-stop input or the
 * controller's safety.request_estop. While any is latched the controller does
 * not run and every command goes to its safe default, ramped by the rate
 * caps for a controlled stop (trap, overrun, stale) or at once for an e-stop.
 * Only roz_runtime_clear_faults() unlatches them.
 */
#ifndef ROZ_RUNTIME_H
#define ROZ_RUNTIME_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/abi.h"
#include "roz/buffer.h"
#include "roz/controller.h"
#include "roz/filter.h"
#include "roz/hal/port.h"
#include "roz/log.h"
#include "roz/manifest.h"
#include "roz/monitor.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Ticks of verification before a controller may drive the robot. */
#define ROZ_RUNTIME_VERIFY_TICKS 100

/** Latched faults (bit mask). */
typedef enum roz_fault {
    ROZ_FAULT_TRAP          = 1u << 0, /**< the controller trapped */
    ROZ_FAULT_OVERRUN       = 1u << 1, /**< process() exceeded the tick budget */
    ROZ_FAULT_STALE         = 1u << 2, /**< no fresh state for stale_ticks ticks, counted
                                            from the first state frame */
    ROZ_FAULT_ESTOP         = 1u << 3, /**< the application's e-stop input */
    ROZ_FAULT_ESTOP_REQUEST = 1u << 4, /**< the controller called safety.request_estop */
    ROZ_FAULT_LINK          = 1u << 5, /**< the port's read() returned ROZ_ELINK: its peer
                                            restarted or came back after it was lost */
} roz_fault_t;
#define ROZ_FAULT_KIND_COUNT 6
/** Faults answered by an immediate stop; the others ramp. A robot that
 *  restarted (LINK) has forgotten the commands a ramp would continue from,
 *  so its first command is the safe default itself. */
#define ROZ_FAULT_IMMEDIATE_MASK (ROZ_FAULT_ESTOP | ROZ_FAULT_ESTOP_REQUEST | ROZ_FAULT_LINK)

/** Configuration; roz_runtime_config_default() fills the defaults. */
typedef struct roz_runtime_config {
    const roz_manifest_t *manifest;
    roz_port_t            port;
    uint32_t     stale_ticks;   /**< ticks without a fresh frame before STALE; default 10 */
    uint64_t     budget_ns;     /**< process() wall-clock budget per tick (deadline, checked
                                     while it runs, needs a clock); default half the period;
                                     UINT64_MAX = none */
    uint64_t     fuel_per_tick; /**< process() fuel per tick (deterministic, see
                                     roz/controller.h); default ROZ_CFG_FUEL_PER_SECOND /
                                     control_rate_hz; UINT64_MAX = unmetered */
    double       position_margin; /**< filter margin; default ROZ_FILTER_DEFAULT_MARGIN */
    roz_clock_fn clock;         /**< monotonic clock for budgets and the monitor; NULL = none
                                     (then no overrun is detected and times read 0) */
    void        *clock_ctx;
    int          monitor_jitter; /**< 1: check each tick's start against the period
                                     (ticks driven by a timer; default); 0: ticks run
                                     back to back in simulated time */
    roz_log_fn   log;           /**< warnings and faults; NULL = silent */
    void        *log_ctx;
} roz_runtime_config_t;

/** Figures of a verification run. */
typedef struct roz_verify_report {
    uint32_t ticks_run;        /**< ticks that completed */
    uint64_t max_process_ns;   /**< slowest tick */
    uint64_t total_process_ns;
    uint64_t nonfinite;        /**< non-finite command.set values */
    uint64_t bad_index;        /**< refused indices (reported, not failing) */
    uint64_t clamped;          /**< clamped command.set values (reported) */
    uint64_t fuel[ROZ_RUNTIME_VERIFY_TICKS]; /**< fuel each verify tick used */
    uint64_t max_fuel;         /**< the most any verify tick used */
    uint64_t fuel_budget;      /**< the per-tick fuel budget it ran under */
    uint64_t max_stack;        /**< deepest C stack of any verify tick, bytes */
} roz_verify_report_t;

/** Counters of the runtime (the filter and ABI keep their own). */
typedef struct roz_runtime_counters {
    uint64_t ticks;            /**< roz_runtime_tick() calls */
    uint64_t controller_ticks; /**< process() calls that drove the robot */
    uint64_t waiting_ticks;    /**< ticks before the first state frame (nothing sent; not
                                    a fault, a warning once after stale_ticks) */
    uint64_t stale_reads;      /**< reads with no fresh frame */
    uint64_t read_errors;      /**< reads that returned an error */
    uint64_t write_errors;     /**< writes that returned an error */
    uint64_t writes;           /**< frames handed to the port */
    uint64_t faults[ROZ_FAULT_KIND_COUNT]; /**< times each fault latched */
    uint64_t swaps;            /**< controllers installed */
    uint64_t swaps_refused;    /**< controllers that failed verification */
    uint64_t last_fuel;        /**< fuel the last process() call used */
    uint64_t max_fuel;         /**< the most one process() call used */
    uint64_t max_stack;        /**< deepest C stack of any process() call, bytes */
    uint64_t rebuilds;         /**< instances rebuilt after a trap or overrun */
} roz_runtime_counters_t;

/** One controller slot. */
typedef struct roz_runtime_slot {
    roz_controller_t ctrl;
    roz_abi_t        abi;
    double           target[ROZ_CFG_MAX_COMMANDS];
    const uint8_t   *wasm;     /* bytes (caller's), kept to rebuild after a trap */
    size_t           wasm_len;
} roz_runtime_slot_t;

/** The runtime. Large: give it static storage. Fields are private. */
typedef struct roz_runtime {
    roz_runtime_config_t   cfg;
    roz_filter_t           filter;
    roz_monitor_t          monitor;
    roz_runtime_counters_t counters;
    roz_metric_ring_t      metrics;
    roz_runtime_slot_t     slot[2];
    ROZ_ATOMIC(int)        active;       /* index of the driving slot, -1 none; written by the tick */
    ROZ_ATOMIC(int)        pending;      /* swap: slot to install at the next tick, -1 none */
    ROZ_ATOMIC(unsigned)   faults;       /* latched fault bits */
    ROZ_ATOMIC(unsigned)   estop_input;  /* set by roz_runtime_estop() */
    ROZ_ATOMIC(unsigned)   clear_request;/* set by roz_runtime_clear_faults() */
    int64_t                ctrl_tick;    /* tick number the controller sees */
    int                    have_state;
    uint32_t               stale_count;
    double                 state[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    double                 out[ROZ_CFG_MAX_COMMANDS];
    /* this tick's state for verification on another thread */
    roz_buffer_t           snapshot;
    double                 snapshot_slots[3 * (ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1)];
    double                 verify_state[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    uint64_t               last_process_ns;
    char                   fault_msg[ROZ_CFG_ERROR_LEN]; /* first fault's message */
    char                   error[ROZ_CFG_ERROR_LEN];     /* last load/verify error */
    int                    started;
} roz_runtime_t;

/** @brief Defaults for everything but manifest and port. */
void roz_runtime_config_default(roz_runtime_config_t *cfg);

/**
 * What a translation unit was compiled with: the sizes of the roz structs
 * it allocates and the ROZ_CFG_* options behind their layout. An
 * application built with another configuration than libroz_core (another
 * ROZ_CONFIG_FILE, or none) would hand roz storage of the wrong size; the
 * caller's view travels with roz_runtime_init() and a mismatch is refused.
 */
typedef struct roz_runtime_layout {
    uint32_t version;          /**< ROZ_RUNTIME_LAYOUT_VERSION */
    uint32_t runtime_bytes;    /**< sizeof(roz_runtime_t) */
    uint32_t config_bytes;     /**< sizeof(roz_runtime_config_t) */
    uint32_t controller_bytes; /**< sizeof(roz_controller_t) */
    uint32_t filter_bytes;     /**< sizeof(roz_filter_t) */
    uint32_t abi_bytes;        /**< sizeof(roz_abi_t) */
    uint32_t max_commands;     /**< ROZ_CFG_MAX_COMMANDS */
    uint32_t max_states;       /**< ROZ_CFG_MAX_STATES */
    uint32_t error_len;        /**< ROZ_CFG_ERROR_LEN */
    uint32_t telemetry_ring;   /**< ROZ_CFG_TELEMETRY_RING */
} roz_runtime_layout_t;

#define ROZ_RUNTIME_LAYOUT_VERSION 1u

/** The layout of the translation unit that expands it. */
#define ROZ_RUNTIME_LAYOUT_INIT                                                              \
    {                                                                                        \
        ROZ_RUNTIME_LAYOUT_VERSION, (uint32_t)sizeof(roz_runtime_t),                         \
            (uint32_t)sizeof(roz_runtime_config_t), (uint32_t)sizeof(roz_controller_t),      \
            (uint32_t)sizeof(roz_filter_t), (uint32_t)sizeof(roz_abi_t),                     \
            (uint32_t)ROZ_CFG_MAX_COMMANDS, (uint32_t)ROZ_CFG_MAX_STATES,                    \
            (uint32_t)ROZ_CFG_ERROR_LEN, (uint32_t)ROZ_CFG_TELEMETRY_RING                    \
    }

/**
 * @brief Compare a caller's layout with the library's.
 * @param[in]  caller  ROZ_RUNTIME_LAYOUT_INIT, expanded in the caller
 * @param[out] err     names the first difference: "ROZ_CFG_MAX_COMMANDS is 16
 *                     in the application, 256 in libroz_core: ..."; may be NULL
 * @retval ROZ_OK      the same
 * @retval ROZ_ECONFIG different
 * Context: any; no I/O.
 */
ROZ_NODISCARD int roz_runtime_layout_check(const roz_runtime_layout_t *caller, char *err,
                                           size_t errlen);

/**
 * @brief roz_runtime_init() with the caller's layout made explicit; use
 *        roz_runtime_init(), which passes it.
 * @retval ROZ_ECONFIG the caller was built with another configuration than
 *                     the library: nothing is written to @p rt, and the
 *                     message goes to @p cfg's log callback when the config
 *                     struct itself has the same layout
 */
ROZ_NODISCARD int roz_runtime_init_layout(roz_runtime_t *rt, const roz_runtime_config_t *cfg,
                                          const roz_runtime_layout_t *caller);

/**
 * @brief Prepare a runtime (no I/O, no allocation).
 * @retval ROZ_EINVAL  bad configuration (invalid manifest, no port read/write)
 * @retval ROZ_ESTATE  the port is not open (roz_port_open() first)
 * @retval ROZ_ECONFIG this translation unit was built with other ROZ_CFG_*
 *                     options than libroz_core (roz_runtime_layout_check())
 * Context: start-up.
 */
ROZ_NODISCARD static inline int roz_runtime_init(roz_runtime_t *rt,
                                                 const roz_runtime_config_t *cfg)
{
    const roz_runtime_layout_t caller = ROZ_RUNTIME_LAYOUT_INIT;
    return roz_runtime_init_layout(rt, cfg, &caller);
}

/**
 * @brief Load, verify (ROZ_RUNTIME_VERIFY_TICKS ticks on a separate instance
 *        against the latest state, outputs discarded) and install a
 *        controller; it starts at tick 0 at the next tick boundary. When
 *        a controller is already running, it keeps running until then, and
 *        keeps running if the new one fails.
 * @param[in]  wasm    module bytes; must outlive the controller
 * @param[out] report  optional verification figures
 * @retval ROZ_OK      verified and scheduled
 * @retval ROZ_EINVAL  refused at load; roz_runtime_error() names the problem
 * @retval ROZ_EFAULT  failed verification (trap, overrun, non-finite
 *                     values, e-stop request); roz_runtime_error() says which
 * @retval ROZ_ESTATE  a swap is already pending
 * Context: not the tick thread; allocates (wasm3).
 */
ROZ_NODISCARD int roz_runtime_load(roz_runtime_t *rt, const uint8_t *wasm, size_t len,
                                   roz_verify_report_t *report);

/**
 * @brief Start: nothing is sent before the port's first state frame.
 * Context: start-up.
 */
ROZ_NODISCARD int roz_runtime_start(roz_runtime_t *rt);

/**
 * @brief One tick. @retval ROZ_OK, or ROZ_EFAULT while a fault is latched
 *        (the tick still ran: defaults went out).
 * Context: the tick thread; RT-safe; no allocation; bounded.
 */
int roz_runtime_tick(roz_runtime_t *rt);

/** @brief Set the e-stop input (latches ROZ_FAULT_ESTOP at the next tick).
 *  Context: any thread or ISR; wait-free. */
void roz_runtime_estop(roz_runtime_t *rt);

/**
 * @brief Clear every latched fault at the next tick. A controller that
 *        trapped or was stopped by its budget is rebuilt from its bytes and
 *        verified first (its instance is not reused); one that overran but
 *        returned normally is reused.
 * @retval ROZ_OK, or the error of rebuilding (the fault then stays latched)
 * Context: not the tick thread; may allocate.
 */
int roz_runtime_clear_faults(roz_runtime_t *rt);

/** @brief Latched faults (roz_fault_t bits). Context: any thread. */
unsigned roz_runtime_faults(const roz_runtime_t *rt);

/** @brief Name of one fault bit ("trap", ...). */
const char *roz_fault_name(unsigned fault_bit);

/** @brief Message of the first fault latched ("" if none). */
const char *roz_runtime_fault_message(const roz_runtime_t *rt);

/** @brief Last load/verify error ("" if none). */
const char *roz_runtime_error(const roz_runtime_t *rt);

/** @brief The commands handed to the port on the last tick (n_commands). */
const double *roz_runtime_last_commands(const roz_runtime_t *rt);

/** @brief This tick's state snapshot (n_states). */
const double *roz_runtime_last_state(const roz_runtime_t *rt);

/** @brief The active controller's targets before filtering (n_commands), or
 *  NULL without one. */
const double *roz_runtime_last_targets(const roz_runtime_t *rt);

/** @brief Stop, unload controllers; idempotent. Context: not the tick. */
void roz_runtime_deinit(roz_runtime_t *rt);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_RUNTIME_H */
