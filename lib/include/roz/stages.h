/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/stages.h
 * @brief The deploy sequence a vendor's deploy runs (zero torque, move to
 *        the stand pose over a set time, hold it, run the controller, stop
 *        in damping), executed by the runtime around the controller, and the
 *        hand-over that keeps the gains on the wire when a controller takes
 *        over (docs/deploy.md).
 *
 * Every stage's commands go through the safety filter like a controller's;
 * a latched fault stops the robot as it always does. The sequence is data
 * (roz_stages_config_t: the stand's command per channel, the move time, the
 * inputs that switch) checked against the manifest by roz_stages_check();
 * rozrun reads it from a deploy file (`--deploy FILE`). Portable: libc only.
 */
#ifndef ROZ_STAGES_H
#define ROZ_STAGES_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/atomic.h"
#include "roz/manifest.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The stages, in the order a deploy runs them. */
typedef enum roz_stage {
    ROZ_STAGE_NONE = 0, /**< no sequence configured: the controller drives from the start */
    ROZ_STAGE_ZERO,     /**< zero torque: stiffness, damping, effort and velocity 0 (within
                             each channel), positions at the measured ones */
    ROZ_STAGE_MOVE,     /**< every command blends linearly from its value at entry (a position
                             command: the measured position) to the stand's, over move_s */
    ROZ_STAGE_HOLD,     /**< the stand's commands */
    ROZ_STAGE_RUN,      /**< the controller drives, from tick 0, behind the gain hand-over */
    ROZ_STAGE_STOP,     /**< damping: stiffness and effort 0, damping stop_damping, positions
                             at the measured ones; left only by a request for ZERO */
} roz_stage_t;
#define ROZ_STAGE_COUNT 6

/** A button input is pressed at this value or above (a button input is 0 or 1). */
#define ROZ_STAGES_PRESSED 0.5

/** Ticks, in milliseconds of the control rate, that a hand-over keeps the
 *  outgoing gains at most (roz_stages_t): the incoming controller's
 *  stiffness and damping targets are raised to the values on the wire at
 *  the hand-over until each reaches that value or this time passes; then
 *  the filter's rate cap takes each to the incoming controller's own. The
 *  policy runner ramps its stiffness in over 1 s (roz_policy.h): 2 s covers
 *  it. Range 0 (no hold) .. 60000. */
#ifndef ROZ_CFG_HANDOVER_MS
#define ROZ_CFG_HANDOVER_MS 2000
#endif
#if ROZ_CFG_HANDOVER_MS < 0 || ROZ_CFG_HANDOVER_MS > 60000
#error "ROZ_CFG_HANDOVER_MS must be in 0..60000"
#endif

/** The sequence of one deployment. */
typedef struct roz_stages_config {
    const double *stand;  /**< n_commands: the stand's command for each channel (the default
                               pose on position commands, the stand's gains on stiffness and
                               damping, any other channel's value), each within its limits */
    double  move_s;       /**< MOVE's duration, s, in (0, 60] (unitree_rl_gym: 2) */
    double  stop_damping; /**< STOP's damping on every damping channel, within each
                               (Unitree's deploy: 8) */
    int32_t start;        /**< input (index into the manifest's inputs) that moves ZERO to
                               MOVE; -1 none (the API and rozrun only) */
    int32_t run;          /**< input that moves HOLD to RUN; -1 none */
    int32_t stand_input;  /**< input that moves RUN back to MOVE (then HOLD); -1 none */
    int32_t stop;         /**< input that moves any stage to STOP; -1 none */
} roz_stages_config_t;

/** Counters, written by the tick. */
typedef struct roz_stages_counters {
    uint64_t transitions;      /**< stage changes */
    uint64_t refused;          /**< requests (API or input) not allowed from the stage */
    uint64_t handovers;        /**< gain holds armed (a swap, or RUN's start) */
    uint64_t handover_raised;  /**< channel-ticks whose gain target the hold raised */
} roz_stages_counters_t;

/** The sequence and the hand-over's state: part of roz_runtime_t. */
typedef struct roz_stages {
    const roz_manifest_t *ROZ_PRIVATE(m);
    roz_stages_config_t   ROZ_PRIVATE(cfg);
    double   ROZ_PRIVATE(stand)[ROZ_CFG_MAX_COMMANDS];  /* the stand's commands, copied */
    double   ROZ_PRIVATE(from)[ROZ_CFG_MAX_COMMANDS];   /* MOVE: the values at entry */
    double   ROZ_PRIVATE(target)[ROZ_CFG_MAX_COMMANDS]; /* what the stage or hold sends */
    double   ROZ_PRIVATE(held)[ROZ_CFG_MAX_COMMANDS];   /* hand-over: gains held, NaN none */
    uint32_t ROZ_PRIVATE(move_ticks), ROZ_PRIVATE(elapsed);
    uint32_t ROZ_PRIVATE(hold_left);                    /* hand-over ticks left, 0 none */
    int      ROZ_PRIVATE(stage);                        /* tick: roz_stage_t */
    ROZ_ATOMIC(int) ROZ_PRIVATE(request);               /* any thread: a stage, -1 none */
    int      ROZ_PRIVATE(taken);                        /* tick: the request it took, -1 */
    ROZ_ATOMIC(int) ROZ_PRIVATE(published);             /* tick: the stage, for any thread */
    roz_stages_counters_t ROZ_PRIVATE(counters);
} roz_stages_t;

/**
 * @brief Check a sequence against a manifest.
 * @param[out] err  names the first problem: `stand[3] "left_knee_joint/position": 4:
 *                  outside its limits [-0.087, 2.88]`; may be NULL
 * @retval ROZ_OK     fits
 * @retval ROZ_EINVAL does not (NULL stand, a non-finite or out-of-range value, a move
 *                    time out of range, an input index not the manifest's)
 * Context: any; no I/O.
 */
ROZ_NODISCARD int roz_stages_check(const roz_manifest_t *m, const roz_stages_config_t *c,
                                   char *err, size_t errlen);

/** @brief The stage's name ("zero", "move", "hold", "run", "stop", "none"), or
 *  NULL for no stage. Context: any. */
const char *roz_stage_name(int stage);

/** @brief The stage named @p name, or -1. Context: any. */
int roz_stage_from_name(const char *name);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_STAGES_H */
