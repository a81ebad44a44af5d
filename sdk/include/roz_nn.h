/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz_nn.h
 * @brief Neural-network layers for controllers: Dense, LSTM and GRU over
 *        float32, on roz's optional "nn" imports (the host does the
 *        multiply-adds and activations on the controller's own memory).
 *
 * Weights are const arrays the controller compiles in, PyTorch's layout:
 * a Dense's W is out x in, row-major; an LSTM's W_ih is 4H x in and W_hh
 * 4H x H, gates in PyTorch's order i, f, g, o; a GRU's are 3H x in and
 * 3H x H, gates r, z, n. A layer's state (h, and an LSTM's c) and scratch
 * live in the controller's memory, in arrays the caller gives (see
 * ROZ_NN_LSTM_DEFINE); reset it at tick 0, which is every fresh instance's
 * first tick, after a swap too. docs/policies.md shows a whole policy.
 *
 * Results are the same bits on every target: the host computes each output
 * in a fixed order (roz/abi.h, roz_abi_nn_matvec), and the element-wise
 * steps here are float arithmetic that wasm32 never fuses. Built natively
 * (not for wasm32), the two imports are the plain loops below, which give
 * those same bits when compiled with -ffp-contract=off: a C reference for
 * tests and benchmarks. ROZ_NN_NO_IMPORTS compiles those loops into a
 * wasm32 module too (for comparison: about 33 times the fuel).
 *
 * Fuel: one unit per multiply-add and 2 per output row (nn.matvec), 24 per
 * tanh/sigmoid/ELU/exp element and 2 per ReLU (nn.act), plus the wasm the
 * layer runs itself: the G1 policy (47 -> LSTM 64 -> 32 ELU -> 12) costs
 * about 47,000 units an inference (bench/nn; 1,540,000 as plain wasm).
 */
#ifndef ROZ_NN_H
#define ROZ_NN_H

#include "roz_controller.h"
#include "roz_math.h"

