/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/fall.h
 * @brief Fall detection: the manifest's fall rule (roz_fall_rule_t) on each
 *        tick's state.
 *
 * The tilt is the angle between the base's z axis and the vertical, from
 * its orientation quaternion q = (x, y, z, w):
 * cos(tilt) = (w^2 + z^2 - x^2 - y^2) / |q|^2, the z component of gravity
 * projected into the base frame (up to sign), without normalising q first.
 * The robot is down once the tilt has exceeded max_tilt on N ticks in a
 * row, N = max(1, ceil(for_ms * control_rate_hz / 1000)); a quaternion
 * that is not finite, or is 0, leaves the count as it is (the port's
 * staleness and link checks cover a sensor gone silent). The runtime
 * latches ROZ_FAULT_FALL and the filter sends the fallen stop
 * (ROZ_STOP_FALLEN, roz/filter.h). docs/robot-toml.md ("Falls") gives the
 * rule and its defaults; SAFETY.md the rows and tests.
 *
 * Beyond the angle is cos(tilt) < cos(max_tilt), that cosine computed once
 * with roz_math.h: the same threshold, to the bit, on every target (a C
 * library's cos differs between glibc and newlib), and no libm linked.
 * ROZ_CFG_FALL 0 (roz/config.h) leaves the detector out: a manifest with a
 * rule is then refused (roz_runtime_init()), never run without it.
 *
 * Portable: no library call. Context: one detector per control loop, used
 * from the tick; no heap; O(1).
 */
#ifndef ROZ_FALL_H
#define ROZ_FALL_H

#include "roz/config.h"

#include <stdint.h>

#include "roz/manifest.h"
#include "roz/private.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A fall detector; caller-owned storage, fields private. */
typedef struct roz_fall {
    const roz_fall_rule_t *ROZ_PRIVATE(rule); /* NULL: no rule, never down */
    double   ROZ_PRIVATE(cos_max); /* cos(max_tilt) */
    uint32_t ROZ_PRIVATE(need);    /* ticks in a row */
    uint32_t ROZ_PRIVATE(run);     /* ticks in a row tilted, up to need */
} roz_fall_t;

/**
 * @brief Prepare a detector for @p m (a valid manifest): its fall rule, or
 *        none when m->fall is NULL. Count 0.
 * Context: start-up.
 */
void roz_fall_init(roz_fall_t *f, const roz_manifest_t *m);

/**
 * @brief Count one tick's @p state (n_states values).
 * @return 1 when the robot is down: tilted beyond the rule's angle on the
 *         last N ticks in a row (and on every tick after, while it stays
 *         so: a level); 0 otherwise, and always without a rule.
 * Context: tick; RT-safe; O(1).
 */
int roz_fall_tick(roz_fall_t *f, const double *state);

/**
 * @brief The tilt of the base in @p state under @p rule, rad in [0, pi];
 *        NaN when the quaternion is not finite or is 0.
 * Context: any; RT-safe; O(1).
 */
double roz_fall_tilt(const roz_fall_rule_t *rule, const double *state);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_FALL_H */
