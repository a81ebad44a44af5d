/* SPDX-License-Identifier: Apache-2.0 */
/* The controllers' math header (lib/math/roz_math.h),
 * compiled natively, against the host's libm: the exact functions bit for
 * bit (signed zeros, NaN), the others within their documented error in ulps
 * of a long double reference (sinl, expl, ...: 64-bit mantissas, so the
 * reference is 2^11 times finer than the result), over dense sweeps of each
 * domain and the edge cases: 0, -0, inf, NaN, huge, tiny, subnormal, and
 * the places where each algorithm changes course. Prints the largest error
 * found per function. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "roz_math.h"
#include "support.h"
#include "ulps.h"
#include "support_thin.h"

/* under an emulator, every THIN-th step of the sweeps and random runs */
#define THIN ROZ_TEST_THIN(32)

/* The documented bounds (roz_math.h), in ulps. */
#define BOUND_SIN   1.0
#define BOUND_EXP   1.0
#define BOUND_LOG   1.0
#define BOUND_POW   1.0
#define BOUND_ATAN2 1.0
#define BOUND_TANH  1.0

/* ---- helpers ---------------------------------------------------------------- */

static uint64_t rng = 0x9E3779B97F4A7C15u;

static uint64_t next_u64(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

/* uniform in [lo, hi] */
static double uniform(double lo, double hi)
{
    return lo + (hi - lo) * ((double)(next_u64() >> 11) * 0x1p-53);
}

/* any finite double, every exponent equally likely */
static double any_double(void)
{
    uint64_t u;
    double d;
    do {
        u = next_u64();
        memcpy(&d, &u, sizeof d);
    } while (!isfinite(d));
    return d;
}

typedef struct {
    const char *name;
    double      worst;
    double      at_x, at_y;
} record_t;

static void note(record_t *r, double err, double x, double y)
{
    if (err > r->worst) {
        r->worst = err;
        r->at_x = x;
        r->at_y = y;
    }
}

static void finish(const record_t *r, double bound)
{
    print_message("roz_math %-6s max error %.3f ulp (at %.17g, %.17g), bound %.1f\n", r->name,
                  r->worst, r->at_x, r->at_y, bound);
    if (!(r->worst < bound))
        fail_msg("%s: %.3f ulp at (%.17g, %.17g), bound %.1f", r->name, r->worst, r->at_x,
                 r->at_y, bound);
}

/* bit for bit, except that any NaN matches any NaN */
static void assert_same(double got, double want, const char *what, double x)
{
    if (isnan(got) && isnan(want))
        return;
    if (bits_of(got) != bits_of(want))
        fail_msg("%s(%.17g) = %.17g (0x%016llx), libm %.17g (0x%016llx)", what, x, got,
                 (unsigned long long)bits_of(got), want, (unsigned long long)bits_of(want));
}

static const double specials[] = {
    0.0, -0.0, 1.0, -1.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 3.0, 0.49999999999999994,
    4503599627370495.5, 4503599627370496.0, -4503599627370497.0, 9007199254740993.0,
    1e300, -1e300, DBL_MAX, -DBL_MAX, DBL_MIN, -DBL_MIN, 5e-324, -5e-324, 1e-310, -2.5e-320,
    1e-300, HUGE_VAL, -HUGE_VAL, NAN, -NAN, 0.1, 1e-17, 123456.789,
};
#define N_SPECIALS (sizeof specials / sizeof specials[0])

/* ---- the exact functions --------------------------------------------------------- */

static void test_math_exact_functions(void **state)
{
    (void)state;
    if (THIN > 1)
        print_message("under an emulator: 1 in %d steps of the sweeps and random runs\n", THIN);
    for (int i = 0; i < 400000 + (int)N_SPECIALS; i += i < (int)N_SPECIALS ? 1 : THIN) {
        double x = i < (int)N_SPECIALS ? specials[i]
                   : i % 2 ? any_double() : uniform(-1e6, 1e6);
        double y = i < (int)N_SPECIALS ? specials[(i + 7) % N_SPECIALS] : any_double();
        assert_same(roz_math_fabs(x), fabs(x), "fabs", x);
        assert_same(roz_math_copysign(x, y), copysign(x, y), "copysign", x);
        assert_same(roz_math_sqrt(x), sqrt(x), "sqrt", x);
        assert_same(roz_math_sqrt(fabs(x)), sqrt(fabs(x)), "sqrt", fabs(x));
        assert_same(roz_math_floor(x), floor(x), "floor", x);
        assert_same(roz_math_ceil(x), ceil(x), "ceil", x);
        assert_same(roz_math_trunc(x), trunc(x), "trunc", x);
        if (!(x == 0.0 && y == 0.0)) { /* libm leaves the sign of fmin(-0, +0) open */
            assert_same(roz_math_fmin(x, y), fmin(x, y), "fmin", x);
            assert_same(roz_math_fmax(x, y), fmax(x, y), "fmax", x);
        }
    }
    /* sqrt near squares and halfway cases of every binade */
    for (int e = -1074; e <= 1023; e += 1) {
        double b = ldexp(1.0, e);
        for (int k = -2; k <= 2; k++) {
            double x = b + k * (e >= -1022 ? ldexp(1.0, e - 52) : 5e-324);
            if (x > 0.0)
                assert_same(roz_math_sqrt(x), sqrt(x), "sqrt", x);
        }
    }
    for (double r = 1.0; r < 1e7; r = r * 1.0001 + 1.0) {
        double sq = r * r;
        assert_same(roz_math_sqrt(sq), sqrt(sq), "sqrt", sq);
        assert_same(roz_math_sqrt(nextafter(sq, 0.0)), sqrt(nextafter(sq, 0.0)), "sqrt", sq);
    }
    /* the signed zeros libm leaves open, as roz_math.h defines them */
    assert_true(signbit(roz_math_fmin(-0.0, 0.0)) && signbit(roz_math_fmin(0.0, -0.0)));
    assert_false(signbit(roz_math_fmax(-0.0, 0.0)) || signbit(roz_math_fmax(0.0, -0.0)));
    /* clamp */
    assert_true(roz_math_clamp(5.0, -1.0, 2.0) == 2.0);
    assert_true(roz_math_clamp(-5.0, -1.0, 2.0) == -1.0);
    assert_true(roz_math_clamp(0.25, -1.0, 2.0) == 0.25);
    assert_true(roz_math_clamp(HUGE_VAL, -1.0, 2.0) == 2.0);
    assert_true(isnan(roz_math_clamp(NAN, -1.0, 2.0)));
}

/* ---- sin, cos ---------------------------------------------------------------------- */

static void check_sincos(record_t *rs, record_t *rc, double x)
{
    note(rs, ulps(roz_math_sin(x), sinl((long double)x)), x, 0);
    note(rc, ulps(roz_math_cos(x), cosl((long double)x)), x, 0);
}

static void test_math_sin_cos(void **state)
{
    record_t rs = { "sin", 0, 0, 0 }, rc = { "cos", 0, 0, 0 };
    (void)state;
    for (int i = 0; i <= 200000; i += THIN) /* dense over two turns */
        check_sincos(&rs, &rc, -4.0 * ROZ_MATH_PI + 8.0 * ROZ_MATH_PI * i / 200000.0);
    for (int i = 0; i < 100000; i += THIN) {
        check_sincos(&rs, &rc, uniform(-1e3, 1e3));
        check_sincos(&rs, &rc, uniform(-0x1p24, 0x1p24));
        check_sincos(&rs, &rc, any_double());             /* the full reduction */
        check_sincos(&rs, &rc, uniform(-1e-5, 1e-5));
    }
    /* next to multiples of pi/2, where the remainder cancels most: small
     * multiples, around 2^24 where the reduction changes, and huge ones */
    for (int k = -2000; k <= 2000; k++) {
        double c = k * (ROZ_MATH_PI / 2.0);
        for (int d = -3; d <= 3; d++) {
            double x = c;
            for (int s = 0; s < (d < 0 ? -d : d); s++)
                x = nextafter(x, d < 0 ? -HUGE_VAL : HUGE_VAL);
            check_sincos(&rs, &rc, x);
        }
    }
    for (double x = 0x1p24 - 64.0; x < 0x1p24 + 64.0; x += 0.25)
        check_sincos(&rs, &rc, x);
    /* doubles known to lie very close to a multiple of pi/2 */
    static const double close[] = { 6381956970095103.0 * 0x1p797, 5.319372648326541e+255,
                                    1.5707963267948966, 3.141592653589793, 4.71238898038469,
                                    6.283185307179586, 355.0, 103993.0, 1e22, 0x1p1023 };
    for (size_t i = 0; i < sizeof close / sizeof close[0]; i++) {
        check_sincos(&rs, &rc, close[i]);
        check_sincos(&rs, &rc, -close[i]);
    }
    for (size_t i = 0; i < N_SPECIALS; i++) {
        double x = specials[i];
        if (isfinite(x)) {
            check_sincos(&rs, &rc, x);
        } else {
            assert_true(isnan(roz_math_sin(x)) && isnan(roz_math_cos(x)));
        }
    }
    assert_same(roz_math_sin(-0.0), -0.0, "sin", -0.0);
    assert_same(roz_math_sin(5e-324), 5e-324, "sin", 5e-324);
    assert_same(roz_math_cos(0.0), 1.0, "cos", 0.0);
    finish(&rs, BOUND_SIN);
    finish(&rc, BOUND_SIN);
}

/* ---- atan2 -------------------------------------------------------------------------- */

static void test_math_atan2(void **state)
{
    record_t r = { "atan2", 0, 0, 0 };
    static const double edge[] = { 0.0, -0.0, 1.0, -1.0, 5e-324, -5e-324, DBL_MAX, -DBL_MAX,
                                   HUGE_VAL, -HUGE_VAL, NAN, 1e-300, 3.0 };
    (void)state;
    for (int i = 0; i <= 200000; i += THIN) { /* around the circle */
        double th = -ROZ_MATH_PI + 2.0 * ROZ_MATH_PI * i / 200000.0, rad = uniform(0.1, 10.0);
        double y = rad * sin(th), x = rad * cos(th);
        note(&r, ulps(roz_math_atan2(y, x), atan2l(y, x)), y, x);
    }
    for (int i = 0; i < 200000; i += THIN) {
        double y = any_double(), x = any_double();
        note(&r, ulps(roz_math_atan2(y, x), atan2l(y, x)), y, x);
        y = uniform(-2.0, 2.0);
        x = uniform(-2.0, 2.0);
        note(&r, ulps(roz_math_atan2(y, x), atan2l(y, x)), y, x);
        x = uniform(0.4, 2.5); /* ratios around tan(pi/8) and 1 */
        y = x * uniform(0.35, 1.05);
        note(&r, ulps(roz_math_atan2(y, x), atan2l(y, x)), y, x);
    }
    for (size_t i = 0; i < sizeof edge / sizeof edge[0]; i++) {
        for (size_t j = 0; j < sizeof edge / sizeof edge[0]; j++) {
            double y = edge[i], x = edge[j], got = roz_math_atan2(y, x), want = atan2(y, x);
            if (isnan(want) || got == 0.0 || isinf(x) || isinf(y) || x == 0.0 || y == 0.0)
                assert_same(got, want, "atan2", y); /* the special cases: exactly C99's */
            else
                note(&r, ulps(got, atan2l(y, x)), y, x);
        }
    }
    finish(&r, BOUND_ATAN2);
}

/* ---- exp, log, pow, tanh ----------------------------------------------------------- */

static void test_math_exp(void **state)
{
    record_t r = { "exp", 0, 0, 0 };
    (void)state;
    for (int i = 0; i <= 300000; i += THIN) {
        double x = -746.0 + 1456.0 * i / 300000.0;
        note(&r, ulps(roz_math_exp(x), expl(x)), x, 0);
    }
    for (int i = 0; i < 200000; i += THIN) {
        double x = uniform(-1.0, 1.0);
        note(&r, ulps(roz_math_exp(x), expl(x)), x, 0);
        x = uniform(-1e-8, 1e-8);
        note(&r, ulps(roz_math_exp(x), expl(x)), x, 0);
        x = uniform(-745.2, -700.0); /* subnormal results */
        note(&r, ulps(roz_math_exp(x), expl(x)), x, 0);
        x = uniform(-760.0, 720.0);
        note(&r, ulps(roz_math_exp(x), expl(x)), x, 0);
    }
    static const double edge[] = { 709.782712893384, 709.7827128933841, 709.78271289338397,
                                   -745.1332191019411, -745.1332191019412, -745.13321910194122,
                                   -708.3964185322641, 1e-300, -1e-300, 5e-324 };
    for (size_t i = 0; i < sizeof edge / sizeof edge[0]; i++)
        note(&r, ulps(roz_math_exp(edge[i]), expl(edge[i])), edge[i], 0);
    for (size_t i = 0; i < N_SPECIALS; i++) {
        double x = specials[i];
        if (!isfinite(x) || fabs(x) > 1000.0 || x == 0.0)
            assert_same(roz_math_exp(x), exp(x), "exp", x);
        else
            note(&r, ulps(roz_math_exp(x), expl(x)), x, 0);
    }
    finish(&r, BOUND_EXP);
}

static void test_math_log(void **state)
{
    record_t r = { "log", 0, 0, 0 };
    (void)state;
    for (int i = 0; i < 300000; i += THIN) {
        double x = fabs(any_double());
        note(&r, ulps(roz_math_log(x), logl(x)), x, 0);
        x = uniform(0.5, 2.0);
        note(&r, ulps(roz_math_log(x), logl(x)), x, 0);
        x = 1.0 + uniform(-1e-6, 1e-6);
        note(&r, ulps(roz_math_log(x), logl(x)), x, 0);
    }
    for (int k = -1074; k <= 1023; k++) { /* powers of two and their neighbours */
        double x = ldexp(1.0, k);
        note(&r, ulps(roz_math_log(x), logl(x)), x, 0);
        note(&r, ulps(roz_math_log(nextafter(x, 0.0)), logl(nextafter(x, 0.0))), x, 0);
        x = ldexp(1.4142135623730951, k < 1023 ? k : 1022); /* where m is halved */
        note(&r, ulps(roz_math_log(x), logl(x)), x, 0);
        note(&r, ulps(roz_math_log(nextafter(x, HUGE_VAL)), logl(nextafter(x, HUGE_VAL))), x, 0);
    }
    for (size_t i = 0; i < N_SPECIALS; i++) {
        double x = specials[i];
        if (!isfinite(x) || x <= 0.0 || x == 1.0)
            assert_same(roz_math_log(x), log(x), "log", x);
        else
            note(&r, ulps(roz_math_log(x), logl(x)), x, 0);
    }
    finish(&r, BOUND_LOG);
}

static void check_pow(record_t *r, double x, double y)
{
    note(r, ulps(roz_math_pow(x, y), powl(x, y)), x, y);
}

static void test_math_pow(void **state)
{
    record_t r = { "pow", 0, 0, 0 };
    static const double edge[] = { 0.0, -0.0, 1.0, -1.0, 0.5, -0.5, 2.0, -2.0, 3.0, -3.0,
                                   2.5, -2.5, 1e300, -1e300, 5e-324, -5e-324, DBL_MAX,
                                   HUGE_VAL, -HUGE_VAL, NAN, 9007199254740993.0,
                                   -9007199254740991.0, 1e20, 1.0000000000000002,
                                   0.9999999999999999 };
    (void)state;
    for (int i = 0; i < 200000; i += THIN) {
        check_pow(&r, uniform(0.0, 100.0), uniform(-50.0, 50.0));
        check_pow(&r, uniform(0.0, 2.0), uniform(-1000.0, 1000.0));
        check_pow(&r, 1.0 + uniform(-1e-3, 1e-3), uniform(-1e6, 1e6));
        check_pow(&r, -uniform(0.0, 10.0), (double)(int)uniform(-300.0, 300.0));
        check_pow(&r, fabs(any_double()), uniform(-4.0, 4.0));
        check_pow(&r, uniform(0.0, 10.0), any_double() * 1e-300);
    }
    for (int k = 2; k < 60; k++) /* exact results: integer powers, square roots */
        for (double b = 2.0; b < 40.0; b += 1.0)
            if (pow(b, k) < 0x1p53) {
                assert_same(roz_math_pow(b, k), pow(b, k), "pow", b);
                assert_same(roz_math_pow(-b, k), pow(-b, k), "pow", -b);
            }
    for (size_t i = 0; i < sizeof edge / sizeof edge[0]; i++) {
        for (size_t j = 0; j < sizeof edge / sizeof edge[0]; j++) {
            double x = edge[i], y = edge[j], got = roz_math_pow(x, y), want = pow(x, y);
            if (isnan(want) || isinf(want) || want == 0.0 || want == 1.0 || isinf(x) ||
                isinf(y) || x == 0.0 || fabs(x) == 1.0 || y == 0.0)
                assert_same(got, want, "pow", x); /* the special cases: exactly C99's */
            else
                check_pow(&r, x, y);
        }
    }
    finish(&r, BOUND_POW);
}

static void test_math_tanh(void **state)
{
    record_t r = { "tanh", 0, 0, 0 };
    (void)state;
    for (int i = 0; i <= 300000; i += THIN) {
        double x = -25.0 + 50.0 * i / 300000.0;
        note(&r, ulps(roz_math_tanh(x), tanhl(x)), x, 0);
    }
    for (int i = 0; i < 200000; i += THIN) {
        double x = uniform(-0.5, 0.5);
        note(&r, ulps(roz_math_tanh(x), tanhl(x)), x, 0);
        x = uniform(-1e-6, 1e-6);
        note(&r, ulps(roz_math_tanh(x), tanhl(x)), x, 0);
        x = any_double();
        note(&r, ulps(roz_math_tanh(x), tanhl(x)), x, 0);
    }
    for (size_t i = 0; i < N_SPECIALS; i++) {
        double x = specials[i];
        if (!isfinite(x) || x == 0.0)
            assert_same(roz_math_tanh(x), tanh(x), "tanh", x);
        else
            note(&r, ulps(roz_math_tanh(x), tanhl(x)), x, 0);
    }
    finish(&r, BOUND_TANH);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_math_exact_functions),
              cmocka_unit_test(test_math_sin_cos),
              cmocka_unit_test(test_math_atan2),
              cmocka_unit_test(test_math_exp),
              cmocka_unit_test(test_math_log),
              cmocka_unit_test(test_math_pow),
              cmocka_unit_test(test_math_tanh))
