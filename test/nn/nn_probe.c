/* SPDX-License-Identifier: Apache-2.0 */
/* The NN probe: three random networks of rozgen.nn (an LSTM policy of the
 * G1's shape, a GRU, an MLP with every activation), run through roz_nn.h;
 * tick t feeds each its test input t and emits every output as a metric,
 * for test_nn_layers.c to compare with the same headers built natively
 * (bit for bit) and with the numpy reference (within a tolerance). A step
 * the host refused emits NaN. Tick 0 resets the recurrent state. */
#include "roz_controller.h"
#include "roz_nn.h"

#include "lstm_net.h"
#include "lstm_net_vectors.h"
#include "gru_net.h"
#include "gru_net_vectors.h"
#include "mlp_net.h"
#include "mlp_net_vectors.h"

ROZ_FUEL_PER_TICK(90000);

static float out[LSTM_N_OUT + GRU_N_OUT + MLP_N_OUT];

static void emit(int rc, const float *v, int n)
{
    for (int i = 0; i < n; i++)
        roz_emit_metric(rc == 0 ? (double)v[i] : __builtin_nan(""));
}

ROZ_PROCESS(tick)
{
    if (tick == 0) {
        lstm_reset();
        gru_reset();
        mlp_reset();
    }
    if (tick >= LSTM_TEST_STEPS)
        return;
    emit(lstm_forward(lstm_test_in[tick], out), out, LSTM_N_OUT);
    emit(gru_forward(gru_test_in[tick], out), out, GRU_N_OUT);
    emit(mlp_forward(mlp_test_in[tick], out), out, MLP_N_OUT);
}
