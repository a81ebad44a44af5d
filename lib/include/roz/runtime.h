/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/runtime.h
 * @brief The tick runtime: snapshot the state,
 *        run the controller, filter, hand the commands to the port, record.
 *
 * Firmware calls roz_runtime_tick() from its own timer or RTOS task
 * (docs/firmware.md); hosts drive it from a periodic thread
 * (roz/runner.h). All storage is in roz_runtime_t, which the caller owns
 * (make it static: it is large). docs/architecture.md describes one tick,
 * the threads and contexts (each function's Context: line says where it may
 * run), the faults and how they latch and clear, and the log ring.
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
#include "roz/fall.h"
#include "roz/filter.h"
#include "roz/identity.h"
#include "roz/inputs.h"
#include "roz/port.h"
#include "roz/log.h"
#include "roz/manifest.h"
#include "roz/monitor.h"
#include "roz/operator.h"
#include "roz/private.h"
#include "roz/recorder.h"
#include "roz/stages.h"

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
    ROZ_FAULT_ROBOT         = 1u << 6, /**< the port's read() returned ROZ_EROBOT: the robot
                                            reports a fault of its own (the port's fault()
                                            op names the part and the code) */
    ROZ_FAULT_COMMAND_TIMEOUT = 1u << 7, /**< the port's read() returned ROZ_EWATCHDOG:
                                            the tick wrote no command for the port's
                                            command timeout, and the port sent the robot
                                            its safe command on its own */
    ROZ_FAULT_FALL          = 1u << 8, /**< the robot is down: its base tilted beyond the
                                            manifest's fall rule (roz/fall.h); the fallen
                                            stop (ROZ_STOP_FALLEN: damping, no stiffness)
                                            wins over every other stop. A level: while the
                                            base stays tilted, a clear is followed by the
                                            next tick's latch */
} roz_fault_t;
#define ROZ_FAULT_KIND_COUNT 9
/** Faults answered by an immediate stop; the others ramp. A robot that
 *  restarted (LINK), or that the port's command watchdog switched to its
 *  safe command (COMMAND_TIMEOUT), no longer tracks the commands a ramp
 *  would continue from, so its first command is the safe default itself. */
#define ROZ_FAULT_IMMEDIATE_MASK                                                              \
    (ROZ_FAULT_ESTOP | ROZ_FAULT_ESTOP_REQUEST | ROZ_FAULT_LINK | ROZ_FAULT_COMMAND_TIMEOUT)

/** Log events the ring holds between two roz_runtime_log_drain() calls. */
#ifndef ROZ_RUNTIME_LOG_RING
#define ROZ_RUNTIME_LOG_RING 64
#endif
#if ROZ_RUNTIME_LOG_RING < 2 || (ROZ_RUNTIME_LOG_RING & (ROZ_RUNTIME_LOG_RING - 1)) != 0
#error "ROZ_RUNTIME_LOG_RING must be a power of two, at least 2"
#endif

/** Monitors of the application's own threads (a host runner's) that
 *  roz_runtime_log_drain() drains besides the runtime's and the port's. */
#define ROZ_RUNTIME_WATCHED 2

