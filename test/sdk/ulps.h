/* SPDX-License-Identifier: Apache-2.0 */
/* How far a double result is from the exact value, for the SDK math tests
 * (test_roz_math.c natively, test_roz_math_wasm.c through the runtime,
 * test_rust_controller.c): its bits, and its error in ulps. Needs
 * <float.h>, <math.h>, <stdint.h> and <string.h>. */
#ifndef ROZ_TEST_SDK_ULPS_H
#define ROZ_TEST_SDK_ULPS_H

static inline uint64_t bits_of(double d)
{
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    return u;
}

/* Error of @got in ulps of the exact value, taken to be @want (long double).
 * Same infinities and NaN: 0; a mismatch of those: 1e9. */
static inline double ulps(double got, long double want)
{
    int e;
    long double ulp;
    if (isnan(want) || isnan(got))
        return isnan(want) && isnan(got) ? 0.0 : 1e9;
    if (fabsl(want) > (long double)DBL_MAX) { /* beyond double: must round to inf... */
        if (isinf(got) && (got > 0) == (want > 0))
            return 0.0;
        /* ...unless it is within half an ulp of DBL_MAX */
        want = want > 0 ? (long double)DBL_MAX : -(long double)DBL_MAX;
    }
    if (isinf(got))
        return 1e9;
    frexpl(want, &e); /* want = m 2^e, m in [0.5, 1) */
    if (e < -1021)
        e = -1021; /* subnormal: the ulp is 2^-1074 */
    ulp = ldexpl(1.0L, e - 53);
    return (double)(fabsl((long double)got - want) / ulp);
}

#endif /* ROZ_TEST_SDK_ULPS_H */
