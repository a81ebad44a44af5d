/* SPDX-License-Identifier: Apache-2.0 */
/* The neural-network extension: nn.matvec equals the plain loop of
 * roz/abi.h bit for bit (the host's rows run side by side in blocks; the
 * reference one at a time), for every shape, flag, alignment and special
 * value; nn.act equals roz_math.h's float functions; hostile arguments
 * (pointers past the memory, wrap-around, huge and negative counts, y
 * overlapping an input, unknown flags and kinds, no memory) are refused
 * without writing a byte, and counted; under wasm3 the work is charged as
 * fuel before it runs, so a budget stops a flood. Tiny numbers follow
 * roz_math.h's rule: no float operation of the imports takes or makes a
 * subnormal number (the slow path), on any input. */
/* white-box: this test reads the private fields of the module it tests */
#define ROZ_PRIVATE_ACCESS
#include <fenv.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "roz/abi.h"
#include "roz/controller.h"
#include "roz_math.h"
#include "support.h"
#include "support_wat.h"
#include "ur5_manifest.h"

#define MEM 65536u

static roz_abi_t abi;
static double target[ROZ_CFG_MAX_COMMANDS];
static double state[ROZ_CFG_MAX_STATES];
static uint8_t mem[MEM], before[MEM];
static uint64_t rng = 0x9E3779B97F4A7C15ull;

static uint32_t next32(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (uint32_t)(rng >> 16);
}

/* Mostly ordinary floats, now and then a special one. */
static float rand_float(void)
{
    static const float special[] = { 0.0f, -0.0f, INFINITY, -INFINITY, NAN, 1e-40f, -3e-39f,
                                     3e38f, -3e38f, 1e-30f };
    uint32_t r = next32();
    if (r % 61 == 0)
        return special[(r >> 8) % (sizeof special / sizeof special[0])];
    return ((float)(int32_t)(next32() % 2000001u) - 1000000.0f) / 250000.0f;
}

static void put(uint32_t at, float f)
{
    memcpy(mem + at, &f, 4);
}

static float get(uint32_t at)
{
    float f;
    memcpy(&f, mem + at, 4);
    return f;
}

static int setup(void **st)
{
    (void)st;
    roz_abi_init(&abi, &roz_manifest_ur5, target, NULL);
    roz_abi_begin_tick(&abi, 0, state);
    return 0;
}

/* a value as the imports read it (roz_math_nn_inputf) */
static float in(uint32_t at)
{
    return roz_math_nn_inputf(get(at));
}

/* The reference: roz/abi.h's loop, one row at a time. */
static void ref_matvec(uint32_t w, uint32_t x, uint32_t b, uint32_t y, int rows, int cols,
                       int flags, float *out)
{
    for (int i = 0; i < rows; i++) {
        float s = 0.0f;
        for (int j = 0; j < cols; j++)
            s = s + in(w + 4u * (uint32_t)(i * cols + j)) * in(x + 4u * (uint32_t)j);
        if (flags & ROZ_ABI_NN_BIAS)
            s = s + in(b + 4u * (uint32_t)i);
        out[i] = (flags & ROZ_ABI_NN_ACCUMULATE) ? in(y + 4u * (uint32_t)i) + s : s;
    }
}

static void test_nn_matvec_equals_plain_loop(void **st)
{
    static float want[256];
    int cases = 0;
    (void)st;
    for (int rows = 0; rows <= 41; rows += (rows < 20 ? 1 : 7)) {
        for (int cols = 0; cols <= 70; cols += (cols < 10 ? 1 : 13)) {
            for (int flags = 0; flags < 4; flags++) {
                /* W, x, b, y at odd offsets: alignment is free */
                uint32_t w = 1 + next32() % 3, x = w + 4u * (uint32_t)(rows * cols) + 1;
                uint32_t b = x + 4u * (uint32_t)cols + 2, y = b + 4u * (uint32_t)rows + 3;
                for (uint32_t k = 0; k < y + 4u * (uint32_t)rows; k += 4)
                    put(k, rand_float());
                ref_matvec(w, x, b, y, rows, cols, flags, want);
                memcpy(before, mem, MEM);
                assert_int_equal(roz_abi_nn_matvec(&abi, mem, MEM, w, x, b, y, rows, cols, flags),
                                 0);
                /* the bits of every output; NaN compared as NaN (its payload is the
                 * compiler's to choose in both loops) */
                for (int i = 0; i < rows; i++) {
                    float got = get(y + 4u * (uint32_t)i);
                    if (isnan(want[i]) ? !isnan(got) : memcmp(&got, &want[i], 4) != 0)
                        fail_msg("rows %d cols %d flags %d: y[%d] = %a, plain loop %a", rows,
                                 cols, flags, i, (double)got, (double)want[i]);
                }
                /* nothing outside y changed */
                assert_memory_equal(mem, before, y);
                assert_memory_equal(mem + y + 4u * (uint32_t)rows,
                                    before + y + 4u * (uint32_t)rows, MEM - y - 4u * rows);
                cases++;
            }
        }
    }
    assert_true(cases > 500);
    assert_int_equal(abi.counters.nn_refused, 0);
    assert_int_equal(abi.counters.nn_calls, (uint64_t)cases);
}

