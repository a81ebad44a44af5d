/* SPDX-License-Identifier: Apache-2.0 */
/* Private to the loopback port: the simulated robot (sim.c). */
#ifndef ROZ_LOOPBACK_SIM_H
#define ROZ_LOOPBACK_SIM_H

#include "roz/port/loopback.h"

/** Bind the manifest's channels to the models; every joint at its default. */
void roz_lbsim_open(roz_loopback_t *lb);

/** Advance the models by one period under lb->cmd. */
void roz_lbsim_step(roz_loopback_t *lb);

/** The models' state, in manifest order (n_states values). */
void roz_lbsim_compose(const roz_loopback_t *lb, double *state);

#endif /* ROZ_LOOPBACK_SIM_H */
