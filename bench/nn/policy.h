/* SPDX-License-Identifier: Apache-2.0 */
/* One inference of the G1 policy's shape (47 -> LSTM 64 -> 32 ELU -> 12,
 * random weights of rozgen.nn) on an input that changes every call: what
 * bench/nn times under wasm3 (policy.c), as plain wasm (policy_plain.c)
 * and natively (main.c). */
#ifndef ROZ_BENCH_NN_POLICY_H
#define ROZ_BENCH_NN_POLICY_H

#include "policy_net.h"

static float bench_in[POLICY_N_IN], bench_out[POLICY_N_OUT];

static inline float bench_infer(long long tick)
{
    if (tick == 0)
        policy_reset();
    for (int k = 0; k < POLICY_N_IN; k++)
        bench_in[k] = (float)((tick * 7 + k * 13) % 101) * 0.02f - 1.0f;
    if (policy_forward(bench_in, bench_out) != 0)
        return -1.0f;
    return bench_out[0];
}

#endif /* ROZ_BENCH_NN_POLICY_H */