static void test_nn_act_equals_roz_math(void **st)
{
    static float (*const fn[ROZ_ABI_NN_ACT_COUNT])(float) = {
        roz_math_reluf, roz_math_tanhf, roz_math_sigmoidf, roz_math_eluf, roz_math_expf,
    };
    (void)st;
    for (int kind = 0; kind < ROZ_ABI_NN_ACT_COUNT; kind++) {
        for (uint32_t k = 0; k < 4000; k += 4)
            put(k + 1, kind == ROZ_ABI_NN_EXP ? rand_float() * 25.0f : rand_float() * 5.0f);
        memcpy(before, mem, MEM);
        assert_int_equal(roz_abi_nn_act(&abi, mem, MEM, kind, 1, 1000), 1000);
        for (uint32_t k = 0; k < 4000; k += 4) {
            float x, got = get(k + 1), want;
            memcpy(&x, before + k + 1, 4);
            want = fn[kind](roz_math_nn_inputf(x));
            if (want != 0.0f && fabsf(want) < 0x1p-126f) /* exp, sigmoid */
                want = 0.0f;
            assert_memory_equal(&got, &want, 4);
        }
    }
    /* relu, and NaN through every kind bit for bit */
    put(0, -2.0f);
    put(4, 3.0f);
    assert_int_equal(roz_abi_nn_act(&abi, mem, MEM, ROZ_ABI_NN_RELU, 0, 2), 2);
    assert_true(get(0) == 0.0f && get(4) == 3.0f);
    for (int kind = 0; kind < ROZ_ABI_NN_ACT_COUNT; kind++) {
        uint32_t nan_bits = 0x7fc01234u, got;
        memcpy(mem + 8, &nan_bits, 4);
        assert_int_equal(roz_abi_nn_act(&abi, mem, MEM, kind, 8, 1), 1);
        memcpy(&got, mem + 8, 4);
        assert_int_equal(got, nan_bits);
    }
}

/* 1 when a float operation since the last call took or made a subnormal
 * number: the underflow flag, and on x86 its denormal-operand flag. */
static void fp_flags_clear(void)
{
    feclearexcept(FE_ALL_EXCEPT);
#if defined(__SSE2__)
    _mm_setcsr(_mm_getcsr() & ~0x3Fu);
#endif
}

static int fp_flags_subnormal(void)
{
    int hit = fetestexcept(FE_UNDERFLOW) != 0;
#if defined(__SSE2__)
    hit |= (_mm_getcsr() & 0x12u) != 0; /* DE, UE */
#endif
    return hit;
}

static int is_subnormal(float f)
{
    return f != 0.0f && fabsf(f) < 0x1p-126f;
}

/* Tiny numbers: read as zero below 2^-51, no subnormal result, no float
 * operation on or to a subnormal (the slow path that made a 1 x 88,000
 * call of 1e-20 cost 65 times its fuel); NaN, infinities and the signs of
 * zeros as plain float arithmetic gives them. */
