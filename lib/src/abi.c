/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/abi.h"

#include <math.h>
#include <string.h>

/* The controller SDK's freestanding math: the same bits on every target */
#include "roz_math.h"

/* ---- the import table ---------------------------------------------------- */

/* NULL, or the name of the option (roz/config.h) that left an import out */
#define LEFT_OUT(option) ((option) ? NULL : #option)

const roz_abi_import_t roz_abi_imports[] = {
    { "command", "set", "i(iF)", NULL },
    { "command", "count", "i()", NULL },
    { "command", "limit_min", "F(i)", NULL },
    { "command", "limit_max", "F(i)", NULL },
    { "state", "get", "F(i)", NULL },
    { "state", "count", "i()", NULL },
    { "math", "sin", "F(F)", LEFT_OUT(ROZ_CFG_MATH_IMPORTS) },
    { "math", "cos", "F(F)", LEFT_OUT(ROZ_CFG_MATH_IMPORTS) },
    { "safety", "request_estop", "v()", NULL },
    { "timing", "now_ns", "I()", NULL },
    { "timing", "sim_time_ns", "I()", NULL },
    { "telemetry", "emit_metric", "v(F)", NULL },
    /* the bulk extension (optional for a controller; see roz/abi.h) */
    { "state", "get_all", "i(ii)", LEFT_OUT(ROZ_CFG_BULK_IMPORTS) },
    { "command", "set_all", "i(ii)", LEFT_OUT(ROZ_CFG_BULK_IMPORTS) },
    /* the neural-network extension (optional; see roz/abi.h) */
    { "nn", "matvec", "i(iiiiiii)", LEFT_OUT(ROZ_CFG_NN_IMPORTS) },
    { "nn", "act", "i(iii)", LEFT_OUT(ROZ_CFG_NN_IMPORTS) },
};
const size_t roz_abi_import_count = sizeof roz_abi_imports / sizeof roz_abi_imports[0];

const roz_abi_import_t *roz_abi_find_import(const char *module, const char *name)
{
    if (module == NULL || name == NULL)
        return NULL;
    for (size_t i = 0; i < roz_abi_import_count; i++) {
        if (strcmp(roz_abi_imports[i].module, module) == 0 &&
            strcmp(roz_abi_imports[i].name, name) == 0)
            return &roz_abi_imports[i];
    }
    return NULL;
}

/* ---- context ------------------------------------------------------------- */

void roz_abi_init(roz_abi_t *abi, const roz_manifest_t *m, double *target,
                  roz_metric_ring_t *metrics)
{
    memset(abi, 0, sizeof *abi);
    abi->manifest = m;
    abi->target = target;
    abi->metrics = metrics;
    abi->period_ns = 1000000000ull / m->control_rate_hz;
    roz_abi_reset(abi);
}

void roz_abi_reset(roz_abi_t *abi)
{
    for (uint16_t i = 0; i < abi->manifest->n_commands; i++)
        abi->target[i] = abi->manifest->commands[i].default_value;
    abi->estop_requested = 0;
}

void roz_abi_begin_tick(roz_abi_t *abi, int64_t tick, const double *state)
{
    abi->tick = tick;
    abi->state = state;
}

void roz_abi_set_clock(roz_abi_t *abi, roz_clock_fn clock, void *clock_ctx, uint64_t period_ns)
{
    abi->clock = clock;
    abi->clock_ctx = clock_ctx;
    if (period_ns != 0)
        abi->period_ns = period_ns;
}

int roz_abi_estop_requested(const roz_abi_t *abi)
{
    return abi->estop_requested;
}

void roz_abi_counters_get(const roz_abi_t *abi, roz_abi_counters_t *out)
{
    *out = abi->counters;
}

/* ---- imports ------------------------------------------------------------- */

int32_t roz_abi_command_set(roz_abi_t *abi, int32_t index, double value)
{
    const roz_channel_t *c;

    abi->counters.sets++;
    if (index < 0 || index >= (int32_t)abi->manifest->n_commands) {
        abi->counters.set_bad_index++;
        return ROZ_ABI_SET_REFUSED;
    }
    c = &abi->manifest->commands[index];
    if (value >= c->min && value <= c->max) { /* the usual value: false for NaN */
        abi->target[index] = value;
        return ROZ_ABI_SET_TAKEN;
    }
    if (!isfinite(value)) {
        /* The safety filter turns a non-finite target into the channel's
         * safe default (holding the paired position for a position
         * command), so hand it one. */
        abi->counters.set_nonfinite++;
        abi->target[index] = NAN;
        return ROZ_ABI_SET_REFUSED;
    }
    abi->counters.set_clamped++;
    abi->target[index] = value < c->min ? c->min : c->max;
    return ROZ_ABI_SET_CLAMPED;
}

