/* SPDX-License-Identifier: Apache-2.0 */
/* roz_math.h's float functions (the NN activations: expf, expm1f, tanhf,
 * sigmoidf, eluf, reluf) against the host's libm in long double over every
 * 2039th float bit pattern (all signs, subnormals, infinities, NaN; every
 * 32771st under an emulator, support_thin.h): each
 * within 1 ulp of the exact result (they round once from double, so the
 * largest error found is ~0.5), special values exact, NaN given back. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz_math.h"
#include "support.h"
#include "support_thin.h"

/* the sweep's stride: prime, so every exponent and sign is still visited */
#define STRIDE (ROZ_TEST_THIN(2) > 1 ? 32771u : 2039u)

/* |got - want| in ulps of the float nearest want */
static double ulps(float got, long double want)
{
    int e;
    if (fabsl(want) > (long double)FLT_MAX)
        return isinf(got) && (got > 0) == (want > 0) ? 0.0 : 1e9;
    frexpl(want, &e);
    if (e < -125)
        e = -125;
    return (double)(fabsl((long double)got - want) / ldexpl(1.0L, e - 24));
}

static long double sigmoidl(long double x)
{
    return 1.0L / (1.0L + expl(-x));
}

static long double elul(long double x)
{
    return x > 0 ? x : expm1l(x);
}

static void sweep(const char *name, float (*f)(float), long double (*ref)(long double),
                  double bound)
{
    double worst = 0.0;
    float worst_x = 0.0f;
    for (uint64_t b = 0; b <= 0xFFFFFFFFull; b += STRIDE) {
        uint32_t u = (uint32_t)b;
        float x, y;
        memcpy(&x, &u, 4);
        y = f(x);
        if (isnan(x)) {
            uint32_t v;
            memcpy(&v, &y, 4);
            assert_int_equal(v, u); /* NaN comes back as given */
            continue;
        }
        double e = ulps(y, ref((long double)x));
        if (e > worst) {
            worst = e;
            worst_x = x;
        }
    }
    print_message("%-9s largest error %.3f ulp at %a\n", name, worst, (double)worst_x);
    if (worst >= bound)
        fail_msg("%s: %.3f ulp at %a, bound %.1f", name, worst, (double)worst_x, bound);
}

static void test_roz_math_f32_sweeps(void **st)
{
    (void)st;
    if (STRIDE != 2039u)
        print_message("under an emulator: 1 in %u float bit patterns\n", STRIDE);
    sweep("expf", roz_math_expf, expl, 1.0);
    sweep("expm1f", roz_math_expm1f, expm1l, 1.0);
    sweep("tanhf", roz_math_tanhf, tanhl, 1.0);
    sweep("sigmoidf", roz_math_sigmoidf, sigmoidl, 1.0);
    sweep("eluf", roz_math_eluf, elul, 1.0);
}

static void test_roz_math_f32_special(void **st)
{
    (void)st;
    assert_true(roz_math_expf(0.0f) == 1.0f && roz_math_expf(-0.0f) == 1.0f);
    assert_true(roz_math_expf(INFINITY) == INFINITY && roz_math_expf(-INFINITY) == 0.0f);
    assert_true(roz_math_expf(88.7f) < INFINITY && roz_math_expf(88.8f) == INFINITY);
    assert_true(roz_math_expf(-103.0f) > 0.0f && roz_math_expf(-104.0f) == 0.0f);
    assert_true(roz_math_tanhf(INFINITY) == 1.0f && roz_math_tanhf(-INFINITY) == -1.0f);
    assert_true(signbit(roz_math_tanhf(-0.0f)) && roz_math_tanhf(-0.0f) == 0.0f);
    assert_true(roz_math_tanhf(1e-40f) == 1e-40f);
    assert_true(roz_math_sigmoidf(0.0f) == 0.5f);
    assert_true(roz_math_sigmoidf(INFINITY) == 1.0f && roz_math_sigmoidf(-INFINITY) == 0.0f);
    assert_true(roz_math_eluf(-INFINITY) == -1.0f && roz_math_eluf(INFINITY) == INFINITY);
    assert_true(signbit(roz_math_eluf(-0.0f)) && roz_math_eluf(2.5f) == 2.5f);
    assert_true(roz_math_reluf(-1.0f) == 0.0f && !signbit(roz_math_reluf(-1.0f)));
    assert_true(roz_math_reluf(3.0f) == 3.0f && isnan(roz_math_reluf(NAN)));
}

ROZ_TEST_MAIN(cmocka_unit_test(test_roz_math_f32_sweeps),
              cmocka_unit_test(test_roz_math_f32_special))
