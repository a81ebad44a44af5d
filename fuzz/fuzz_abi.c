/* SPDX-License-Identifier: Apache-2.0 */
/* libFuzzer target: the input is a program of host-function calls. The
 * first byte picks the manifest (UR5 or Unitree G1); then each operation is
 * one byte of opcode and its arguments, read little-endian from the bytes
 * that follow (missing bytes read as zero):
 *   command.set (any i32 index, or a near one), count, limit_min/max,
 *   state.get, state.count, math.sin/cos, safety.request_estop,
 *   timing.now_ns/sim_time_ns, telemetry.emit_metric, a state value (any
 *   double, NaN and Inf included), the tick number, the bulk calls
 *   command.set_all and state.get_all on a 1 KiB memory (any pointer and
 *   count, the memory's bytes from the input), the NN calls nn.matvec and
 *   nn.act on the same memory (any pointers, counts, flags and kinds), and
 *   "tick": the filter runs over the targets with a stop mode from the
 *   input.
 * Checked: every command.set result against its documented meaning; a bulk
 * call refused exactly when its range leaves the memory or its count the
 * manifest, then changing nothing, else each value as command.set takes it
 * and the snapshot copied bit for bit, nothing outside the range; and
 * every filtered command inside the manifest, within max_rate of the last
 * one unless an e-stop or a counted limit stop allowed more. */
/* white-box: the harness drives the module's private fields directly */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "roz/abi.h"
#include "roz/filter.h"
#include "roz_math.h"
#include "unitree_g1_manifest.h"
#include "ur5_manifest.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct {
    const uint8_t *p, *end;
} input_t;

static uint8_t u8(input_t *in)
{
    return in->p < in->end ? *in->p++ : 0;
}

static uint64_t u64(input_t *in, int bytes)
{
    uint64_t v = 0;
    for (int i = 0; i < bytes; i++)
        v |= (uint64_t)u8(in) << (8 * i);
    return v;
}

static double f64(input_t *in)
{
    uint64_t bits = u64(in, 8);
    double d;
    memcpy(&d, &bits, sizeof d);
    return d;
}

static roz_abi_t abi;
static roz_metric_ring_t ring;
static roz_filter_t filt;
static double target[ROZ_CFG_MAX_COMMANDS];
static double state[ROZ_CFG_MAX_STATES];
static double out[ROZ_CFG_MAX_COMMANDS];
static double last[ROZ_CFG_MAX_COMMANDS];
static uint32_t stops[ROZ_CFG_MAX_COMMANDS];

static void check_set(const roz_manifest_t *m, int32_t index, double v, int32_t rc)
{
    if (index < 0 || index >= (int32_t)m->n_commands) {
        if (rc != ROZ_ABI_SET_REFUSED)
            abort();
        return;
    }
    const roz_channel_t *c = &m->commands[index];
    if (!isfinite(v)) {
        if (rc != ROZ_ABI_SET_REFUSED || isfinite(target[index]))
            abort();
    } else if (v < c->min || v > c->max) {
        if (rc != ROZ_ABI_SET_CLAMPED || target[index] != (v < c->min ? c->min : c->max))
            abort();
    } else if (rc != ROZ_ABI_SET_TAKEN || target[index] != v) {
        abort();
    }
}

/* ---- the bulk calls on a small memory --------------------------------------- */

#define BULK_MEM 1024
static uint8_t mem[BULK_MEM], mem_before[BULK_MEM];

static int32_t bulk_count(input_t *in)
{
    /* mostly near the channel counts, sometimes any i32 */
    uint8_t k = u8(in);
    return k & 0x80 ? (int32_t)(uint32_t)u64(in, 4) : (int32_t)(k & 0x7f) - 8;
}

static uint32_t bulk_ptr(input_t *in)
{
    uint8_t k = u8(in);
    return k & 0x80 ? (uint32_t)u64(in, 4) : (uint32_t)u64(in, 2) % (BULK_MEM + 64u);
}