/** Configuration; roz_runtime_config_default() fills the defaults. */
typedef struct roz_runtime_config {
    const roz_manifest_t *manifest;
    roz_port_t            port;
    uint32_t     stale_ticks;   /**< ticks without a fresh frame before STALE; default 10 */
    /* budgets: 0 = the default, ROZ_BUDGET_OFF = off (roz/controller.h) */
    uint64_t     budget_ns;     /**< process() wall-clock budget per tick (deadline, checked
                                     while it runs, needs a clock); 0: half the period;
                                     ROZ_BUDGET_OFF: none */
    uint64_t     fuel_per_tick; /**< process() fuel per tick (deterministic, see
                                     roz/controller.h); 0: ROZ_CFG_FUEL_PER_SECOND /
                                     control_rate_hz (refused if that rounds to 0);
                                     ROZ_BUDGET_OFF: unmetered */
    uint64_t     fuel_per_tick_max; /**< the most fuel per tick a controller may declare
                                     it needs (roz.fuel, ROZ_FUEL_PER_TICK of
                                     roz_controller.h), which it then gets instead of
                                     fuel_per_tick, verification included; a larger
                                     declaration is refused at load. 0:
                                     ROZ_CFG_FUEL_MAX_PER_SECOND / control_rate_hz;
                                     ROZ_BUDGET_OFF: any. Unmetered runtimes ignore
                                     declarations */
    roz_clock_fn clock;         /**< monotonic clock for budgets and the monitor; NULL = none
                                     (then no overrun is detected and times read 0) */
    void        *clock_ctx;
    roz_clock_fn deadline_clock; /**< what the process() deadline (budget_ns) counts, read
                                     on the tick's thread only; NULL (default): @c clock,
                                     the wall clock, which also counts the time other
                                     threads preempt the tick. A host whose tick is not
                                     real-time passes the tick thread's CPU time
                                     (roz_clock_thread_cpu_ns(), roz/hal/clock.h):
                                     docs/budget.md */
    void        *deadline_clock_ctx;
    int          monitor_jitter; /**< 1: check each tick's start against the period
                                     (ticks driven by a timer; default); 0: ticks run
                                     back to back in simulated time */
    roz_log_fn   log;           /**< warnings and faults, called by roz_runtime_log_drain()
                                     (never from the tick); NULL = silent */
    void        *log_ctx;
    int          allow_foreign_controller; /**< 0 (default): roz_runtime_load() refuses a
                                     controller whose identity (roz/identity.h) names another
                                     robot or another channel table; 1: loads it (it runs
                                     behind the same filter, but its indices may mean other
                                     channels). Controllers without an identity load either way */
    roz_recorder_t *recorder;   /**< the flight recorder every tick pushes its record into
                                     (roz/recorder.h), set up on the same manifest; NULL
                                     (default): none */
    roz_load_scratch_t *load_scratch; /**< where the module validator works while a
                                     controller loads (roz/controller.h,
                                     ROZ_CONTROLLER_SCRATCH_BYTES); NULL (default): the
                                     loader thread's stack; firmware passes static storage.
                                     The runtime's loads run one at a time */
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
    uint64_t fuel_declared;    /**< what the controller declared it needs (roz.fuel); 0
                                    none */
    uint64_t max_stack;        /**< deepest C stack of any verify tick, bytes */
    roz_identity_t identity;   /**< the robot the controller says it was built for */
    roz_identity_match_t identity_match; /**< that against this robot: OTHER_ROBOT or
                                    TABLE_CHANGED when the load was refused for it, or
                                    allowed by allow_foreign_controller */
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

/** Everything the runtime counts, as of the end of the last tick (the
 *  loader's counters as of now): roz_runtime_stats(). */
typedef struct roz_runtime_stats {
    roz_runtime_counters_t runtime;
    roz_filter_counters_t  filter;          /**< the safety filter's totals */
    roz_abi_counters_t     abi;             /**< the calls of every controller that
                                                 drove the robot since init (verification
                                                 runs not counted) */
    int64_t                controller_tick; /**< the tick number process() sees next */
    uint64_t               last_process_ns; /**< the last process() call, wall clock */
} roz_runtime_stats_t;

/** 32-bit words the tick publishes roz_runtime_stats_t in (private). */
#define ROZ_RUNTIME_STATS_WORDS ((sizeof(roz_runtime_stats_t) + 3u) / 4u)

/** One controller slot. */
typedef struct roz_runtime_slot {
    roz_controller_t ROZ_PRIVATE(ctrl);
    roz_abi_t        ROZ_PRIVATE(abi);
    double           ROZ_PRIVATE(target)[ROZ_CFG_MAX_COMMANDS];
    const uint8_t   *ROZ_PRIVATE(wasm);     /* bytes (caller's), kept to rebuild after a trap */
    size_t           ROZ_PRIVATE(wasm_len);
    const struct roz_aot_module *ROZ_PRIVATE(aot); /* the compiled controller, NULL: wasm3's */
    uint64_t         ROZ_PRIVATE(hash);     /* roz_recorder_hash() of the bytes, for the recorder */
    uint64_t         ROZ_PRIVATE(fuel);     /* its fuel per tick (declared or the default) */
    ROZ_ATOMIC(int)  ROZ_PRIVATE(dead);     /* 1: trapped or stopped by its budget; set by the tick
                                  before the fault is published, never run again */
} roz_runtime_slot_t;

/** The first fault's record (private): numbers and the controller's text,
 *  written by the tick under a sequence counter, formatted by readers. */
typedef struct roz_runtime_fault_rec {
    ROZ_ATOMIC(unsigned) ROZ_PRIVATE(seq);       /* odd while the tick writes */
    ROZ_ATOMIC(unsigned) ROZ_PRIVATE(bit);       /* the fault, 0 none */
    ROZ_ATOMIC(unsigned) ROZ_PRIVATE(latch);     /* latch sequence number of that fault */
    ROZ_ATOMIC(unsigned) ROZ_PRIVATE(num)[4];    /* its figures (see runtime.c) */
    ROZ_ATOMIC(unsigned char) ROZ_PRIVATE(text)[ROZ_CFG_ERROR_LEN]; /* the controller's message, or "" */
} roz_runtime_fault_rec_t;

/** One queued log event (private). */
typedef struct roz_runtime_log_event {
    uint8_t  ROZ_PRIVATE(level);          /* roz_log_level_t */
    uint8_t  ROZ_PRIVATE(code);           /* what happened (runtime.c) */
    uint16_t ROZ_PRIVATE(kind);           /* fault bit index, monitor kind */
    uint32_t ROZ_PRIVATE(latch);          /* latch sequence number of a fault */
    uint64_t ROZ_PRIVATE(num)[4];
} roz_runtime_log_event_t;

/** The runtime. Large: give it static storage. Fields are private. */
typedef struct roz_runtime {
    roz_runtime_config_t   ROZ_PRIVATE(cfg);
    roz_filter_t           ROZ_PRIVATE(filter);
    roz_monitor_t          ROZ_PRIVATE(monitor);
    roz_runtime_counters_t ROZ_PRIVATE(counters);
    roz_metric_ring_t      ROZ_PRIVATE(metrics);
    roz_runtime_slot_t     ROZ_PRIVATE(slot)[2];
    ROZ_ATOMIC(int)        ROZ_PRIVATE(active);       /* index of the driving slot, -1 none; written by the tick */
    ROZ_ATOMIC(int)        ROZ_PRIVATE(pending);      /* swap: slot to install at the next tick, -1 none */
    /* Faults: latched bits (low ROZ_FAULT_KIND_COUNT) | latch sequence
     * number << ROZ_FAULT_KIND_COUNT. Written by
     * the tick only; a new latch bumps the sequence, so a clear can tell the
     * faults it saw from those latched since. */
    ROZ_ATOMIC(unsigned)   ROZ_PRIVATE(faults);
    ROZ_ATOMIC(unsigned)   ROZ_PRIVATE(clear_request);/* the faults word a clear saw, 0 none; taken by exchange */
    ROZ_ATOMIC(unsigned)   ROZ_PRIVATE(estop_level);  /* the e-stop input: 1 pressed */
    ROZ_ATOMIC(unsigned)   ROZ_PRIVATE(estop_press);  /* a press the tick has not seen; taken by exchange */
    ROZ_ATOMIC(unsigned)   ROZ_PRIVATE(remote_estop); /* the remote's last frame held its e-stop chord */
    ROZ_ATOMIC(unsigned)   ROZ_PRIVATE(loader_busy);  /* 1 while a load or rebuild runs; taken by exchange */
    /* wasm3's loader (roz_controller_load_in), set by roz_runtime_load(): an
     * image that loads only compiled controllers links no interpreter */
    int (*ROZ_PRIVATE(load_wasm))(roz_controller_t *c, const uint8_t *wasm, size_t len,
                                  roz_abi_t *abi, roz_load_scratch_t *scratch);
    uint32_t               ROZ_PRIVATE(latch_seq);    /* tick: last latch sequence number */
    uint32_t               ROZ_PRIVATE(latch_stamp)[ROZ_FAULT_KIND_COUNT]; /* tick: each bit's latch */
    roz_runtime_fault_rec_t ROZ_PRIVATE(first_fault);
    roz_runtime_log_event_t ROZ_PRIVATE(log_ring)[ROZ_RUNTIME_LOG_RING];
    ROZ_ATOMIC(unsigned)   ROZ_PRIVATE(log_head);     /* written by the tick */
    ROZ_ATOMIC(unsigned)   ROZ_PRIVATE(log_tail);     /* written by the drain */
    ROZ_ATOMIC(unsigned)   ROZ_PRIVATE(log_dropped);  /* events the ring had no room for */
    uint32_t               ROZ_PRIVATE(log_dropped_seen); /* drain: drops already reported */
    roz_monitor_t         *ROZ_PRIVATE(watched)[ROZ_RUNTIME_WATCHED]; /* drain: more monitors */
    int                    ROZ_PRIVATE(nonfinite_warned); /* tick: the first-frame warning went out */
    int64_t                ROZ_PRIVATE(ctrl_tick);    /* tick number the controller sees */
    /* tick: this tick's account for the recorder (roz_record_t) */
    uint32_t               ROZ_PRIVATE(rec_flags);
    uint32_t               ROZ_PRIVATE(rec_cleared);
    int32_t                ROZ_PRIVATE(rec_read_rc);
    int64_t                ROZ_PRIVATE(rec_ctrl_tick);
    const double          *ROZ_PRIVATE(last_target); /* tick: what drove it (the recorder's target) */
    int                    ROZ_PRIVATE(have_state);
    roz_fall_t             ROZ_PRIVATE(fall);         /* tick: the manifest's fall rule */
    uint32_t               ROZ_PRIVATE(stale_count);
    double                 ROZ_PRIVATE(state)[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    double                 ROZ_PRIVATE(out)[ROZ_CFG_MAX_COMMANDS];
    /* this tick's state for verification on another thread; read() fills
     * its spare slot */
    roz_buffer_t           ROZ_PRIVATE(snapshot);
    double                 ROZ_PRIVATE(snapshot_slots)[3 * (ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1)];
    double                 ROZ_PRIVATE(verify_state)[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    /* the operator's inputs: set by any thread, taken by the tick into
     * state[n_states + k] */
    roz_inputs_t           ROZ_PRIVATE(inputs);
    /* the deploy sequence and the hand-over's gain hold (roz/stages.h) */
    roz_stages_t           ROZ_PRIVATE(stages);
    uint64_t               ROZ_PRIVATE(last_process_ns);
    char                   ROZ_PRIVATE(fault_msg)[ROZ_CFG_ERROR_LEN + 64]; /* roz_runtime_fault_message() */
    char                   ROZ_PRIVATE(error)[ROZ_CFG_ERROR_LEN];     /* last load/verify error */
    int                    ROZ_PRIVATE(started);
    roz_abi_counters_t     ROZ_PRIVATE(abi_retired);   /* tick: ABI counters of replaced slots */
    ROZ_ATOMIC(uint32_t)   ROZ_PRIVATE(swaps_refused); /* loader: counters.swaps_refused */
    ROZ_ATOMIC(uint32_t)   ROZ_PRIVATE(rebuilds);      /* loader: counters.rebuilds */
    /* roz_runtime_stats_t as the tick published it (lib/src/seqlock.h) */
    ROZ_ATOMIC(uint32_t)   ROZ_PRIVATE(stats_seq);
    ROZ_ATOMIC(uint32_t)   ROZ_PRIVATE(stats_words)[ROZ_RUNTIME_STATS_WORDS];
} roz_runtime_t;

/** @brief Defaults for everything but manifest and port.
 *  Context: start-up. */
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
    uint32_t scratch_bytes;    /**< sizeof(roz_load_scratch_t): the ROZ_CFG_WASM_MAX_*
                                    limits of the validator (load_scratch) */
} roz_runtime_layout_t;

/** Raised whenever the fields of a public struct change: a manifest table
 *  or a configuration laid out for other fields would be misread. */
#define ROZ_RUNTIME_LAYOUT_VERSION 11u

/** The layout of the translation unit that expands it. */
#define ROZ_RUNTIME_LAYOUT_INIT                                                              \
    {                                                                                        \
        ROZ_RUNTIME_LAYOUT_VERSION, (uint32_t)sizeof(roz_runtime_t),                         \
            (uint32_t)sizeof(roz_runtime_config_t), (uint32_t)sizeof(roz_controller_t),      \
            (uint32_t)sizeof(roz_filter_t), (uint32_t)sizeof(roz_abi_t),                     \
            (uint32_t)ROZ_CFG_MAX_COMMANDS, (uint32_t)ROZ_CFG_MAX_STATES,                    \
            (uint32_t)ROZ_CFG_ERROR_LEN, (uint32_t)ROZ_CFG_TELEMETRY_RING,                   \
            (uint32_t)sizeof(roz_load_scratch_t)                                             \
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
 * Context: start-up.
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
 * @brief Load, check the robot the controller was built for (its identity,
 *        roz/identity.h), verify (ROZ_RUNTIME_VERIFY_TICKS ticks on a separate
 *        instance against the latest state, outputs discarded) and install a
 *        controller; it starts at tick 0 at the next tick boundary. When
 *        a controller is already running, it keeps running until then, and
 *        keeps running if the new one fails.
 * @param[in]  wasm    module bytes; must outlive the controller
 * @param[out] report  optional verification figures
 * @retval ROZ_OK      verified and scheduled
 * @retval ROZ_EINVAL  refused at load; roz_runtime_error() names the problem,
 *                     among them a controller built for another robot or
 *                     channel table (its "roz.manifest" identity; see
 *                     allow_foreign_controller), naming both robots
 * @retval ROZ_EVERIFY failed verification (trap, overrun, non-finite
 *                     values, e-stop request); roz_runtime_error() says which
 * @retval ROZ_ESTATE  a swap is already pending, or another load or a
 *                     rebuild (roz_runtime_clear_faults()) is running
 * Context: a loader thread, not the tick; blocks while it verifies;
 *          allocates (wasm3).
 */
ROZ_NODISCARD int roz_runtime_load(roz_runtime_t *rt, const uint8_t *wasm, size_t len,
                                   roz_verify_report_t *report);

/**
 * @brief roz_runtime_load() for a controller compiled into the image ahead
 *        of time (roz/aot.h): the same identity and declared-fuel checks
 *        (on the module's roz.* sections, kept by the build), the same
 *        verification, the same swap at a tick boundary; the recorder sees
 *        the hash of the module it was compiled from.
 * @param[in] aot  the compiled controller (ROZ_AOT_DECLARE); static
 * @return as roz_runtime_load(); ROZ_ENOMEM when every instance of @p aot
 *         is in use (ROZ_CFG_AOT_INSTANCES)
 * Context: a loader thread, not the tick; blocks while it verifies.
 */
ROZ_NODISCARD int roz_runtime_load_aot(roz_runtime_t *rt, const struct roz_aot_module *aot,
                                       roz_verify_report_t *report);

/**
 * @brief Arm the tick: before this call roz_runtime_tick() neither reads nor
 *        writes the port (it returns ROZ_ESTATE), so the application decides
 *        when the robot may first be driven, after the port is active and a
 *        controller loaded. Once started, nothing is sent before the port's
 *        first usable state frame (one in which every position paired with a
 *        position command is finite: a command that holds an unknown
 *        position would jump).
 * @retval ROZ_OK     started
 * @retval ROZ_ESTATE already started
 * Context: start-up, before the tick runs.
 */
ROZ_NODISCARD int roz_runtime_start(roz_runtime_t *rt);

/**
 * @brief One tick, in this order: hand-overs from other threads (a pending
 *        swap, then a clear), the e-stop input, the port's read() into a
 *        scratch frame (the state snapshot's spare slot), the controller
 *        unless a fault is latched, the filter, the port's write().
 * @retval ROZ_OK     no fault latched
 * @retval ROZ_EFAULT a fault is latched (the tick still ran: defaults went out)
 * @retval ROZ_ESTATE not started (roz_runtime_start()): nothing read or sent
 * Context: the tick thread only; RT-safe; no allocation, no formatting,
 *          no locks; bounded.
 */
ROZ_NODISCARD int roz_runtime_tick(roz_runtime_t *rt);

/**
 * @brief Set the e-stop input level: 1 pressed, 0 released. A press latches
 *        ROZ_FAULT_ESTOP at the start of the next tick (before the controller
 *        runs; every command at its safe default at once), even if the input
 *        is released again before that tick. ROZ_FAULT_ESTOP cannot be
 *        cleared while the input is pressed.
 * Context: any thread or an ISR; wait-free (one or two atomic stores).
 */
void roz_runtime_estop_set(roz_runtime_t *rt, int pressed);

/**
 * @brief A momentary e-stop press (an edge: a press and release): latches
 *        ROZ_FAULT_ESTOP at the start of the next tick. A clear before that
 *        tick does not lose it; a clear after it clears the fault.
 * Context: any thread or an ISR; wait-free (one atomic store).
 */
void roz_runtime_estop(roz_runtime_t *rt);

/**
 * @brief An operator input's latest value (robot.toml's [[manifest.inputs]],
 *        roz/inputs.h): the next tick takes it into state n_states + @p k,
 *        after its rules (a non-finite value refused, an out-of-range one
 *        clamped, both counted; every change at most max_rate_of_change a
 *        tick; no value for stale_after_ms of ticks: back to the default).
 * @retval ROZ_OK     stored
 * @retval ROZ_EINVAL @p k is not an input of the manifest
 * @retval ROZ_ESTATE another thread's set of input @p k was in progress: dropped
 * Context: any thread; wait-free (no loop, no lock; roz/inputs.h); no heap.
 */
int roz_runtime_input_set(roz_runtime_t *rt, uint32_t k, double value);

/** @brief The inputs' counters as the last tick left them (roz/inputs.h).
 *  Context: the tick's thread, or after the ticks stopped. */
const roz_inputs_counters_t *roz_runtime_input_counters(const roz_runtime_t *rt);

/**
 * @brief Run the deploy sequence @p c around the controller (roz/stages.h,
 *        docs/deploy.md): the robot starts in ZERO (zero torque), and the
 *        stages change by the inputs @p c names, roz_runtime_stage_request()
 *        or MOVE's end. Without this call the controller drives from the
 *        first tick, as before (ROZ_STAGE_NONE).
 * @param[out] err  why @p c does not fit the manifest (roz_stages_check())
 * @retval ROZ_OK     taken (copied)
 * @retval ROZ_EINVAL @p c does not fit the manifest
 * @retval ROZ_ESTATE the runtime is started already
 * Context: start-up, after roz_runtime_init(), before roz_runtime_start().
 */
ROZ_NODISCARD int roz_runtime_stages_set(roz_runtime_t *rt, const roz_stages_config_t *c,
                                         char *err, size_t errlen);

/**
 * @brief Ask for a stage at the next tick: MOVE (from ZERO: start; from RUN:
 *        back to the stand), RUN (from HOLD, with a controller loaded), STOP
 *        (from any), ZERO (from STOP). The latest request wins; one not
 *        allowed from the stage the tick finds is dropped and counted
 *        (roz_runtime_stages_counters()); while a fault is latched only STOP
 *        is taken.
 * @retval ROZ_OK     stored
 * @retval ROZ_EINVAL not one of those stages
 * @retval ROZ_ESTATE no sequence (roz_runtime_stages_set())
 * Context: any thread; wait-free (one atomic store).
 */
int roz_runtime_stage_request(roz_runtime_t *rt, roz_stage_t stage);

/** @brief The sequence roz_runtime_stages_set() took (its stand the runtime's
 *  copy), or NULL without one: what a recording writes once (/roz/deploy).
 *  Context: start-up, or the tick's thread. */
const roz_stages_config_t *roz_runtime_stages_config(const roz_runtime_t *rt);

/** @brief The stage as of the last tick (ROZ_STAGE_NONE without a sequence).
 *  Context: any thread; wait-free. */
roz_stage_t roz_runtime_stage(const roz_runtime_t *rt);

/** @brief The sequence's and the hand-over's counters as the last tick left
 *  them. Context: the tick's thread, or after the ticks stopped. */
const roz_stages_counters_t *roz_runtime_stages_counters(const roz_runtime_t *rt);

/**
 * @brief Clear the latched faults this call sees, at the next tick. A
 *        fault that latches after this call looked (even one of the same
 *        kind) stays latched; a call that sees no fault changes nothing.
 *        A controller instance that trapped or was stopped by its budget is
 *        rebuilt from its bytes and verified first (it is never run again);
 *        one that overran but returned normally is reused.
 * @retval ROZ_OK      the faults seen are cleared at the next tick
 * @retval ROZ_ESTATE  the e-stop input is still pressed (or the remote's last
 *                     frame held its e-stop chord, roz/operator.h): every fault seen
 *                     but ROZ_FAULT_ESTOP is cleared; or a load or rebuild
 *                     is running on another thread: nothing is cleared
 * @retval other       the error of rebuilding (nothing is cleared;
 *                     roz_runtime_error() says why)
 * Context: a loader thread, not the tick; may block and allocate while it
 *          rebuilds.
 */
ROZ_NODISCARD int roz_runtime_clear_faults(roz_runtime_t *rt);

/** @brief Latched faults (roz_fault_t bits).
 *  Context: any thread; wait-free. */
unsigned roz_runtime_faults(const roz_runtime_t *rt);

/** @brief Name of one fault bit ("trap", ...). Context: any thread. */
const char *roz_fault_name(unsigned fault_bit);

/**
 * @brief Copy the message of the first fault latched since the faults were
 *        last all clear into @p buf ("" if none), truncated to @p len.
 *        Consistent: never half of one message and half of another. A fault
 *        seen in roz_runtime_faults() has its message here (it is written
 *        before the fault is published).
 * @retval ROZ_OK     copied
 * @retval ROZ_EINVAL @p buf NULL or @p len 0
 * @retval ROZ_ESTATE the tick kept rewriting it (1000 tries); buf holds ""
 * Context: any thread; never blocks the tick (the tick writes it wait-free;
 *          this retries).
 */
int roz_runtime_fault_message_copy(const roz_runtime_t *rt, char *buf, size_t len);

/**
 * @brief roz_runtime_fault_message_copy() into storage of @p rt, returned.
 * Context: one thread at a time (the supervisor, or the tick's thread between
 *          ticks); from several threads use roz_runtime_fault_message_copy().
 */
const char *roz_runtime_fault_message(roz_runtime_t *rt);

/**
 * @brief Format the queued log events (faults, warnings, the monitor's
 *        threshold warnings) and pass each to the configured log callback,
 *        with a line for events dropped since the last drain; then what the
 *        port's threads kept (roz_port_drain(), to the port's own log
 *        callback) and the watched monitors (roz_runtime_watch_monitor()).
 *        The one call an application makes: no thread roz runs (the tick,
 *        a port's) formats text or calls the log callback.
 * @return the number of events and lines drained
 * Context: one non-real-time thread at a time (never the tick's RT thread;
 *          an application's idle loop between ticks is fine); formats text.
 */
size_t roz_runtime_log_drain(roz_runtime_t *rt);

/**
 * @brief Drain @p m too in roz_runtime_log_drain() (roz_monitor_drain():
 *        its warnings go to the log callback given to its init), e.g. a
 *        host runner's (roz/runner.h).
 * @retval ROZ_OK     watched (also when it already was)
 * @retval ROZ_EINVAL NULL
 * @retval ROZ_ENOSPC ROZ_RUNTIME_WATCHED monitors are watched already
 * Context: the thread that drains, before it drains.
 */
int roz_runtime_watch_monitor(roz_runtime_t *rt, roz_monitor_t *m);

/** @brief Log events dropped because the ring was full, since init.
 *  Context: any thread. */
uint32_t roz_runtime_log_dropped(const roz_runtime_t *rt);

/**
 * @brief A consistent copy of everything the runtime counts: its own
 *        counters, the safety filter's and the driving controller's ABI
 *        counters, as the tick published them at the end of the last tick
 *        (zeros before the first), and the loader's counters as of now.
 * @retval ROZ_OK     copied
 * @retval ROZ_EINVAL NULL argument
 * @retval ROZ_ESTATE the tick kept republishing (1000 tries): @p out zeroed
 * Context: any thread; never blocks the tick (it publishes wait-free; this
 *          retries).
 */
ROZ_NODISCARD int roz_runtime_stats(const roz_runtime_t *rt, roz_runtime_stats_t *out);

/**
 * @brief One command channel's safety-filter counters.
 * @retval ROZ_OK     copied
 * @retval ROZ_ENOENT no such channel (@p out zeroed)
 * Context: the tick's thread between ticks, or after the tick stopped.
 */
int roz_runtime_channel_counters(const roz_runtime_t *rt, size_t channel,
                                 roz_filter_channel_counters_t *out);

/**
 * @brief The runtime's latency monitor (read, write, process, tick, and the
 *        tick's jitter when monitor_jitter is set), for roz_monitor_snapshot().
 * Context: any thread (snapshots are consistent while the tick records).
 */
const roz_monitor_t *roz_runtime_monitor(const roz_runtime_t *rt);

/**
 * @brief Take the oldest metric the controllers emitted (telemetry.emit_metric;
 *        verification runs emit none).
 * @retval 1 one metric taken into @p out
 * @retval 0 none queued
 * Context: one consumer thread at a time; wait-free.
 */
int roz_runtime_metric_pop(roz_runtime_t *rt, roz_metric_t *out);

/** @brief Metrics lost to a full ring (ROZ_CFG_TELEMETRY_RING) since init.
 *  Context: any thread. */
uint32_t roz_runtime_metrics_dropped(const roz_runtime_t *rt);

/** @brief The configuration the runtime runs with, defaults resolved (e.g.
 *  the budgets init chose). Context: any thread after init (it is not
 *  changed after init). */
const roz_runtime_config_t *roz_runtime_config(const roz_runtime_t *rt);

/** @brief Last load/verify error ("" if none). Context: the loader thread. */
const char *roz_runtime_error(const roz_runtime_t *rt);

/** @brief The commands handed to the port on the last tick (n_commands).
 *  Context: the tick's thread (between ticks) or after it stopped. */
const double *roz_runtime_last_commands(const roz_runtime_t *rt);

/** @brief The last good state frame (n_states). Context: as above. */
const double *roz_runtime_last_state(const roz_runtime_t *rt);

/** @brief The targets that drove the last tick, before the filter
 *  (n_commands): the deploy stage's commands while a stage drives (move,
 *  hold, stop, zero; roz/stages.h), else the active controller's; NULL
 *  before the first tick, or with neither. What the flight recorder records
 *  as the tick's targets (roz_record_t.target, /roz/target). The hand-over's
 *  gain hold (roz/stages.h) and the filter come after: the commands the
 *  port was given are roz_runtime_last_commands(). Context: as above. */
const double *roz_runtime_last_targets(const roz_runtime_t *rt);

/** @brief Stop and unload controllers; idempotent. A port given this
 *  runtime's operator sink (roz_runtime_operator_sink()) must be closed
 *  first: its threads may hand frames to the runtime until then.
 *  Context: not the tick. */
void roz_runtime_deinit(roz_runtime_t *rt);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_RUNTIME_H */
