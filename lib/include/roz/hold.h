/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @brief The hold: what every stop sends a joint (the filter's stops, every
 *        port's command watchdog, the hold after a trip, the exit), but the
 *        fallen stop, which sends damping (ROZ_STOP_FALLEN, roz/filter.h).
 * @file roz/hold.h
 *
 * A hold is computed from the last command the controller sent (never from
 * a frame a port made up) and the joint's measured position: the setpoint
 * keeps the torque of that command under the stiffness actually being sent
 * (kp_sent * (setpoint - measured) = kp * (commanded - measured)), and stays
 * within ROZ_HOLD_BAND_TICKS rate caps of the measured position, so a stop
 * never pushes a joint harder than the controller did, nor further than the
 * band past where it is. A joint without a position command holds its
 * measured position. SAFETY.md §7-8 give the rows; test/core/test_hold.c the
 * property over random gains, setpoints and stop kinds.
 *
 * Portable: libc only. Context: any; RT-safe; no heap.
 */
#ifndef ROZ_HOLD_H
#define ROZ_HOLD_H

#include "roz/config.h"

#include "roz/manifest.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The band, in rate caps (max_rate) of the position command, around the
 *  measured position that a hold's setpoint stays inside: enough for the
 *  sag of a standing humanoid's joints under gravity
 *  (test/ports/mujoco/test_mujoco_stops.c), little against a joint held
 *  back. A position command without a rate cap has no band: its hold is the
 *  measured position. */
#define ROZ_HOLD_BAND_TICKS 5.0

/** The relative (and absolute, N*m) rounding roz_hold_gain_cap() allows
 *  the torque before it holds a stiffness back. */
#define ROZ_HOLD_ROUNDING 1e-9

/** What a hold is computed from: the controller's last command for one
 *  joint and the joint's measured position. */
typedef struct roz_hold_from {
    double setpoint; /**< the position last commanded; NaN: none (no position command) */
    double kp;       /**< the stiffness last commanded; NaN: none (no stiffness command,
                          the robot's own gain) */
    double measured; /**< the measured position; NaN: unknown */
} roz_hold_from_t;

/** The setpoint that keeps a joint's torque when its stiffness changes
 *  from @p kp_was to @p kp_hold: measured + (kp_was / kp_hold) * (setpoint -
 *  measured), so kp_hold * (result - measured) = kp_was * (setpoint -
 *  measured). @p setpoint as it is when a value is not finite or kp_hold is
 *  not above 0. The building block of roz_hold_setpoint(). */
static inline double roz_hold_keep_torque(double setpoint, double measured, double kp_was,
                                          double kp_hold)
{
    double v = measured + (kp_was / kp_hold) * (setpoint - measured);
    return kp_hold > 0.0 && v - v == 0.0 ? v : setpoint; /* v - v: NaN unless finite */
}

/** The band of position command @p c: ROZ_HOLD_BAND_TICKS * its max_rate
 *  (0 without a rate cap). */
static inline double roz_hold_band(const roz_channel_t *c)
{
    return c->max_rate > 0.0 ? ROZ_HOLD_BAND_TICKS * c->max_rate : 0.0;
}

/**
 * @brief The hold's setpoint under the stiffness @p kp_sent.
 *
 * - position known, a position command: the torque kept
 *   (roz_hold_keep_torque(); the setpoint as it was without a stiffness
 *   command or with kp_sent not above 0), then within @p band of the
 *   measured position;
 * - position known, no position command (setpoint NaN): the measured
 *   position;
 * - position unknown: the setpoint (NaN when there is none either: no hold
 *   can be computed, and the caller must send no stiffness).
 *
 * |kp_sent * (result - measured)| <= |kp * (setpoint - measured)|, and the
 * result lies on the setpoint's side of the measured position, within
 * max(|setpoint - measured|, band) of it.
 */
double roz_hold_setpoint(const roz_hold_from_t *h, double kp_sent, double band);

/**
 * @brief The highest stiffness at most @p kp_sent, and not below @p kp_floor,
 *        under which the setpoint @p q_sent (a ramp may lag the hold's) keeps
 *        no more torque than the controller's last command (within
 *        ROZ_HOLD_ROUNDING): kp_sent itself when it does, or when the
 *        position or the command is unknown.
 */
double roz_hold_gain_cap(const roz_hold_from_t *h, double q_sent, double kp_sent,
                         double kp_floor);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HOLD_H */