static int bulk_fits(uint32_t ptr, int32_t count, int32_t n)
{
    return count >= 0 && count <= n && (uint64_t)ptr + 8u * (uint64_t)count <= BULK_MEM;
}

static void check_set_all(const roz_manifest_t *m, uint32_t ptr, int32_t count)
{
    static double before[ROZ_CFG_MAX_COMMANDS];
    roz_abi_counters_t c0 = abi.counters;
    memcpy(before, target, sizeof before);
    int32_t rc = roz_abi_command_set_all(&abi, mem, BULK_MEM, ptr, count);
    if (!bulk_fits(ptr, count, (int32_t)m->n_commands)) {
        if (rc != -1 || memcmp(before, target, sizeof before) != 0 ||
            abi.counters.sets != c0.sets + 1 || abi.counters.set_bad_index != c0.set_bad_index + 1)
            abort();
        return;
    }
    int32_t not_taken = 0;
    for (int32_t i = 0; i < count; i++) {
        double v;
        memcpy(&v, mem + ptr + 8u * (uint32_t)i, sizeof v); /* little-endian hosts */
        const roz_channel_t *c = &m->commands[i];
        if (!isfinite(v)) {
            not_taken++;
            if (isfinite(target[i]))
                abort();
        } else if (v < c->min || v > c->max) {
            not_taken++;
            if (target[i] != (v < c->min ? c->min : c->max))
                abort();
        } else if (memcmp(&target[i], &v, sizeof v) != 0) {
            abort();
        }
    }
    if (rc != not_taken || abi.counters.sets != c0.sets + (uint64_t)count ||
        memcmp(&target[count], &before[count], (ROZ_CFG_MAX_COMMANDS - (size_t)count) * 8u) != 0)
        abort();
}

static void check_get_all(const roz_manifest_t *m, uint32_t ptr, int32_t count)
{
    memcpy(mem_before, mem, BULK_MEM);
    int32_t rc = roz_abi_state_get_all(&abi, mem, BULK_MEM, ptr, count);
    if (!bulk_fits(ptr, count, (int32_t)m->n_states)) {
        if (rc != -1 || memcmp(mem, mem_before, BULK_MEM) != 0)
            abort();
        return;
    }
    if (rc != count || memcmp(mem + ptr, state, 8u * (size_t)count) != 0 ||
        memcmp(mem, mem_before, ptr) != 0 ||
        memcmp(mem + ptr + 8u * (size_t)count, mem_before + ptr + 8u * (size_t)count,
               BULK_MEM - ptr - 8u * (size_t)count) != 0)
        abort();
}

/* ---- the NN calls on the same memory ------------------------------------------ */

static int nn_fits(uint32_t at, uint64_t bytes)
{
    return bytes <= BULK_MEM && at <= BULK_MEM - bytes;
}

static int nn_overlap(uint32_t a, uint64_t an, uint32_t b, uint64_t bn)
{
    return an && bn && (uint64_t)a < b + bn && (uint64_t)b < a + an;
}

/* a float of the memory before the call as the nn imports read it: zero
 * of its sign below 2^-51 (roz_math_nn_inputf(), the rule roz/abi.h states) */
static float ldf(uint32_t at)
{
    float f;
    memcpy(&f, mem_before + at, 4);
    return roz_math_nn_inputf(f);
}