int32_t roz_abi_command_count(const roz_abi_t *abi)
{
    return (int32_t)abi->manifest->n_commands;
}

double roz_abi_command_limit_min(roz_abi_t *abi, int32_t index)
{
    if (index < 0 || index >= (int32_t)abi->manifest->n_commands) {
        abi->counters.get_bad_index++;
        return NAN;
    }
    return abi->manifest->commands[index].min;
}

double roz_abi_command_limit_max(roz_abi_t *abi, int32_t index)
{
    if (index < 0 || index >= (int32_t)abi->manifest->n_commands) {
        abi->counters.get_bad_index++;
        return NAN;
    }
    return abi->manifest->commands[index].max;
}

double roz_abi_state_get(roz_abi_t *abi, int32_t index)
{
    if (index < 0 || index >= roz_abi_state_count(abi) || abi->state == NULL) {
        abi->counters.get_bad_index++;
        return NAN;
    }
    return abi->state[index];
}

int32_t roz_abi_state_count(const roz_abi_t *abi)
{
    /* the port's states, then the operator's inputs */
    return (int32_t)abi->manifest->n_states + (int32_t)abi->manifest->n_inputs;
}

/* Not the C library's sin and cos: glibc and newlib differ in the last
 * bit now and then, and a controller's outputs would then depend on the
 * machine it runs on. The SDK's (roz_math.h: < 1 ulp, exact argument
 * reduction, double arithmetic only) give the same bits on every target,
 * so a controller run on a Cortex-M and on the host agrees bit for bit
 * (test/firmware/), and a recording replays on any machine. */
double roz_abi_math_sin(double x)
{
    return roz_math_sin(x);
}

double roz_abi_math_cos(double x)
{
    return roz_math_cos(x);
}

void roz_abi_safety_request_estop(roz_abi_t *abi)
{
    abi->counters.estop_requests++;
    abi->estop_requested = 1;
}

int64_t roz_abi_timing_now_ns(const roz_abi_t *abi)
{
    return abi->clock != NULL ? (int64_t)abi->clock(abi->clock_ctx) : 0;
}

int64_t roz_abi_timing_sim_time_ns(const roz_abi_t *abi)
{
    return abi->tick * (int64_t)abi->period_ns;
}

void roz_abi_telemetry_emit_metric(roz_abi_t *abi, double value)
{
    roz_metric_ring_t *r = abi->metrics;
    uint_fast32_t head, tail;

    abi->counters.metrics++;
    if (r == NULL)
        return;
    head = atomic_load_explicit(&r->head, memory_order_relaxed);
    tail = atomic_load_explicit(&r->tail, memory_order_acquire);
    if (head - tail >= ROZ_CFG_TELEMETRY_RING) {
        atomic_store_explicit(&r->dropped,
                              atomic_load_explicit(&r->dropped, memory_order_relaxed) + 1u,
                              memory_order_relaxed);
        return;
    }
    r->items[head & (ROZ_CFG_TELEMETRY_RING - 1)] = (roz_metric_t){ abi->tick, value };
    atomic_store_explicit(&r->head, head + 1, memory_order_release);
}

int roz_metric_ring_pop(roz_metric_ring_t *r, roz_metric_t *out)
{
    uint_fast32_t tail = atomic_load_explicit(&r->tail, memory_order_relaxed);
    uint_fast32_t head = atomic_load_explicit(&r->head, memory_order_acquire);

    if (head == tail)
        return 0;
    *out = r->items[tail & (ROZ_CFG_TELEMETRY_RING - 1)];
    atomic_store_explicit(&r->tail, tail + 1, memory_order_release);
    return 1;
}

uint32_t roz_metric_ring_dropped(const roz_metric_ring_t *r)
{
    return atomic_load_explicit(&r->dropped, memory_order_relaxed);
}

/* ---- fuel of the imports ------------------------------------------------- */

/* The imports whose work is more than a call's, charged on top before the
 * work, so that a unit stays about the same time whatever the controller
 * calls (bench/fuel, host_*): sin and cos run a polynomial after a
 * Cody-Waite reduction, and below |x| = 2^24 that is about 40 units' worth;
 * from 2^24 on the reduction multiplies the mantissa by 192 bits of 2/pi,
 * about three times that (BENCHMARKS.md, bench/fuel has the figures).
 * timing.now_ns reads the host's clock (a vDSO clock_gettime, ~30 ns here):
 * ROZ_ABI_NOW_UNITS. */
