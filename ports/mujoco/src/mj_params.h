/* SPDX-License-Identifier: Apache-2.0 */
/* Private to the mujoco port: its parameters (the rows its info shows, the
 * known keys, the ranges and defaults the parser reads) and the rules of
 * those that need no model, which its open and its registered check
 * (roz_mujoco_check()) run alike. No MuJoCo here. */
#ifndef ROZ_MJ_PARAMS_H
#define ROZ_MJ_PARAMS_H

#include <stddef.h>
#include <stdint.h>

#include "roz/hal/params.h"
#include "roz/port/mujoco.h"

/* The rows, one a key, in the order an unknown key's error lists them. */
extern const roz_port_param_info_t roz__mj_params[];
extern const size_t roz__mj_n_params;
#define MJ_PARAMS roz__mj_params, roz__mj_n_params

/* What the port says about itself (roz_mujoco_ops.info): its rows. */
extern const roz_port_info_t roz__mj_info;

/* What the open reads before the model loads (0: absent, where the row has
 * no default of its own). */
typedef struct roz__mj_values {
    double   wheel_radius, wheel_separation, max_thrust, servo_kp, servo_kd;
    double   noise_q, noise_dq, noise_tau, noise_gyro, noise_acc;
    uint32_t latency, seed;
} roz__mj_values_t;

/* The perturbations' numbers, read once the model loaded. */
typedef struct roz__mj_perturb {
    double   mass, friction, gains, damping, armature;
    double   bias_q, bias_gyro, bias_acc, bias_orientation;
    uint32_t cmd_latency;
} roz__mj_perturb_t;

/* The keys known (rule "unknown-key": nothing else is checked after one),
 * then the numbers and words that need no model. Without @p report (the
 * open): ROZ_EINVAL at the first problem, err saying it. With it: each
 * problem written to err and reported (rule "mujoco-param"), going on with
 * the next key; ROZ_EINVAL after at least one report. */
int roz__mj_params_read(const roz_params_t *p, roz__mj_values_t *v, char *err, size_t errlen,
                        roz_params_problem_fn report, void *ctx);

/* The perturbations' numbers, as roz__mj_params_read() reads. */
int roz__mj_perturb_read(const roz_params_t *p, roz__mj_perturb_t *v, char *err, size_t errlen,
                         roz_params_problem_fn report, void *ctx);

#endif /* ROZ_MJ_PARAMS_H */