static void check_matvec(uint32_t w, uint32_t x, uint32_t b, uint32_t y, int32_t rows,
                         int32_t cols, int32_t flags)
{
    memcpy(mem_before, mem, BULK_MEM);
    int32_t rc = roz_abi_nn_matvec(&abi, mem, BULK_MEM, w, x, b, y, rows, cols, flags);
    int ok = rows >= 0 && cols >= 0 && (flags & ~3) == 0;
    uint64_t wn = ok ? 4u * (uint64_t)rows * (uint64_t)cols : 0, xn = ok ? 4u * (uint64_t)cols : 0;
    uint64_t yn = ok ? 4u * (uint64_t)rows : 0, bn = (flags & 1) ? yn : 0;
    ok = ok && nn_fits(w, wn) && nn_fits(x, xn) && (bn == 0 || nn_fits(b, bn)) &&
         nn_fits(y, yn) && !nn_overlap(y, yn, w, wn) && !nn_overlap(y, yn, x, xn) &&
         !nn_overlap(y, yn, b, bn);
    if (!ok) {
        if (rc != -1 || memcmp(mem, mem_before, BULK_MEM) != 0)
            abort();
        return;
    }
    if (rc != 0 || memcmp(mem, mem_before, y) != 0 ||
        memcmp(mem + y + yn, mem_before + y + yn, BULK_MEM - y - yn) != 0)
        abort();
    for (int32_t i = 0; i < rows; i++) {
        float s = 0.0f, got;
        for (int32_t j = 0; j < cols; j++)
            s = s + ldf(w + 4u * (uint32_t)(i * cols + j)) * ldf(x + 4u * (uint32_t)j);
        if (flags & 1)
            s = s + ldf(b + 4u * (uint32_t)i);
        if (flags & 2)
            s = ldf(y + 4u * (uint32_t)i) + s;
        memcpy(&got, mem + y + 4u * (uint32_t)i, 4);
        if (isnan(s) ? !isnan(got) : memcmp(&got, &s, 4) != 0)
            abort();
    }
}

static void check_act(int32_t kind, uint32_t ptr, int32_t count)
{
    memcpy(mem_before, mem, BULK_MEM);
    int32_t rc = roz_abi_nn_act(&abi, mem, BULK_MEM, kind, ptr, count);
    if (kind < 0 || kind >= ROZ_ABI_NN_ACT_COUNT || count < 0 ||
        !nn_fits(ptr, 4u * (uint64_t)count)) {
        if (rc != -1 || memcmp(mem, mem_before, BULK_MEM) != 0)
            abort();
        return;
    }
    if (rc != count || memcmp(mem, mem_before, ptr) != 0 ||
        memcmp(mem + ptr + 4u * (uint32_t)count, mem_before + ptr + 4u * (uint32_t)count,
               BULK_MEM - ptr - 4u * (uint32_t)count) != 0)
        abort();
}

static int32_t nn_dim(input_t *in)
{
    /* mostly small, sometimes any i32 */
    uint8_t k = u8(in);
    return k & 0x80 ? (int32_t)(uint32_t)u64(in, 4) : (int32_t)(k & 0x3f) - 2;
}

