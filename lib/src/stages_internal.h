/* SPDX-License-Identifier: Apache-2.0 */
/* The runtime's side of the deploy sequence and the hand-over (roz/stages.h),
 * called by runtime.c's tick only. */
#ifndef ROZ_STAGES_INTERNAL_H
#define ROZ_STAGES_INTERNAL_H

#include "roz/stages.h"

/** @brief No sequence, no hold (ROZ_STAGE_NONE). Context: start-up. */
void roz__stages_init(roz_stages_t *s, const roz_manifest_t *m);

/** @brief Take @p c (checked) and start at ZERO. Context: start-up. */
void roz__stages_configure(roz_stages_t *s, const roz_stages_config_t *c, uint32_t rate_hz);

/**
 * @brief One tick's transition: a request from the API, else the inputs
 *        (@p inputs: n_inputs values), else MOVE's end. Only STOP is taken
 *        while @p faulted. Returns the stage, and sets *@p entered when it
 *        changed this tick. RUN needs a controller (@p have_controller).
 *        @p out: the commands on the wire, NULL before the first went out.
 * Context: the tick.
 */
int roz__stages_step(roz_stages_t *s, const double *inputs, const double *state,
                     const double *out, int have_controller, int faulted, int *entered);

/** @brief The commands of the current stage (not RUN, not NONE) into the
 *  stage's buffer, returned. @p state: this tick's; @p out: last tick's
 *  applied commands. Context: the tick; O(n_commands). */
const double *roz__stages_commands(roz_stages_t *s, const double *state);

/** @brief Arm the hand-over's gain hold from @p out, the commands on the
 *  wire. Context: the tick. */
void roz__stages_handover(roz_stages_t *s, const double *out, uint32_t rate_hz);

/** @brief @p target with the gain hold applied (the stage's buffer), or
 *  @p target itself when no hold is armed. Context: the tick; O(n_commands). */
const double *roz__stages_hold_gains(roz_stages_t *s, const double *target);

#endif /* ROZ_STAGES_INTERNAL_H */