#define MATH_UNITS       32u
#define MATH_LARGE_UNITS 96u /* more, for |x| >= 2^24 (and inf, NaN: cheap, rare) */

uint64_t roz_abi_math_units(double x)
{
    return (x < 0x1p24 && x > -0x1p24) ? MATH_UNITS : MATH_UNITS + MATH_LARGE_UNITS;
}

/* The bulk extension: the values a call moves are charged on top of the
 * call, before any moves, so that fuel stays proportional to work: a value
 * moved costs about what an instruction does (bench/fuel: host_get_all,
 * host_set_all). */
#define BULK_GET_UNITS_PER_VALUE 1u
#define BULK_SET_UNITS_PER_VALUE 2u

/* Units for `count` values: none for a count the ABI will refuse anyway. */
static uint64_t bulk_units(int32_t count, uint32_t per_value)
{
    return count > 0 && count <= ROZ_ABI_BULK_MAX ? (uint64_t)count * per_value : 0u;
}

uint64_t roz_abi_state_get_all_units(int32_t count)
{
    return bulk_units(count, BULK_GET_UNITS_PER_VALUE);
}

uint64_t roz_abi_command_set_all_units(int32_t count)
{
    return bulk_units(count, BULK_SET_UNITS_PER_VALUE);
}

/* ---- the bulk extension ---------------------------------------------------- */

/* Values cross linear memory as little-endian f64 (the WebAssembly byte
 * order); on a big-endian host each one is turned around. */
#if defined(__BYTE_ORDER__) && defined(__ORDER_BIG_ENDIAN__) && \
    __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#define ROZ_ABI_BIG_ENDIAN 1
#else
#define ROZ_ABI_BIG_ENDIAN 0
#endif

static inline uint64_t le64(uint64_t v)
{
#if ROZ_ABI_BIG_ENDIAN
    return __builtin_bswap64(v);
#else
    return v;
#endif
}

/* 1 when [ptr, ptr + 8 count) lies inside a memory of mem_len bytes;
 * count is 0..ROZ_ABI_BULK_MAX here, so nothing overflows 64 bits. */
static int bulk_range_ok(const uint8_t *mem, size_t mem_len, uint32_t ptr, int32_t count)
{
    uint64_t end = (uint64_t)ptr + 8u * (uint64_t)count;
    return mem != NULL && end <= (uint64_t)mem_len;
}

int32_t roz_abi_state_get_all(roz_abi_t *abi, uint8_t *mem, size_t mem_len, uint32_t ptr,
                              int32_t count)
{
    if (count < 0 || count > roz_abi_state_count(abi) || abi->state == NULL ||
        !bulk_range_ok(mem, mem_len, ptr, count)) {
        abi->counters.get_bad_index++;
        return -1;
    }
    uint8_t *dst = mem + ptr;
#if ROZ_ABI_BIG_ENDIAN
    for (int32_t i = 0; i < count; i++) {
        uint64_t bits;
        memcpy(&bits, &abi->state[i], sizeof bits);
        bits = le64(bits);
        memcpy(dst + 8 * (size_t)i, &bits, sizeof bits);
    }
#else
    memcpy(dst, abi->state, 8u * (size_t)count);
#endif
    return count;
}

int32_t roz_abi_command_set_all(roz_abi_t *abi, const uint8_t *mem, size_t mem_len,
                                uint32_t ptr, int32_t count)
{
    if (count < 0 || count > (int32_t)abi->manifest->n_commands ||
        !bulk_range_ok(mem, mem_len, ptr, count)) {
        abi->counters.sets++;
        abi->counters.set_bad_index++;
        return -1;
    }
    /* command.set's steps for each value (roz_abi_command_set), with the
     * index known good and the counters summed once */
    const uint8_t *src = mem + ptr;
    const roz_channel_t *c = abi->manifest->commands;
    uint64_t clamped = 0, nonfinite = 0;
    for (int32_t i = 0; i < count; i++) {
        uint64_t bits;
        double v;
        memcpy(&bits, src + 8 * (size_t)i, sizeof bits);
        bits = le64(bits);
        memcpy(&v, &bits, sizeof v);
        if (v >= c[i].min && v <= c[i].max) { /* the usual value: false for NaN */
            abi->target[i] = v;
        } else if (!isfinite(v)) {
            nonfinite++;
            abi->target[i] = NAN;
        } else {
            clamped++;
            abi->target[i] = v < c[i].min ? c[i].min : c[i].max;
        }
    }
    abi->counters.sets += (uint64_t)count;
    abi->counters.set_clamped += clamped;
    abi->counters.set_nonfinite += nonfinite;
    return (int32_t)(clamped + nonfinite);
}