static void test_nn_tiny_numbers(void **st)
{
    static const float pick[] = { 1e-20f, -1e-20f, 3e-39f, -1e-45f, 0x1p-51f, -0x1p-51f,
                                  0x1.fffffep-52f, 0x1p-63f, 1e-30f, 0x1.8p-126f, -0x1p-126f,
                                  0x1p-50f, 0.5f, -2.0f, 0.0f, -0.0f, INFINITY, NAN };
    static float want[64];
    (void)st;
    /* the case: W and x at 1e-20, each product 1e-40 */
    for (uint32_t k = 0; k < 4000; k += 4)
        put(k, 1e-20f);
    fp_flags_clear();
    assert_int_equal(roz_abi_nn_matvec(&abi, mem, MEM, 0, 2000, 0, 8000, 1, 500, 0), 0);
    assert_false(fp_flags_subnormal());
    assert_true(get(8000) == 0.0f && !signbit(get(8000)));
    /* a row of 2^-51 times 2^-51: each product 2^-102, kept */
    for (uint32_t k = 0; k < 4000; k += 4)
        put(k, 0x1p-51f);
    assert_int_equal(roz_abi_nn_matvec(&abi, mem, MEM, 0, 2000, 0, 8000, 1, 500, 0), 0);
    assert_true(get(8000) == 500.0f * 0x1p-102f);
    /* every mix of them, every shape and flag, against the reference, flags
     * clear and no subnormal out */
    for (int round = 0; round < 400; round++) {
        int rows = 1 + (int)(next32() % 20), cols = 1 + (int)(next32() % 40);
        int flags = (int)(next32() % 4);
        uint32_t w = 0, x = 4u * (uint32_t)(rows * cols), b = x + 4u * (uint32_t)cols;
        uint32_t y = b + 4u * (uint32_t)rows;
        for (uint32_t k = 0; k < y + 4u * (uint32_t)rows; k += 4) {
            uint32_t r = next32();
            put(k, r % 3 == 0 ? rand_float() : pick[r % (sizeof pick / sizeof pick[0])]);
        }
        ref_matvec(w, x, b, y, rows, cols, flags, want);
        fp_flags_clear();
        assert_int_equal(roz_abi_nn_matvec(&abi, mem, MEM, w, x, b, y, rows, cols, flags), 0);
        assert_false(fp_flags_subnormal());
        for (int i = 0; i < rows; i++) {
            float got = get(y + 4u * (uint32_t)i);
            assert_false(is_subnormal(got));
            if (isnan(want[i]) ? !isnan(got) : memcmp(&got, &want[i], 4) != 0)
                fail_msg("rows %d cols %d flags %d: y[%d] = %a, reference %a", rows, cols,
                         flags, i, (double)got, (double)want[i]);
        }
    }
    /* activations: tiny inputs, and exp and sigmoid where the result would
     * be subnormal (below ROZ_MATH_NN_EXP_MIN), +0 */
    for (int kind = 0; kind < ROZ_ABI_NN_ACT_COUNT; kind++) {
        for (uint32_t k = 0; k < 64; k++) {
            uint32_t r = next32();
            put(4u * k, r % 2 ? pick[r % (sizeof pick / sizeof pick[0])]
                              : -87.0f - (float)(r % 1000) * 0.017f);
        }
        fp_flags_clear();
        assert_int_equal(roz_abi_nn_act(&abi, mem, MEM, kind, 0, 64), 64);
        assert_false(fp_flags_subnormal());
        for (uint32_t k = 0; k < 64; k++)
            assert_false(is_subnormal(get(4u * k)));
    }
    put(0, -87.5f);
    put(4, ROZ_MATH_NN_EXP_MIN);
    put(8, nextafterf(ROZ_MATH_NN_EXP_MIN, -INFINITY));
    assert_int_equal(roz_abi_nn_act(&abi, mem, MEM, ROZ_ABI_NN_EXP, 0, 3), 3);
    assert_true(get(0) == 0.0f && get(4) >= 0x1p-126f && get(8) == 0.0f);
    put(0, 3e-39f);
    put(4, -1e-20f);
    assert_int_equal(roz_abi_nn_act(&abi, mem, MEM, ROZ_ABI_NN_TANH, 0, 2), 2);
    assert_true(get(0) == 0.0f && !signbit(get(0)) && get(4) == 0.0f && signbit(get(4)));
}

/* The threshold is the exact one: at and above it exp and sigmoid are
 * normal, just below they are subnormal, for every float between -104 and
 * -87 (where they are monotonic). */
static void test_nn_exp_threshold(void **st)
{
    (void)st;
    for (float x = ROZ_MATH_NN_EXP_MIN; x > -87.0f; x = nextafterf(x, 0.0f))
        assert_true(roz_math_expf(x) >= 0x1p-126f && roz_math_sigmoidf(x) >= 0x1p-126f);
    for (float x = nextafterf(ROZ_MATH_NN_EXP_MIN, -INFINITY); x >= -104.0f;
         x = nextafterf(x, -INFINITY))
        assert_true(roz_math_expf(x) < 0x1p-126f && roz_math_sigmoidf(x) < 0x1p-126f);
}