static void tick(const roz_manifest_t *m, roz_stop_t stop)
{
    roz_filter_apply(&filt, target, state, stop, out);
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        int limited = filt.channel_limit_stops[i] != stops[i];
        stops[i] = filt.channel_limit_stops[i];
        if (!(out[i] >= c->min && out[i] <= c->max))
            abort();
        if (stop != ROZ_STOP_IMMEDIATE && !limited && c->max_rate > 0.0 &&
            fabs(out[i] - last[i]) > c->max_rate * (1.0 + 1e-12))
            abort();
        last[i] = out[i];
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    input_t in = { data, data + size };
    const roz_manifest_t *m = u8(&in) & 1 ? &roz_manifest_unitree_g1 : &roz_manifest_ur5;
    roz_metric_t metric;
    volatile double sink = 0.0;
    volatile int64_t isink = 0;

    /* validating a manifest is quadratic in its channels: once per manifest */
    static roz_filter_t fresh[2];
    static int ready[2];
    int which = m == &roz_manifest_unitree_g1;
    if (!ready[which]) {
        if (roz_filter_init(&fresh[which], m) != ROZ_OK)
            abort();
        ready[which] = 1;
    }
    filt = fresh[which];

    roz_abi_init(&abi, m, target, &ring);
    memset(mem, 0, sizeof mem); /* each input starts from the same memory */
    for (uint16_t s = 0; s < m->n_states; s++)
        state[s] = m->states[s].default_value;
    abi.state = state;
    roz_filter_prime(&filt, state);
    memcpy(last, filt.last, m->n_commands * sizeof last[0]);
    memset(stops, 0, sizeof stops);

    while (in.p < in.end) {
        uint8_t op = u8(&in);
        switch (op % 21) {
        case 0: {
            int32_t i = (int32_t)(uint32_t)u64(&in, 4);
            double v = f64(&in);
            check_set(m, i, v, roz_abi_command_set(&abi, i, v));
            break;
        }
        case 1: {
            int32_t i = (int32_t)u8(&in) - 8; /* mostly valid, some just outside */
            double v = f64(&in);
            check_set(m, i, v, roz_abi_command_set(&abi, i, v));
            break;
        }
        case 2:
            if (roz_abi_command_count(&abi) != m->n_commands)
                abort();
            break;
        case 3: sink = roz_abi_command_limit_min(&abi, (int32_t)(uint32_t)u64(&in, 4)); break;
        case 4: sink = roz_abi_command_limit_max(&abi, (int32_t)(uint32_t)u64(&in, 4)); break;
        case 5: {
            int32_t i = (int32_t)(uint32_t)u64(&in, 4);
            double v = roz_abi_state_get(&abi, i);
            int ok = i >= 0 && i < (int32_t)m->n_states;
            if (ok ? memcmp(&v, &state[i], sizeof v) != 0 : !isnan(v))
                abort();
            break;
        }
        case 6:
            if (roz_abi_state_count(&abi) != m->n_states)
                abort();
            break;
        case 7: sink = roz_abi_math_sin(f64(&in)); break;
        case 8: sink = roz_abi_math_cos(f64(&in)); break;
        case 9: roz_abi_safety_request_estop(&abi); break;
        case 10: isink = roz_abi_timing_now_ns(&abi); break;
        case 11: isink = roz_abi_timing_sim_time_ns(&abi); break;
        case 12: roz_abi_telemetry_emit_metric(&abi, f64(&in)); break;
        case 13: {
            uint8_t s = u8(&in);
            double v = f64(&in);
            if (m->n_states > 0)
                state[s % m->n_states] = v;
            break;
        }
        case 14:
            /* any tick within 292 years of control time, where
             * tick * period_ns still fits in an int64 */
            abi.tick = (int64_t)(u64(&in, 8) % ((uint64_t)INT64_MAX / abi.period_ns + 1));
            break;
        case 15: {
            uint32_t ptr = bulk_ptr(&in);
            check_set_all(m, ptr, bulk_count(&in));
            break;
        }
        case 16: {
            uint32_t ptr = bulk_ptr(&in);
            check_get_all(m, ptr, bulk_count(&in));
            break;
        }
        case 17: { /* bytes of the memory, from the input */
            uint16_t at = (uint16_t)(u64(&in, 2) % BULK_MEM);
            uint64_t bits = u64(&in, 8);
            memcpy(mem + at, &bits, at + 8u <= BULK_MEM ? 8u : BULK_MEM - at);
            break;
        }
        case 19: {
            uint32_t w = bulk_ptr(&in), x = bulk_ptr(&in), b = bulk_ptr(&in), y = bulk_ptr(&in);
            int32_t rows = nn_dim(&in), cols = nn_dim(&in);
            check_matvec(w, x, b, y, rows, cols, (int32_t)(u8(&in) % 5));
            break;
        }
        case 20: {
            int32_t kind = (int32_t)(u8(&in) % 7) - 1;
            uint32_t ptr = bulk_ptr(&in);
            check_act(kind, ptr, nn_dim(&in));
            break;
        }
        default:
            tick(m, (roz_stop_t)(u8(&in) % 3));
            break;
        }
    }
    tick(m, ROZ_STOP_NONE);
    while (roz_metric_ring_pop(&ring, &metric))
        ;
    (void)sink;
    (void)isink;
    return 0;
}
