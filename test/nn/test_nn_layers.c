/* SPDX-License-Identifier: Apache-2.0 */
/* roz_nn.h's layers on three random networks of rozgen.nn (an LSTM policy
 * of the G1's shape 47 -> LSTM 64 -> 32 ELU -> 12, a GRU, an MLP through
 * every activation): the probe controller (nn_probe.c) under wasm3 gives
 * the bits of the same headers built natively, whose nn imports are the
 * plain loops of roz/abi.h (a C reference in the same summation order), and
 * both stay within a tolerance of rozgen.nn's numpy reference (float64),
 * step by step through the recurrent state. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz/abi.h"
#include "roz/controller.h"
#include "support.h"
#include "ur5_manifest.h"

/* the networks natively: roz_nn.h's plain-C imports */
#include "lstm_net.h"
#include "lstm_net_vectors.h"
#include "gru_net.h"
#include "gru_net_vectors.h"
#include "mlp_net.h"
#include "mlp_net_vectors.h"

#define N_OUT (LSTM_N_OUT + GRU_N_OUT + MLP_N_OUT)

static roz_controller_t ctl;
static roz_abi_t abi;
static roz_metric_ring_t ring;
static double target[ROZ_CFG_MAX_COMMANDS];
static double state[ROZ_CFG_MAX_STATES];
static uint8_t wasm[1 << 20];

/* |got - want| within 2^-14 of max(1, |want|): float32 arithmetic against
 * float64, through 16 steps of recurrence */
static void near(double got, double want, const char *what, int step, int i)
{
    double tol = ldexp(fmax(1.0, fabs(want)), -14);
    if (!(fabs(got - want) <= tol))
        fail_msg("%s step %d output %d: %.9g, numpy %.9g (tolerance %.3g)", what, step, i, got,
                 want, tol);
}

static void test_nn_layers_wasm_native_numpy(void **st)
{
    float out[N_OUT];
    double worst = 0.0;
    (void)st;
    FILE *f = fopen(ROZ_NN_PROBE, "rb");
    if (f == NULL)
        fail_msg("cannot open %s", ROZ_NN_PROBE);
    size_t len = fread(wasm, 1, sizeof wasm, f);
    fclose(f);
    roz_budget_t b = { 1000000, ROZ_BUDGET_OFF, NULL, NULL };
    roz_controller_init(&ctl);
    roz_abi_init(&abi, &roz_manifest_ur5, target, &ring);
    if (roz_controller_load(&ctl, wasm, len, &abi) != ROZ_OK)
        fail_msg("load: %s", roz_controller_error(&ctl));
    assert_int_equal(roz_controller_set_budget(&ctl, &b), ROZ_OK);
    lstm_reset();
    gru_reset();
    mlp_reset();
    for (int t = 0; t < LSTM_TEST_STEPS; t++) {
        roz_abi_begin_tick(&abi, t, state);
        assert_int_equal(roz_controller_process(&ctl, t), ROZ_OK);
        if (t == 0)
            print_message("nn probe: %llu fuel units for the three networks\n",
                          (unsigned long long)roz_controller_fuel_used(&ctl));
        assert_int_equal(lstm_forward(lstm_test_in[t], out), 0);
        assert_int_equal(gru_forward(gru_test_in[t], out + LSTM_N_OUT), 0);
        assert_int_equal(mlp_forward(mlp_test_in[t], out + LSTM_N_OUT + GRU_N_OUT), 0);
        for (int i = 0; i < N_OUT; i++) {
            roz_metric_t m;
            assert_int_equal(roz_metric_ring_pop(&ring, &m), 1);
            float w = (float)m.value;
            if (memcmp(&w, &out[i], 4) != 0 || (double)w != m.value)
                fail_msg("step %d output %d: wasm %a, native %a", t, i, m.value,
                         (double)out[i]);
            const char *what = i < LSTM_N_OUT ? "lstm" : i < LSTM_N_OUT + GRU_N_OUT ? "gru" : "mlp";
            double want = i < LSTM_N_OUT ? lstm_test_out[t][i]
                          : i < LSTM_N_OUT + GRU_N_OUT
                              ? gru_test_out[t][i - LSTM_N_OUT]
                              : mlp_test_out[t][i - LSTM_N_OUT - GRU_N_OUT];
            near(out[i], want, what, t, i);
            double e = fabs(out[i] - want) / fmax(1.0, fabs(want));
            if (e > worst)
                worst = e;
        }
    }
    print_message("largest error against numpy: %.3g (relative to max(1, |y|))\n", worst);
    roz_abi_counters_t c;
    roz_abi_counters_get(&abi, &c);
    assert_int_equal(c.nn_refused, 0);
    roz_controller_unload(&ctl);
}

/* A second instance starts from a zero state: tick 0 resets, so the first
 * step's outputs come again. */
static void test_nn_layers_reset_at_tick0(void **st)
{
    double first[N_OUT];
    (void)st;
    FILE *f = fopen(ROZ_NN_PROBE, "rb");
    size_t len = fread(wasm, 1, sizeof wasm, f);
    fclose(f);
    roz_budget_t b = { 1000000, ROZ_BUDGET_OFF, NULL, NULL };
    for (int round = 0; round < 2; round++) {
        roz_controller_init(&ctl);
        roz_abi_init(&abi, &roz_manifest_ur5, target, &ring);
        assert_int_equal(roz_controller_load(&ctl, wasm, len, &abi), ROZ_OK);
        assert_int_equal(roz_controller_set_budget(&ctl, &b), ROZ_OK);
        for (int t = 0; t < 3; t++) {
            roz_abi_begin_tick(&abi, round == 0 ? t : 0, state);
            assert_int_equal(roz_controller_process(&ctl, round == 0 ? t : 0), ROZ_OK);
            for (int i = 0; i < N_OUT; i++) {
                roz_metric_t m;
                assert_int_equal(roz_metric_ring_pop(&ring, &m), 1);
                if (round == 0 && t == 0)
                    first[i] = m.value;
                if (round == 1) /* tick 0 again and again: the state reset each time */
                    assert_memory_equal(&m.value, &first[i], sizeof m.value);
            }
        }
        roz_controller_unload(&ctl);
    }
}

ROZ_TEST_MAIN(cmocka_unit_test(test_nn_layers_wasm_native_numpy),
              cmocka_unit_test(test_nn_layers_reset_at_tick0))