/* Every refusal: -1, not a byte of the memory changed, one nn_refused. */
static void test_nn_refusals(void **st)
{
    static const struct {
        uint32_t w, x, b, y;
        int32_t rows, cols, flags;
        const char *what;
    } mv[] = {
        { 0, 400, 800, 1000, 4, 4, 1, NULL },             /* fits: the control case */
        { MEM - 63, 400, 800, 1000, 4, 4, 0, "W one byte past the end" },
        { 0, MEM - 15, 800, 1000, 4, 4, 0, "x one byte past the end" },
        { 0, 400, MEM - 15, 1000, 4, 4, 1, "b one byte past the end" },
        { 0, 400, 800, MEM - 15, 4, 4, 0, "y one byte past the end" },
        { 0xFFFFFFFFu, 400, 800, 1000, 1, 1, 0, "W at -1" },
        { 0xFFFFFFF0u, 400, 800, 1000, 4, 4, 0, "W wraps 32 bits" },
        { 0, 400, 800, 0xFFFFFFFCu, 2, 1, 0, "y wraps 32 bits" },
        { 0, 400, 800, 1000, 0x40000000, 1, 0, "4 rows is 2^32" },
        { 0, 400, 800, 1000, 0x7FFFFFFF, 0x7FFFFFFF, 0, "rows * cols near 2^62" },
        { 0, 400, 800, 1000, 65536, 65536, 0, "4 rows cols is 2^34" },
        { 0, 400, 800, 1000, -1, 4, 0, "rows negative" },
        { 0, 400, 800, 1000, 4, INT32_MIN, 0, "cols negative" },
        { 0, 400, 800, 1000, 4, 4, 4, "unknown flag" },
        { 0, 400, 800, 1000, 4, 4, -1, "every flag" },
        { 0, 400, 800, 16, 4, 4, 0, "y inside W" },
        { 0, 400, 800, 60, 4, 4, 0, "y's first value on W's last" },
        { 0, 400, 800, 388, 4, 4, 0, "y's last value on x's first" },
        { 0, 400, 800, 412, 4, 4, 0, "y's first value on x's last" },
        { 0, 400, 800, 790, 4, 4, 1, "y overlapping b" },
        { 0, 400, 1000, 1000, 4, 4, 1, "y is b" },
        { 0, 1000, 800, 1000, 4, 4, 0, "y is x" },
    };
    roz_abi_counters_t c0;
    (void)st;
    for (size_t k = 0; k < sizeof mv / sizeof mv[0]; k++) {
        for (uint32_t i = 0; i < MEM; i += 4)
            put(i, (float)(i % 97) * 0.25f);
        memcpy(before, mem, MEM);
        c0 = abi.counters;
        int32_t rc = roz_abi_nn_matvec(&abi, mem, MEM, mv[k].w, mv[k].x, mv[k].b, mv[k].y,
                                       mv[k].rows, mv[k].cols, mv[k].flags);
        if (mv[k].what == NULL) {
            assert_int_equal(rc, 0);
            continue;
        }
        if (rc != -1 || memcmp(mem, before, MEM) != 0)
            fail_msg("%s: returned %d, %s", mv[k].what, (int)rc,
                     memcmp(mem, before, MEM) != 0 ? "wrote" : "wrote nothing");
        assert_int_equal(abi.counters.nn_refused, c0.nn_refused + 1);
        assert_int_equal(abi.counters.nn_calls, c0.nn_calls + 1);
    }
    /* legal edges: b not read without BIAS (so anywhere), empty ranges anywhere,
     * y adjacent to its inputs, in-place accumulation */
    assert_int_equal(roz_abi_nn_matvec(&abi, mem, MEM, 0, 400, 0xFFFFFFFFu, 1000, 4, 4, 0), 0);
    assert_int_equal(roz_abi_nn_matvec(&abi, mem, MEM, MEM, MEM, MEM, MEM, 0, 0, 3), 0);
    assert_int_equal(roz_abi_nn_matvec(&abi, mem, MEM, 0, 400, 800, 64, 4, 4, 3), 0);
    assert_int_equal(roz_abi_nn_matvec(&abi, mem, MEM, 0, 400, 800, MEM - 16, 4, 4, 3), 0);
    /* no memory */
    c0 = abi.counters;
    assert_int_equal(roz_abi_nn_matvec(&abi, NULL, 0, 0, 0, 0, 0, 0, 0, 0), -1);
    assert_int_equal(roz_abi_nn_act(&abi, NULL, 0, 0, 0, 0), -1);
    assert_int_equal(abi.counters.nn_refused, c0.nn_refused + 2);

    static const struct {
        int32_t kind;
        uint32_t ptr;
        int32_t count;
        const char *what;
    } act[] = {
        { 1, MEM - 16, 4, NULL },
        { 1, MEM - 15, 4, "one byte past the end" },
        { 1, 0xFFFFFFFCu, 2, "wraps 32 bits" },
        { 1, 0, 0x40000000, "4 count is 2^32" },
        { 1, 0, 0x7FFFFFFF, "huge" },
        { 1, 0, -1, "negative count" },
        { -1, 0, 4, "kind -1" },
        { ROZ_ABI_NN_ACT_COUNT, 0, 4, "kind past the last" },
    };
    for (size_t k = 0; k < sizeof act / sizeof act[0]; k++) {
        memcpy(before, mem, MEM);
        c0 = abi.counters;
        int32_t rc = roz_abi_nn_act(&abi, mem, MEM, act[k].kind, act[k].ptr, act[k].count);
        if (act[k].what == NULL) {
            assert_int_equal(rc, act[k].count);
            continue;
        }
        if (rc != -1 || memcmp(mem, before, MEM) != 0)
            fail_msg("nn.act %s: returned %d", act[k].what, (int)rc);
        assert_int_equal(abi.counters.nn_refused, c0.nn_refused + 1);
    }
}

