/* SPDX-License-Identifier: Apache-2.0 */
/* Private to the G1 port: its rules of the [hardware] keys (the joints and
 * channels bound, the parameters read), which its open and its registered
 * check (roz_unitree_g1_check()) run alike. No DDS, no IDL type. */
#ifndef ROZ_G1_RULES_H
#define ROZ_G1_RULES_H

#include <stddef.h>

#include "roz/port/unitree_g1.h"

/* The port's parameters: the rows its info shows, the bounds and defaults
 * roz__g1_parse_params() reads. */
#define ROZ__G1_PARAM_ROWS                                                                      \
    ROZ_DDS_PARAM_INFO("0"),                                                                    \
        ROZ_PORT_PARAM_TEXT_ROW("mode_pr", "PR|AB|0|1", "PR",                                   \
                                "the ankles' and waist's control mode"),                        \
        ROZ_DDS_HOLD_PARAM_INFO,                                                                \
        ROZ_PORT_PARAM_TEXT_ROW("peer", "robot|unitree_mujoco", "robot",                        \
                                "unitree_mujoco: Unitree's simulator on lo (no state CRC, no "  \
                                "tick); never a robot")

/* Binds the manifest's joints and IMU to motor slots and channels; every
 * channel must find its place. ROZ_ENOENT (a joint: not the G1's, listed
 * twice, none listed, or without a channel) or ROZ_EINVAL (a channel), err
 * naming it. */
int roz__g1_bind(roz_unitree_g1_t *g1, const roz_manifest_t *m, char *err, size_t errlen);

/* Reads @p p into @p g1 (bound first: the damping gains' range is the bound
 * channels'). Without @p report (the open): ROZ_EINVAL at the first problem,
 * err saying it. With it (roz_unitree_g1_check()): each problem written to
 * err and reported (rule "unknown-key" or "g1-param"), going on where the
 * next key does not depend on it; ROZ_EINVAL after at least one report. */
int roz__g1_parse_params(roz_unitree_g1_t *g1, const roz_params_t *p, char *err,
                         size_t errlen, roz_unitree_g1_problem_fn report, void *ctx);

#endif /* ROZ_G1_RULES_H */
