/* SPDX-License-Identifier: Apache-2.0 */
/* The inputs of the math probe (math_probe.c, a controller built for wasm32)
 * for each tick, shared with the test that checks its results
 * (test_roz_math_wasm.c), which recomputes them natively. Freestanding. */
#ifndef ROZ_TEST_MATH_PROBE_H
#define ROZ_TEST_MATH_PROBE_H

#include "roz_math.h"

/* The functions probed, in the order the probe emits their results, one
 * metric each per tick. */
enum {
    PROBE_FABS, PROBE_SQRT, PROBE_FLOOR, PROBE_CEIL, PROBE_TRUNC, PROBE_FMIN, PROBE_FMAX,
    PROBE_CLAMP, PROBE_SIN, PROBE_COS, PROBE_ATAN2, PROBE_EXP, PROBE_LOG, PROBE_POW,
    PROBE_TANH, PROBE_COUNT
};

static const double probe_specials[] = {
    0.0, -0.0, 1.0, -1.0, 0.5, -2.5, 3.0, 1e300, -1e300, 1.7976931348623157e308,
    2.2250738585072014e-308, 5e-324, -1e-310, 1e-300, 1.0 / 0.0, -1.0 / 0.0, 0.0 / 0.0,
    1.5707963267948966, 3.141592653589793, 709.78, -745.1, 0.41421356237309503,
};
#define PROBE_N_SPECIALS (sizeof probe_specials / sizeof probe_specials[0])

/* A double for tick @t and slot @k: the specials first, then values of
 * every magnitude and sign from a fixed sequence of bits. */
static inline double probe_input(long long t, int k)
{
    unsigned long long u = (unsigned long long)t * 0x9E3779B97F4A7C15ULL + (unsigned long long)k;
    if (t < (long long)PROBE_N_SPECIALS)
        return probe_specials[(t + k) % (long long)PROBE_N_SPECIALS];
    u ^= u >> 31;
    u *= 0xBF58476D1CE4E5B9ULL;
    u ^= u >> 29;
    switch (t % 4) {
    case 0: /* any double, every exponent */
        return roz__math_from_bits(u & 0xFFEFFFFFFFFFFFFFULL);
    case 1: /* -10 .. 10 */
        return ((double)(u >> 11) * 0x1p-53 - 0.5) * 20.0;
    case 2: /* -750 .. 750 */
        return ((double)(u >> 11) * 0x1p-53 - 0.5) * 1500.0;
    default: /* 0 .. 2 */
        return (double)(u >> 11) * 0x1p-52;
    }
}

/* The probe's results for tick @t, in the order above. */
static inline void probe_results(long long t, double out[PROBE_COUNT])
{
    double x = probe_input(t, 0), y = probe_input(t, 1);
    out[PROBE_FABS] = roz_math_fabs(x);
    out[PROBE_SQRT] = roz_math_sqrt(x);
    out[PROBE_FLOOR] = roz_math_floor(x);
    out[PROBE_CEIL] = roz_math_ceil(x);
    out[PROBE_TRUNC] = roz_math_trunc(x);
    out[PROBE_FMIN] = roz_math_fmin(x, y);
    out[PROBE_FMAX] = roz_math_fmax(x, y);
    out[PROBE_CLAMP] = roz_math_clamp(x, -1.0, 2.0);
    out[PROBE_SIN] = roz_math_sin(x);
    out[PROBE_COS] = roz_math_cos(x);
    out[PROBE_ATAN2] = roz_math_atan2(y, x);
    out[PROBE_EXP] = roz_math_exp(x);
    out[PROBE_LOG] = roz_math_log(x);
    out[PROBE_POW] = roz_math_pow(t % 2 ? roz_math_fabs(x) : x, t % 4 == 2 ? y / 64.0 : y);
    out[PROBE_TANH] = roz_math_tanh(x);
}

#endif /* ROZ_TEST_MATH_PROBE_H */