/* ---- the neural-network extension ---------------------------------------- */
#if ROZ_CFG_NN_IMPORTS /* to the end of the file */

/* the host-order bits of a little-endian f32 */
static inline uint32_t ld_bits32(const uint8_t *p)
{
    uint32_t u;
    memcpy(&u, p, sizeof u);
#if ROZ_ABI_BIG_ENDIAN
    u = __builtin_bswap32(u);
#endif
    return u;
}

static inline float f32_of(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline float ld_f32(const uint8_t *p)
{
    return f32_of(ld_bits32(p));
}

/* a float the nn imports read: roz_math_nn_inputf()'s rule (zero of its
 * sign below 2^-51), on the bits, branch-free so that rows stay in lanes */
static inline float ld_nn(const uint8_t *p)
{
    uint32_t u = ld_bits32(p);
    u &= (u & 0x7FFFFFFFu) < ROZ_MATH_NN_TINY_BITS ? 0x80000000u : 0xFFFFFFFFu;
    return f32_of(u);
}

static inline void st_f32(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
#if ROZ_ABI_BIG_ENDIAN
    u = __builtin_bswap32(u);
#endif
    memcpy(p, &u, sizeof u);
}

/* 1 when [at, at + bytes) lies inside the memory; no sum can wrap */
static int nn_range_ok(size_t mem_len, uint32_t at, uint64_t bytes)
{
    return bytes <= (uint64_t)mem_len && (uint64_t)at <= (uint64_t)mem_len - bytes;
}

/* 1 when two ranges share a byte (empty ones share none) */
static int nn_overlap(uint32_t a, uint64_t an, uint32_t b, uint64_t bn)
{
    return an != 0 && bn != 0 && (uint64_t)a < (uint64_t)b + bn && (uint64_t)b < (uint64_t)a + an;
}

static int32_t nn_refuse(roz_abi_t *abi)
{
    abi->counters.nn_refused++;
    return -1;
}

uint64_t roz_abi_nn_matvec_units(int32_t rows, int32_t cols)
{
    if (rows < 0 || cols < 0)
        return 0;
    uint64_t macs = (uint64_t)rows * (uint64_t)cols; /* < 2^62 */
    if (macs > ROZ_ABI_NN_MAX_BYTES / 4u || (uint64_t)rows > ROZ_ABI_NN_MAX_BYTES / 4u)
        return 0;
    return macs * ROZ_ABI_NN_UNITS_PER_MAC + (uint64_t)rows * ROZ_ABI_NN_UNITS_PER_ROW;
}

uint64_t roz_abi_nn_act_units(int32_t kind, int32_t count)
{
    if (kind < 0 || kind >= ROZ_ABI_NN_ACT_COUNT || count < 0 ||
        (uint64_t)count > ROZ_ABI_NN_MAX_BYTES / 4u)
        return 0;
    return (uint64_t)count * (kind == ROZ_ABI_NN_RELU ? ROZ_ABI_NN_UNITS_RELU
                                                      : ROZ_ABI_NN_UNITS_CURVE);
}

/* Rows side by side: NN_BLOCK independent sums, each in its own fixed
 * order (that of the plain loop in roz/abi.h), so a compiler may keep them
 * in vector lanes or registers but never changes a result. Float arithmetic
 * throughout; the core is built with -ffp-contract=off, so no product is
 * fused into its sum. */
#define NN_BLOCK 8

static float nn_finish(float s, const uint8_t *b, const uint8_t *y, int32_t flags)
{
    if (flags & ROZ_ABI_NN_BIAS)
        s = s + ld_nn(b);
    if (flags & ROZ_ABI_NN_ACCUMULATE)
        s = ld_nn(y) + s;
    return s;
}

int32_t roz_abi_nn_matvec(roz_abi_t *abi, uint8_t *mem, size_t mem_len, uint32_t w,
                          uint32_t x, uint32_t b, uint32_t y, int32_t rows, int32_t cols,
                          int32_t flags)
{
    abi->counters.nn_calls++;
    if (mem == NULL || rows < 0 || cols < 0 ||
        (flags & ~(ROZ_ABI_NN_BIAS | ROZ_ABI_NN_ACCUMULATE)) != 0)
        return nn_refuse(abi);
    uint64_t wn = 4u * (uint64_t)rows * (uint64_t)cols; /* < 2^64: both < 2^31 */
    uint64_t xn = 4u * (uint64_t)cols, yn = 4u * (uint64_t)rows;
    uint64_t bn = (flags & ROZ_ABI_NN_BIAS) ? yn : 0u;
    if (!nn_range_ok(mem_len, w, wn) || !nn_range_ok(mem_len, x, xn) ||
        (bn != 0 && !nn_range_ok(mem_len, b, bn)) || !nn_range_ok(mem_len, y, yn) ||
        nn_overlap(y, yn, w, wn) || nn_overlap(y, yn, x, xn) || nn_overlap(y, yn, b, bn))
        return nn_refuse(abi);

    const uint8_t *W = mem + w, *X = mem + x, *B = mem + b;
    uint8_t *Y = mem + y;
    size_t stride = 4u * (size_t)cols, n = (size_t)cols;
    int32_t i = 0;
    for (; rows - i >= NN_BLOCK; i += NN_BLOCK) {
        float s[NN_BLOCK] = { 0 };
        const uint8_t *row = W + (size_t)i * stride;
        for (size_t j = 0; j < n; j++) {
            float xj = ld_nn(X + 4u * j);
            for (int r = 0; r < NN_BLOCK; r++)
                s[r] = s[r] + ld_nn(row + (size_t)r * stride + 4u * j) * xj;
        }
        for (int r = 0; r < NN_BLOCK; r++) {
            size_t o = 4u * ((size_t)i + (size_t)r);
            st_f32(Y + o, nn_finish(s[r], B + o, Y + o, flags));
        }
    }
    for (; i < rows; i++) {
        float s = 0.0f;
        const uint8_t *row = W + (size_t)i * stride;
        for (size_t j = 0; j < n; j++)
            s = s + ld_nn(row + 4u * j) * ld_nn(X + 4u * j);
        size_t o = 4u * (size_t)i;
        st_f32(Y + o, nn_finish(s, B + o, Y + o, flags));
    }
    return 0;
}

/* roz_math_nn_actf() takes the kinds by number */
_Static_assert(ROZ_ABI_NN_RELU == 0 && ROZ_ABI_NN_TANH == 1 && ROZ_ABI_NN_SIGMOID == 2 &&
                   ROZ_ABI_NN_ELU == 3 && ROZ_ABI_NN_EXP == 4 && ROZ_ABI_NN_ACT_COUNT == 5,
               "nn.act kinds");

/* each kind its own loop: the kind a constant in roz_math_nn_actf() */
static inline __attribute__((always_inline)) void nn_act_run(uint8_t *v, size_t n, int kind)
{
    for (size_t i = 0; i < n; i++)
        st_f32(v + 4u * i, roz_math_nn_actf(kind, ld_f32(v + 4u * i)));
}

int32_t roz_abi_nn_act(roz_abi_t *abi, uint8_t *mem, size_t mem_len, int32_t kind, uint32_t ptr,
                       int32_t count)
{
    abi->counters.nn_calls++;
    if (mem == NULL || kind < 0 || kind >= ROZ_ABI_NN_ACT_COUNT || count < 0 ||
        !nn_range_ok(mem_len, ptr, 4u * (uint64_t)count))
        return nn_refuse(abi);
    uint8_t *v = mem + ptr;
    size_t n = (size_t)count;
    switch ((roz_abi_nn_act_t)kind) {
    case ROZ_ABI_NN_RELU:
        nn_act_run(v, n, ROZ_ABI_NN_RELU);
        break;
    case ROZ_ABI_NN_TANH:
        nn_act_run(v, n, ROZ_ABI_NN_TANH);
        break;
    case ROZ_ABI_NN_SIGMOID:
        nn_act_run(v, n, ROZ_ABI_NN_SIGMOID);
        break;
    case ROZ_ABI_NN_ELU:
        nn_act_run(v, n, ROZ_ABI_NN_ELU);
        break;
    case ROZ_ABI_NN_EXP:
    default:
        nn_act_run(v, n, ROZ_ABI_NN_EXP);
        break;
    }
    return count;
}

#endif /* ROZ_CFG_NN_IMPORTS */