#ifdef __cplusplus
extern "C" {
#endif

/** roz_nn_matvec() flags. */
#define ROZ_NN_BIAS       1 /**< add b */
#define ROZ_NN_ACCUMULATE 2 /**< y += W x (+ b) instead of y = W x (+ b) */

/** Activations (roz_nn_act(); roz_math.h's float functions). */
#define ROZ_NN_LINEAR  (-1) /**< none: a layer's output as it is */
#define ROZ_NN_RELU    0
#define ROZ_NN_TANH    1
#define ROZ_NN_SIGMOID 2
#define ROZ_NN_ELU     3    /**< alpha 1, PyTorch's default */
#define ROZ_NN_EXP     4

#if defined(__wasm__) && !defined(ROZ_NN_NO_IMPORTS)
/** y = W x (+ b) (or y += ...), W rows x cols row-major; y must not overlap
 *  W, x or b. Returns 0, or -1 (nothing written) for arrays outside the
 *  memory, overlapping, or bad counts or flags. */
ROZ_IMPORT("nn", "matvec")
int roz_nn_matvec(const float *w, const float *x, const float *b, float *y, int rows, int cols,
                  int flags);
/** v[i] = f(v[i]) for i < count, f the kind's; returns count, or -1
 *  (nothing written). */
ROZ_IMPORT("nn", "act") int roz_nn_act(int kind, float *v, int count);
#else
/* The host's imports as plain C: each output in the order roz/abi.h
 * defines, each value read as roz_math_nn_inputf() reads it. */
static inline int roz_nn_matvec(const float *w, const float *x, const float *b, float *y,
                                int rows, int cols, int flags)
{
    if (rows < 0 || cols < 0 || (flags & ~(ROZ_NN_BIAS | ROZ_NN_ACCUMULATE)) != 0)
        return -1;
    for (int i = 0; i < rows; i++) {
        float s = 0.0f;
        for (int j = 0; j < cols; j++)
            s = s + roz_math_nn_inputf(w[(long)i * cols + j]) * roz_math_nn_inputf(x[j]);
        if (flags & ROZ_NN_BIAS)
            s = s + roz_math_nn_inputf(b[i]);
        y[i] = (flags & ROZ_NN_ACCUMULATE) ? roz_math_nn_inputf(y[i]) + s : s;
    }
    return 0;
}

static inline int roz_nn_act(int kind, float *v, int count)
{
    if (kind < ROZ_NN_RELU || kind > ROZ_NN_EXP || count < 0)
        return -1;
    for (int i = 0; i < count; i++)
        v[i] = roz_math_nn_actf(kind, v[i]);
    return count;
}
#endif

/* ---- Dense ------------------------------------------------------------------ */

/** A fully connected layer: y = act(W x + b); b may be NULL. */
typedef struct roz_nn_dense {
    int in, out;
    const float *w; /**< out x in, row-major */
    const float *b; /**< out, or NULL */
    int act;        /**< ROZ_NN_LINEAR or an activation */
} roz_nn_dense_t;

/** @brief y = act(W x + b); y (out values) must not overlap x or the
 *  weights. Returns 0, or -1 when the host refused a call. */
static inline int roz_nn_dense(const roz_nn_dense_t *l, const float *x, float *y)
{
    if (roz_nn_matvec(l->w, x, l->b, y, l->out, l->in, l->b != 0 ? ROZ_NN_BIAS : 0) != 0)
        return -1;
    if (l->act != ROZ_NN_LINEAR && roz_nn_act(l->act, y, l->out) != l->out)
        return -1;
    return 0;
}

/* ---- LSTM (one layer, PyTorch's nn.LSTM) ------------------------------------ */

/** An LSTM layer with its state: h (the output) and c, and 4H of scratch. */
typedef struct roz_nn_lstm {
    int in, hidden;
    const float *w_ih, *w_hh; /**< 4H x in, 4H x H; gates i, f, g, o */
    const float *b_ih, *b_hh; /**< 4H each (either may be NULL) */
    float *h, *c;             /**< H each: the state */
    float *gates;             /**< 4H: scratch */
} roz_nn_lstm_t;

/** File-scope storage for an LSTM of IN inputs and H hidden units, and the
 *  layer over it, named NAME. */
#define ROZ_NN_LSTM_DEFINE(name, IN, H, w_ih, w_hh, b_ih, b_hh)                          \
    static float name##_h[H], name##_c[H], name##_gates[4 * (H)];                      \
    static roz_nn_lstm_t name = { (IN), (H), (w_ih), (w_hh), (b_ih), (b_hh),           \
                                  name##_h, name##_c, name##_gates }

/** @brief h = c = 0. */
static inline void roz_nn_lstm_reset(roz_nn_lstm_t *l)
{
    for (int k = 0; k < l->hidden; k++)
        l->h[k] = l->c[k] = 0.0f;
}

/** @brief One step: gates = W_ih x + b_ih + W_hh h + b_hh; c = f c + i g;
 *  h = o tanh(c). The output is l->h. Returns 0, or -1 when the host
 *  refused a call (the state is then not to be trusted: reset it). */
static inline int roz_nn_lstm_step(roz_nn_lstm_t *l, const float *x)
{
    const int H = l->hidden;
    float *g = l->gates;
    if (roz_nn_matvec(l->w_ih, x, l->b_ih, g, 4 * H, l->in, l->b_ih != 0 ? ROZ_NN_BIAS : 0) ||
        roz_nn_matvec(l->w_hh, l->h, l->b_hh, g, 4 * H, H,
                      ROZ_NN_ACCUMULATE | (l->b_hh != 0 ? ROZ_NN_BIAS : 0)) ||
        roz_nn_act(ROZ_NN_SIGMOID, g, 2 * H) != 2 * H ||
        roz_nn_act(ROZ_NN_TANH, g + 2 * H, H) != H ||
        roz_nn_act(ROZ_NN_SIGMOID, g + 3 * H, H) != H)
        return -1;
    for (int k = 0; k < H; k++) {
        float c = g[H + k] * l->c[k] + g[k] * g[2 * H + k];
        l->c[k] = c;
        g[2 * H + k] = c; /* g is spent: its slot takes tanh(c) */
    }
    if (roz_nn_act(ROZ_NN_TANH, g + 2 * H, H) != H)
        return -1;
    for (int k = 0; k < H; k++)
        l->h[k] = g[3 * H + k] * g[2 * H + k];
    return 0;
}

/* ---- GRU (one layer, PyTorch's nn.GRU) -------------------------------------- */

/** A GRU layer with its state h, and 6H of scratch. */
typedef struct roz_nn_gru {
    int in, hidden;
    const float *w_ih, *w_hh; /**< 3H x in, 3H x H; gates r, z, n */
    const float *b_ih, *b_hh; /**< 3H each (either may be NULL) */
    float *h;                 /**< H: the state */
    float *scratch;           /**< 6H */
} roz_nn_gru_t;

/** File-scope storage for a GRU of IN inputs and H hidden units. */
#define ROZ_NN_GRU_DEFINE(name, IN, H, w_ih, w_hh, b_ih, b_hh)                           \
    static float name##_h[H], name##_scratch[6 * (H)];                                 \
    static roz_nn_gru_t name = { (IN), (H), (w_ih), (w_hh), (b_ih), (b_hh),            \
                                 name##_h, name##_scratch }

/** @brief h = 0. */
static inline void roz_nn_gru_reset(roz_nn_gru_t *l)
{
    for (int k = 0; k < l->hidden; k++)
        l->h[k] = 0.0f;
}

/** @brief One step, as PyTorch: r = s(Wi_r x + bi_r + Wh_r h + bh_r), z
 *  likewise, n = tanh(Wi_n x + bi_n + r (Wh_n h + bh_n)), h = (1 - z) n +
 *  z h. The output is l->h. Returns 0, or -1 when the host refused a call. */
static inline int roz_nn_gru_step(roz_nn_gru_t *l, const float *x)
{
    const int H = l->hidden;
    float *gi = l->scratch, *gh = l->scratch + 3 * H;
    if (roz_nn_matvec(l->w_ih, x, l->b_ih, gi, 3 * H, l->in, l->b_ih != 0 ? ROZ_NN_BIAS : 0) ||
        roz_nn_matvec(l->w_hh, l->h, l->b_hh, gh, 3 * H, H, l->b_hh != 0 ? ROZ_NN_BIAS : 0))
        return -1;
    for (int k = 0; k < 2 * H; k++)
        gi[k] = gi[k] + gh[k];
    if (roz_nn_act(ROZ_NN_SIGMOID, gi, 2 * H) != 2 * H)
        return -1;
    for (int k = 0; k < H; k++)
        gi[2 * H + k] = gi[2 * H + k] + gi[k] * gh[2 * H + k];
    if (roz_nn_act(ROZ_NN_TANH, gi + 2 * H, H) != H)
        return -1;
    for (int k = 0; k < H; k++) {
        float z = gi[H + k];
        l->h[k] = (1.0f - z) * gi[2 * H + k] + z * l->h[k];
    }
    return 0;
}

#ifdef __cplusplus
}
#endif

#endif /* ROZ_NN_H */
