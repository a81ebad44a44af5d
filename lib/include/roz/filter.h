/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @brief The safety filter: the last word on
 *        every command before it reaches a port.
 * @file roz/filter.h
 *
 * docs/architecture.md ("The safety filter") gives its five steps in order
 * (non-finite, clamp, rate cap, position limits with the limit margin, a
 * final clamp), the safe defaults, and how a stop is ramped; SAFETY.md §1
 * its promises with their tests.
 *
 * Context: one filter per control loop, used only from the tick; no heap, no
 * locks, bounded by the channel count. What the manifest implies is worked
 * out once, at init: the manifest must not change while a filter uses it.
 */
#ifndef ROZ_FILTER_H
#define ROZ_FILTER_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/hold.h"
#include "roz/manifest.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How the filter treats the controller's targets this tick. */
typedef enum roz_stop {
    ROZ_STOP_NONE = 0,    /**< run: filter the controller's targets */
    ROZ_STOP_CONTROLLED,  /**< ramp every channel to its safe default under the rate caps */
    ROZ_STOP_IMMEDIATE,   /**< e-stop: every channel at its safe default now */
    ROZ_STOP_FALLEN,      /**< the robot is down (ROZ_FAULT_FALL, roz/fall.h): damping
                               now, as a vendor's damping command: every stiffness 0,
                               every other channel at its safe default with a position
                               command following the measured position (never a hold:
                               no stiffness pushes into the ground) */
} roz_stop_t;

/** Counters, totals since init. */
typedef struct roz_filter_counters {
    uint64_t ticks;        /**< roz_filter_apply() calls */
    uint64_t clamps;       /**< values moved into [min, max] by the filter */
    uint64_t nonfinite;    /**< non-finite targets replaced by the safe default */
    uint64_t rate_caps;    /**< values held back by max_rate */
    uint64_t limit_stops;  /**< values held back by position-limit enforcement */
} roz_filter_counters_t;

/** One command channel's counters, totals since init. */
typedef struct roz_filter_channel_counters {
    uint32_t clamps;       /**< values moved into [min, max] */
    uint32_t rate_caps;    /**< values held back by max_rate */
    uint32_t limit_stops;  /**< values held back by position-limit enforcement */
    uint32_t stop_run;     /**< ticks in a row, up to the last one, that position-limit
                                enforcement held the channel back; 0 when the last tick
                                did not; saturates */
    uint32_t stop_longest; /**< the longest such run */
} roz_filter_channel_counters_t;

/* 1 where the filter can test a tick's targets on AVX2 vectors when the CPU
 * has them (x86-64, GCC or Clang: vector extensions, a target attribute and
 * __builtin_cpu_supports()); 0 elsewhere. Not an option: it follows the
 * compiler, and sizes the struct below. */
#if (defined(__GNUC__) || defined(__clang__)) && defined(__x86_64__)
#define ROZ__FILTER_AVX2 1
#else
#define ROZ__FILTER_AVX2 0
#endif

/** Filter state; caller-owned storage, fields private (roz/private.h). */
typedef struct roz_filter {
    const roz_manifest_t *ROZ_PRIVATE(manifest);
    double   ROZ_PRIVATE(dt);          /* 1 / control_rate_hz */
    int      ROZ_PRIVATE(primed);      /* last[] holds applied values */
    /* taken from the manifest at init: the commands step 4 applies to (the
     * velocities, then the efforts, paired with a position state) and each
     * position state's limit margin (roz_manifest_limit_margin()) */
    uint16_t ROZ_PRIVATE(paired)[ROZ_CFG_MAX_COMMANDS];
    uint16_t ROZ_PRIVATE(n_velocity);  /* paired[0, n_velocity): velocities */
    uint16_t ROZ_PRIVATE(n_paired);    /* paired[n_velocity, n_paired): efforts */
    uint16_t ROZ_PRIVATE(pair_state)[ROZ_CFG_MAX_COMMANDS]; /* paired[k]'s position state */
    double   ROZ_PRIVATE(pair_lo)[ROZ_CFG_MAX_COMMANDS];    /* its min + margin (efforts) */
    double   ROZ_PRIVATE(pair_hi)[ROZ_CFG_MAX_COMMANDS];    /* its max - margin (efforts) */
    double   ROZ_PRIVATE(margin)[ROZ_CFG_MAX_STATES > 0 ? ROZ_CFG_MAX_STATES : 1];
    uint8_t  ROZ_PRIVATE(pair_acts)[ROZ_CFG_MAX_COMMANDS]; /* this tick: step 4 may change the
                                                              channel's target (0 when unpaired) */
#if ROZ__FILTER_AVX2
    /* each command's min, max and rate cap (+inf: none) side by side, for
     * the test of a whole tick on vectors; avx2: the CPU has them */
    double   ROZ_PRIVATE(pass_min)[ROZ_CFG_MAX_COMMANDS];
    double   ROZ_PRIVATE(pass_max)[ROZ_CFG_MAX_COMMANDS];
    double   ROZ_PRIVATE(pass_rate)[ROZ_CFG_MAX_COMMANDS];
    int      ROZ_PRIVATE(avx2);
#endif
    int      ROZ_PRIVATE(running); /* channel_stop_run[] may not be all 0 */
    int      ROZ_PRIVATE(stopping); /* a stop is on: hold[] latched at its first tick */
    int      ROZ_PRIVATE(fallen);   /* the stop is ROZ_STOP_FALLEN: no hold */
    double   ROZ_PRIVATE(hold)[ROZ_CFG_MAX_COMMANDS]; /* ROZ_SAFE_HOLD channels: the safe
                                                         default this tick of the stop */
    roz_hold_from_t ROZ_PRIVATE(hold_from)[ROZ_CFG_MAX_COMMANDS]; /* ROZ_SAFE_HOLD channels:
                                                         what the stop latched */
    uint8_t  ROZ_PRIVATE(hold_gain)[ROZ_CFG_MAX_COMMANDS]; /* 1: a hold channel's stiffness */
    uint16_t ROZ_PRIVATE(hold_kp)[ROZ_CFG_MAX_COMMANDS]; /* ROZ_SAFE_HOLD channels: their
                                                        joint's stiffness command, or
                                                        UINT16_MAX: none */
    double   ROZ_PRIVATE(last)[ROZ_CFG_MAX_COMMANDS]; /* last applied value per channel */
    roz_filter_counters_t ROZ_PRIVATE(counters);
    uint32_t ROZ_PRIVATE(channel_clamps)[ROZ_CFG_MAX_COMMANDS];
    uint32_t ROZ_PRIVATE(channel_rate_caps)[ROZ_CFG_MAX_COMMANDS];
    uint32_t ROZ_PRIVATE(channel_limit_stops)[ROZ_CFG_MAX_COMMANDS];
    uint32_t ROZ_PRIVATE(channel_stop_run)[ROZ_CFG_MAX_COMMANDS];     /* see stop_run */
    uint32_t ROZ_PRIVATE(channel_stop_longest)[ROZ_CFG_MAX_COMMANDS]; /* see stop_longest */
} roz_filter_t;