static void test_nn_units(void **st)
{
    (void)st;
    assert_int_equal(roz_abi_nn_matvec_units(256, 47), 256u * 47u + 2u * 256u);
    assert_int_equal(roz_abi_nn_matvec_units(0, 0), 0);
    assert_int_equal(roz_abi_nn_matvec_units(-1, 4), 0);
    assert_int_equal(roz_abi_nn_matvec_units(0x7FFFFFFF, 0x7FFFFFFF), 0); /* refused anyway */
    assert_int_equal(roz_abi_nn_act_units(ROZ_ABI_NN_TANH, 64), 64u * ROZ_ABI_NN_UNITS_CURVE);
    assert_int_equal(roz_abi_nn_act_units(ROZ_ABI_NN_RELU, 64), 64u * ROZ_ABI_NN_UNITS_RELU);
    assert_int_equal(roz_abi_nn_act_units(9, 64), 0);
    assert_int_equal(roz_abi_nn_act_units(1, -64), 0);
}

/* ---- under wasm3 ------------------------------------------------------------ */

static roz_controller_t ctl;
static roz_abi_t wabi;
static double wtarget[ROZ_CFG_MAX_COMMANDS];
static uint8_t wasm[4096];

static int teardown(void **st)
{
    (void)st;
    roz_controller_unload(&ctl);
    return 0;
}

/* Loads `text` on the UR5 with a fuel budget and runs tick 0. */
static int run_wat(const char *text, uint64_t fuel)
{
    roz_budget_t b = { fuel, ROZ_BUDGET_OFF, NULL, NULL };
    size_t len = roz_test_wat(text, wasm, sizeof wasm);
    roz_controller_unload(&ctl);
    roz_controller_init(&ctl);
    roz_abi_init(&wabi, &roz_manifest_ur5, wtarget, NULL);
    roz_abi_begin_tick(&wabi, 0, state);
    if (roz_controller_load(&ctl, wasm, len, &wabi) != ROZ_OK)
        fail_msg("load: %s", roz_controller_error(&ctl));
    assert_int_equal(roz_controller_set_budget(&ctl, &b), ROZ_OK);
    return roz_controller_process(&ctl, 0);
}

/* One nn.matvec call with these arguments; its result lands in command 0
 * (0 or -1). */