/**
 * @brief Prepare a filter for a (valid) manifest; counters zero, not primed;
 *        the paired commands and the position states' margins taken from
 *        @p m.
 * @retval ROZ_OK     ready
 * @retval ROZ_EINVAL NULL argument or manifest failing roz_manifest_validate()
 * Context: start-up.
 */
ROZ_NODISCARD int roz_filter_init(roz_filter_t *f, const roz_manifest_t *m);

/**
 * @brief The safe default of command @p i given the state snapshot: for a
 *        position command paired with a position state, that state's value
 *        (clamped to the command's limits), or the last applied value when
 *        the state is not finite (position unknown: hold, don't jump); for
 *        every other channel the manifest default. While a stop is on, a
 *        channel whose safe_default is ROZ_SAFE_HOLD gives instead its
 *        hold (roz/hold.h) (not in a ROZ_STOP_FALLEN stop), latched at the
 *        stop's first tick by
 *        roz_filter_apply() from its last applied value (the setpoint the
 *        joint was held at), its stiffness's last applied value and the
 *        rule above's value then (the measured position), and computed
 *        each tick for the stiffness the stop sends; released by the first
 *        tick without a stop.
 * Context: RT-safe.
 */
double roz_filter_safe_default(const roz_filter_t *f, uint16_t i, const double *state);

/**
 * @brief Start from the safe defaults: the "last applied" values become the
 *        safe defaults for @p state, so the first rate cap ramps from there;
 *        stiffness and damping channels start at 0 (clamped to the channel),
 *        as the ports' start-up hold sends them.
 * Context: RT-safe.
 */
void roz_filter_prime(roz_filter_t *f, const double *state);

/**
 * @brief Filter one tick.
 * @param[in]  target  n_commands controller targets (ignored when stopping)
 * @param[in]  state   n_states values of this tick's snapshot
 * @param[in]  stop    run, controlled stop, e-stop or the fallen stop; the
 *                     first tick of a stop other than the fallen one (after
 *                     a tick without a stop, or with the fallen stop)
 *                     latches the ROZ_SAFE_HOLD channels' safe defaults
 *                     (roz_filter_safe_default())
 * @param[out] out     n_commands values for the port, each within [min, max];
 *                     may be @p target itself
 * Context: tick; RT-safe; O(n_commands).
 */
void roz_filter_apply(roz_filter_t *f, const double *target, const double *state,
                      roz_stop_t stop, double *out);

/** @brief The filter's totals. Context: the filter's thread (a runtime's
 *  filter: roz_runtime_stats() from any thread). */
void roz_filter_counters_get(const roz_filter_t *f, roz_filter_counters_t *out);

/**
 * @brief One command channel's counters.
 * @retval ROZ_OK    copied
 * @retval ROZ_ENOENT no such channel (@p out zeroed)
 * Context: the filter's thread.
 */
int roz_filter_channel_counters_get(const roz_filter_t *f, size_t channel,
                                    roz_filter_channel_counters_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_FILTER_H */