static int32_t wasm_matvec(uint32_t w, uint32_t x, uint32_t b, uint32_t y, int32_t rows,
                           int32_t cols, int32_t flags, int memory, uint64_t *fuel)
{
    char text[1400];
    snprintf(text, sizeof text,
             "(module\n"
             "  (import \"nn\" \"matvec\" (func $mv (param i32 i32 i32 i32 i32 i32 i32)"
             " (result i32)))\n"
             "  (import \"command\" \"set\" (func $set (param i32 f64) (result i32)))\n"
             "  %s\n"
             "  (func (export \"process\") (param i64)\n"
             "    (drop (call $set (i32.const 0) (f64.convert_i32_s (call $mv (i32.const %u)"
             " (i32.const %u) (i32.const %u) (i32.const %u) (i32.const %d) (i32.const %d)"
             " (i32.const %d)))))))\n",
             memory ? "(memory 1)" : "", (unsigned)w, (unsigned)x, (unsigned)b, (unsigned)y,
             (int)rows, (int)cols, (int)flags);
    assert_int_equal(run_wat(text, 100000000), ROZ_OK); /* never a trap */
    if (fuel != NULL)
        *fuel = roz_controller_fuel_used(&ctl);
    return (int32_t)wtarget[0];
}

static void test_nn_wasm_refusals_and_fuel(void **st)
{
    uint64_t f0, f1, f2;
    (void)st;
    assert_int_equal(wasm_matvec(0, 4096, 8192, 9000, 16, 32, 1, 1, &f1), 0);
    assert_int_equal(wasm_matvec(0, 4096, 8192, 9000, 0, 0, 1, 1, &f0), 0);
    assert_int_equal(f1 - f0, roz_abi_nn_matvec_units(16, 32));
    assert_int_equal(wasm_matvec(0, 4096, 8192, 9000, 64, 32, 1, 1, &f2), 0);
    assert_int_equal(f2 - f0, 64u * 32u + 2u * 64u);
    /* refused, no trap, nothing charged for counts refused whatever the pointers */
    assert_int_equal(wasm_matvec(65536 - 4, 0, 0, 9000, 16, 32, 0, 1, &f1), -1);
    assert_int_equal(f1 - f0, roz_abi_nn_matvec_units(16, 32)); /* a bad pointer costs the work */
    assert_int_equal(wasm_matvec(0, 0, 0, 9000, 0x7FFFFFFF, 0x7FFFFFFF, 0, 1, &f1), -1);
    assert_true(f1 <= f0 + 2); /* the call's own units (its constants compile differently),
                                  nothing for 2^62 multiply-adds */
    assert_int_equal(wasm_matvec(0, 0, 0, 0xFFFFFFF0u, 4, 4, 0, 1, NULL), -1);
    assert_int_equal(wasm_matvec(0, 0, 0, 60, 4, 4, 0, 1, NULL), -1); /* y inside W */
    assert_int_equal(wasm_matvec(0, 0, 0, 0, 0, 0, 0, 0, NULL), -1);  /* no memory */
    assert_int_equal(wabi.counters.nn_refused, 1);

    /* a flood of the largest legal calls is stopped by its budget */
    static const char flood[] =
        "(module\n"
        "  (import \"nn\" \"matvec\" (func $mv (param i32 i32 i32 i32 i32 i32 i32)"
        " (result i32)))\n"
        "  (import \"nn\" \"act\" (func $act (param i32 i32 i32) (result i32)))\n"
        "  (memory 1)\n"
        "  (func (export \"process\") (param i64)\n"
        "    (loop $l\n"
        "      (drop (call $mv (i32.const 0) (i32.const 0) (i32.const 0) (i32.const 64000)"
        " (i32.const 100) (i32.const 150) (i32.const 0)))\n"
        "      (drop (call $act (i32.const 1) (i32.const 0) (i32.const 16000)))\n"
        "      (br $l))))\n";
    assert_int_equal(run_wat(flood, 1000000), ROZ_ETIMEDOUT);
    assert_non_null(strstr(roz_controller_error(&ctl), "fuel exhausted"));
    /* stopped within one call's charge of the budget, before that call ran */
    assert_true(roz_controller_fuel_used(&ctl) <= 1000000u + 16000u * ROZ_ABI_NN_UNITS_CURVE);
    assert_true(wabi.counters.nn_calls < 2u * (1000000u / (100u * 150u)) + 2u);
}

ROZ_TEST_MAIN(cmocka_unit_test_setup(test_nn_matvec_equals_plain_loop, setup),
              cmocka_unit_test_setup(test_nn_act_equals_roz_math, setup),
              cmocka_unit_test_setup(test_nn_tiny_numbers, setup),
              cmocka_unit_test(test_nn_exp_threshold),
              cmocka_unit_test_setup(test_nn_refusals, setup),
              cmocka_unit_test(test_nn_units),
              cmocka_unit_test_teardown(test_nn_wasm_refusals_and_fuel, teardown))
