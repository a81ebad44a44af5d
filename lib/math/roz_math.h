/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz_math.h
 * @brief Freestanding math for controllers: C compiled to wasm32 has no
 *        libc, so no math.h. Plain C99 (C++17 too), every function static
 *        inline, no include, no library call.
 *
 * Accuracy, in ulps (units in the last place of the exact result): the
 * bound each function is held to by test/sdk/test_roz_math.c, which
 * compares it with the host's libm in long double (2^11 times finer than
 * double) over dense sweeps of every domain and the edge cases (0, -0, inf,
 * NaN, huge, tiny, subnormal, where each algorithm changes course), and the
 * largest error that test found; "exact" is bit for bit with libm. Fuel:
 * roz's work units for one call inside a controller, measured (a 100 Hz
 * robot's default budget is 100,000 units a tick).
 *
 *   function            bound   largest  fuel   domain and special values
 *   fabs, copysign      exact            1
 *   sqrt                exact            5      x < 0: NaN; sqrt(-0) = -0
 *   floor, ceil, trunc  exact            1
 *   fmin, fmax          exact            ~10    a NaN gives the other argument;
 *                                               fmin(-0, +0) = -0, fmax(-0, +0) = +0
 *   clamp(x, lo, hi)    exact            ~5     NaN stays NaN (command.set refuses it)
 *   sin, cos            < 1     0.77     90     any finite x, reduced exactly
 *                                        700    (|x| >= 2^24); inf, NaN: NaN
 *   atan2(y, x)         < 1     0.70     ~400   C99's zeros and infinities
 *   exp                 < 1     0.75     230    inf above 709.78, 0 below -745.13
 *   log                 < 1     0.50     380    log(+-0) = -inf; x < 0: NaN
 *   pow(x, y)           < 1     0.83     780    C99's special cases: pow(x, +-0) = 1,
 *                                               pow(1, y) = 1, x < 0 only with an
 *                                               integer y (else NaN), zeros, infinities
 *   tanh                < 1     0.74     290    +-1 beyond |x| = 22
 *
 * The inexact functions use double arithmetic only (an argument reduction
 * exact enough, then a Taylor polynomial, with sums and products kept as
 * pairs of doubles where the last bits matter), so one wasm module gives the
 * same bits on every host. roz_sin() and roz_cos() of roz_controller.h are
 * imports, and the host answers them with these same roz_math_sin() and
 * roz_math_cos() (lib/src/abi.c), not with its libm: the same bits too.
 *
 * On wasm32 fabs, sqrt, floor, ceil and trunc are single instructions
 * (f64.abs, f64.sqrt, f64.floor, f64.ceil, f64.trunc, exact by the
 * WebAssembly specification). Compiled natively (a test, a native build of
 * a controller) they are portable C with the same results, and the whole
 * header gives the wasm build's bits (test/sdk/test_roz_math_wasm.c checks
 * it) when built without contracting a * b + c into a fused multiply-add
 * (-ffp-contract=off; wasm32 has no such instruction).
 *
 * Every function is pure: no state, no side effect. Context: any.
 */
#ifndef ROZ_MATH_H
#define ROZ_MATH_H

#ifdef __cplusplus
extern "C" {
#endif

#define ROZ_MATH_PI     3.141592653589793   /**< pi, rounded to double */
#define ROZ_MATH_PI_2   1.5707963267948966  /**< pi/2 */
#define ROZ_MATH_PI_4   0.7853981633974483  /**< pi/4 */
#define ROZ_MATH_TWO_PI 6.283185307179586   /**< 2 pi */
#define ROZ_MATH_E      2.718281828459045   /**< e */
#define ROZ_MATH_LN2    0.6931471805599453  /**< log(2) */

/* ---- private: bits, and sums and products without rounding error ------------ */

typedef char roz__math_check_widths[sizeof(unsigned long long) == 8 && sizeof(double) == 8
                                        ? 1
                                        : -1];

typedef union roz__math_bits {
    double             d;
    unsigned long long u;
} roz__math_bits_t;

static inline unsigned long long roz__math_to_bits(double x)
{
    roz__math_bits_t b;
    b.d = x;
    return b.u;
}

static inline double roz__math_from_bits(unsigned long long u)
{
    roz__math_bits_t b;
    b.u = u;
    return b.d;
}

#define ROZ__MATH_SIGN 0x8000000000000000ULL
#define ROZ__MATH_MANT 0x000FFFFFFFFFFFFFULL
#define ROZ__MATH_INF  0x7FF0000000000000ULL
#define ROZ__MATH_NAN  0x7FF8000000000000ULL
#define ROZ__MATH_ROUNDER 0x1.8p52 /* adding and subtracting it rounds to an integer */

static inline int roz__math_isnan(double x)
{
    return (roz__math_to_bits(x) & ~ROZ__MATH_SIGN) > ROZ__MATH_INF;
}

static inline int roz__math_isinf(double x)
{
    return (roz__math_to_bits(x) & ~ROZ__MATH_SIGN) == ROZ__MATH_INF;
}

/* 2^k for -1022 <= k <= 1023 */
static inline double roz__math_pow2(int k)
{
    return roz__math_from_bits((unsigned long long)(k + 1023) << 52);
}

/* x * 2^k for any k in -2200..2200, rounded once */
static inline double roz__math_scale(double x, int k)
{
    if (k > 1023) {
        x *= 0x1p1023;
        k -= 1023;
        if (k > 1023) {
            x *= 0x1p1023;
            k -= 1023;
        }
        if (k > 1023)
            k = 1023;
    } else if (k < -1022) {
        /* two steps, the first exact, so that a subnormal result is
         * rounded only once */
        x *= 0x1p-969;
        k += 969;
        if (k < -1022) {
            x *= 0x1p-969;
            k += 969;
        }
        if (k < -1022)
            k = -1022;
    }
    return x * roz__math_pow2(k);
}

/* s + err == a + b exactly (any magnitudes) */
static inline double roz__math_two_sum(double a, double b, double *err)
{
    double s = a + b, bb = s - a;
    *err = (a - (s - bb)) + (b - bb);
    return s;
}

/* s + err == a + b exactly, when |a| >= |b| */
static inline double roz__math_fast_two_sum(double a, double b, double *err)
{
    double s = a + b;
    *err = b - (s - a);
    return s;
}

/* p + err == a * b exactly (|a|, |b| below 2^995), by splitting each
 * factor into two halves of 26 bits whose products are exact */
static inline double roz__math_two_prod(double a, double b, double *err)
{
    double p = a * b;
    double ca = 134217729.0 * a, cb = 134217729.0 * b; /* 2^27 + 1 */
    double ah = ca - (ca - a), al = a - ah;
    double bh = cb - (cb - b), bl = b - bh;
    *err = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    return p;
}

/* ---- exact operations ------------------------------------------------------- */

/** @brief |x|. Exact. */
static inline double roz_math_fabs(double x)
{
#if defined(__wasm__)
    return __builtin_fabs(x); /* f64.abs */
#else
    return roz__math_from_bits(roz__math_to_bits(x) & ~ROZ__MATH_SIGN);
#endif
}

/** @brief |x| with the sign of @p s. Exact. */
static inline double roz_math_copysign(double x, double s)
{
    return roz__math_from_bits((roz__math_to_bits(x) & ~ROZ__MATH_SIGN) |
                               (roz__math_to_bits(s) & ROZ__MATH_SIGN));
}

/* Square root digit by digit, two bits of the radicand per bit of the
 * root, with one more bit to round on (an exact half cannot happen). */
static inline double roz__math_sqrt_soft(double x)
{
    unsigned long long u = roz__math_to_bits(x), m, r = 0, rem = 0;
    int e;
    if (roz__math_isnan(x) || x == 0.0 || x == roz__math_from_bits(ROZ__MATH_INF))
        return x;
    if (x < 0.0)
        return roz__math_from_bits(ROZ__MATH_NAN);
    e = (int)(u >> 52);
    m = u & ROZ__MATH_MANT;
    if (e == 0) { /* subnormal: make it m * 2^(e - 1075) with m in [2^52, 2^53) */
        e = 1;
        while (!(m & (1ULL << 52))) {
            m <<= 1;
            e--;
        }
    } else {
        m |= 1ULL << 52;
    }
    e -= 1075;
    if (e & 1) { /* an even exponent: m in [2^52, 2^54) */
        m <<= 1;
        e--;
    }
    /* r = floor(sqrt(m * 2^54)): 54 bits, from the 27 pairs of bits of m
     * then 27 pairs of zeros */
    for (int i = 0; i < 54; i++) {
        unsigned long long t;
        rem = (rem << 2) | (i < 27 ? (m >> (52 - 2 * i)) & 3u : 0u);
        t = (r << 2) | 1u;
        r <<= 1;
        if (rem >= t) {
            rem -= t;
            r |= 1u;
        }
    }
    r = (r >> 1) + (r & 1u); /* to 53 bits, to nearest */
    return roz__math_from_bits(((unsigned long long)((e - 54) / 2 + 1076) << 52) |
                               (r & ROZ__MATH_MANT));
}

/** @brief Square root, correctly rounded; NaN for x < 0, -0 for -0. */
static inline double roz_math_sqrt(double x)
{
#if defined(__wasm__)
    return __builtin_sqrt(x); /* f64.sqrt */
#else
    return roz__math_sqrt_soft(x);
#endif
}

/** @brief x rounded toward zero. Exact. */
static inline double roz_math_trunc(double x)
{
#if defined(__wasm__)
    return __builtin_trunc(x); /* f64.trunc */
#else
    double t;
    if (!(roz_math_fabs(x) < 0x1p52)) /* already integral, or inf or NaN */
        return x;
    t = (double)(long long)x;
    return roz_math_copysign(t, x);
#endif
}

/** @brief The largest integer not above x. Exact. */
static inline double roz_math_floor(double x)
{
#if defined(__wasm__)
    return __builtin_floor(x); /* f64.floor */
#else
    double t = roz_math_trunc(x);
    return t > x ? t - 1.0 : t;
#endif
}

/** @brief The smallest integer not below x. Exact. */
static inline double roz_math_ceil(double x)
{
#if defined(__wasm__)
    return __builtin_ceil(x); /* f64.ceil */
#else
    double t = roz_math_trunc(x);
    return t < x ? t + 1.0 : t;
#endif
}

/** @brief The smaller of a and b; the other when one is NaN; -0 below +0. */
static inline double roz_math_fmin(double a, double b)
{
    if (roz__math_isnan(a))
        return b;
    if (roz__math_isnan(b))
        return a;
    if (a == b) /* +0 and -0: the one with the sign bit */
        return roz__math_to_bits(a) & ROZ__MATH_SIGN ? a : b;
    return a < b ? a : b;
}

/** @brief The larger of a and b; the other when one is NaN; +0 above -0. */
static inline double roz_math_fmax(double a, double b)
{
    if (roz__math_isnan(a))
        return b;
    if (roz__math_isnan(b))
        return a;
    if (a == b)
        return roz__math_to_bits(a) & ROZ__MATH_SIGN ? b : a;
    return a > b ? a : b;
}

/** @brief x limited to [lo, hi] (lo <= hi); NaN stays NaN. */
static inline double roz_math_clamp(double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

/* ---- sin, cos ------------------------------------------------------------------ */

/* pi/2 in four parts: three of 29 bits (k times one is exact for |k| < 2^24)
 * and the rest, 141 bits in all */
#define ROZ__MATH_PIO2_1 0x1.921fb54p+0
#define ROZ__MATH_PIO2_2 0x1.10b4611p-30
#define ROZ__MATH_PIO2_3 0x1.4c4c662p-59
#define ROZ__MATH_PIO2_4 0x1.1701b839a2520p-88
/* pi/2 as a sum of two doubles (107 bits) */
#define ROZ__MATH_PIO2_HI 0x1.921fb54442d18p+0
#define ROZ__MATH_PIO2_LO 0x1.1a62633145c07p-54

/* Bits of 2/pi after the binary point, 32 a word: enough for any double. */
static const unsigned int roz__math_two_over_pi[40] = {
    0xa2f9836eu, 0x4e441529u, 0xfc2757d1u, 0xf534ddc0u, 0xdb629599u, 0x3c439041u, 0xfe5163abu,
    0xdebbc561u, 0xb7246e3au, 0x424dd2e0u, 0x06492eeau, 0x09d1921cu, 0xfe1deb1cu, 0xb129a73eu,
    0xe88235f5u, 0x2ebb4484u, 0xe99c7026u, 0xb45f7e41u, 0x3991d639u, 0x835339f4u, 0x9c845f8bu,
    0xbdf9283bu, 0x1ff897ffu, 0xde05980fu, 0xef2f118bu, 0x5a0a6d1fu, 0x6d367ecfu, 0x27cb09b7u,
    0x4f463f66u, 0x9e5fea2du, 0x7527bac7u, 0xebe5f17bu, 0x3d0739f7u, 0x8a5292eau, 0x6bfb5fb1u,
    0x1f8d5d08u, 0x56033046u, 0xfc7b6babu, 0xf0cfbc20u, 0x9af4361du,
};

/* 64 bits of the 256-bit number w (w[0] its least significant word) from
 * bit @at up; bits above the top are 0 */
static inline unsigned long long roz__math_bits64(const unsigned long long w[4], int at)
{
    int i = at / 64, o = at % 64;
    unsigned long long v = i < 4 ? w[i] >> o : 0u;
    if (o != 0 && i + 1 < 4)
        v |= w[i + 1] << (64 - o);
    return v;
}

/* |x| = n * pi/2 + (*hi + *lo), |*hi| <= pi/4, for 2^24 <= |x| < inf:
 * |x| * 2/pi is formed in integers from x's 53-bit mantissa M and the 192
 * bits of 2/pi that matter (those before contribute multiples of 4, those
 * after less than 2^-137); returns n mod 4. */
static inline int roz__math_rem_pio2_large(double x, double *hi, double *lo)
{
    unsigned long long u = roz__math_to_bits(x);
    unsigned long long mant = (u & ROZ__MATH_MANT) | (1ULL << 52);
    int e = (int)((u >> 52) & 0x7FF) - 1075; /* |x| = mant * 2^e, e >= -28 */
    int first = e - 1 > 1 ? e - 1 : 1;       /* first bit of 2/pi that matters */
    int word = (first - 1) / 32, off = (first - 1) % 32, point, n;
    unsigned int t[6], p[8] = { 0, 0, 0, 0, 0, 0, 0, 0 };
    unsigned long long m[2], w[4], f_hi, f_lo, carry;
    double fh, fl, ph, pe, sign = 1.0;

    for (int k = 0; k < 6; k++) /* the window, most significant word first */
        t[k] = off == 0 ? roz__math_two_over_pi[word + k]
                        : (roz__math_two_over_pi[word + k] << off) |
                              (roz__math_two_over_pi[word + k + 1] >> (32 - off));
    m[0] = mant >> 32;         /* 21 bits */
    m[1] = mant & 0xFFFFFFFFu; /* 32 bits */
    /* p = mant * t in 32-bit words, p[0] the most significant */
    for (int j = 1; j >= 0; j--) {
        carry = 0;
        for (int k = 5; k >= 0; k--) {
            unsigned long long v = m[j] * t[k] + p[j + k + 1] + carry;
            p[j + k + 1] = (unsigned int)v;
            carry = v >> 32;
        }
        p[j] = (unsigned int)(p[j] + carry);
    }
    for (int k = 0; k < 4; k++)
        w[k] = ((unsigned long long)p[6 - 2 * k] << 32) | p[7 - 2 * k];
    /* |x| * 2/pi = p * 2^(e - first - 191): its binary point is 'point'
     * bits above bit 0 of p (192 for e >= 2, up to 220 for small e) */
    point = first + 191 - e;
    n = (int)(roz__math_bits64(w, point) & 3u);
    f_hi = roz__math_bits64(w, point - 64);
    f_lo = roz__math_bits64(w, point - 128);
    if (f_hi >> 63) { /* a half or more: the next quadrant, from below */
        n = (n + 1) & 3;
        f_lo = ~f_lo + 1u;
        f_hi = ~f_hi + (f_lo == 0 ? 1u : 0u);
        sign = -1.0;
    }
    /* the fraction (128 bits) as a sum of two doubles, times pi/2 */
    fh = (double)(f_hi >> 11) * 0x1p-53;
    fl = ((double)(f_hi & 0x7FFu) * 0x1p64 + (double)f_lo) * 0x1p-128;
    fh = roz__math_two_sum(fh, fl, &fl);
    ph = roz__math_two_prod(fh, ROZ__MATH_PIO2_HI, &pe);
    pe += fh * ROZ__MATH_PIO2_LO + fl * ROZ__MATH_PIO2_HI;
    ph = roz__math_fast_two_sum(ph, pe, &pe);
    *hi = sign * ph;
    *lo = sign * pe;
    return n;
}

/* x = n * pi/2 + (*hi + *lo), |*hi| <= pi/4 (a little more at most);
 * returns n mod 4. x finite. */
static inline int roz__math_rem_pio2(double x, double *hi, double *lo)
{
    double k, r, a, ea, b, eb, l;
    if (roz_math_fabs(x) <= ROZ_MATH_PI_4) {
        *hi = x;
        *lo = 0.0;
        return 0;
    }
    if (!(roz_math_fabs(x) < 0x1p24)) {
        int n = roz__math_rem_pio2_large(x, hi, lo);
        if (x < 0.0) { /* x = -n pi/2 - (hi + lo) */
            *hi = -*hi;
            *lo = -*lo;
            n = (4 - n) & 3;
        }
        return n;
    }
    k = (x * 0x1.45f306dc9c883p-1 + ROZ__MATH_ROUNDER) - ROZ__MATH_ROUNDER; /* x * 2/pi */
    r = x - k * ROZ__MATH_PIO2_1; /* both exact */
    a = roz__math_two_sum(r, -k * ROZ__MATH_PIO2_2, &ea);
    b = roz__math_two_sum(a, -k * ROZ__MATH_PIO2_3, &eb);
    l = (ea + eb) - k * ROZ__MATH_PIO2_4;
    *hi = roz__math_two_sum(b, l, lo);
    return (int)((long long)k & 3);
}

/* sin(hi + lo) for |hi| <= pi/4 + a little, |lo| tiny: Taylor to x^17
 * (the next term is below 2^-63 of the result) */
static inline double roz__math_sin_kernel(double hi, double lo)
{
    double z = hi * hi, v = z * hi;
    double s = -1.0 / 6.0 + z * (1.0 / 120.0 + z * (-1.0 / 5040.0 + z * (1.0 / 362880.0 +
               z * (-1.0 / 39916800.0 + z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0 +
               z * (1.0 / 355687428096000.0)))))));
    return hi + (v * s + lo * (1.0 - 0.5 * z));
}

/* cos(hi + lo), same conditions: 1 - z/2 exactly split, Taylor to x^18 */
static inline double roz__math_cos_kernel(double hi, double lo)
{
    double z = hi * hi, hz = 0.5 * z, w = 1.0 - hz;
    double c = 1.0 / 24.0 + z * (-1.0 / 720.0 + z * (1.0 / 40320.0 + z * (-1.0 / 3628800.0 +
               z * (1.0 / 479001600.0 + z * (-1.0 / 87178291200.0 + z * (1.0 / 20922789888000.0 +
               z * (-1.0 / 6402373705728000.0)))))));
    return w + (((1.0 - w) - hz) + (z * z * c - hi * lo));
}

/** @brief Sine of x (radians). < 1 ulp, any finite x; NaN for inf and NaN. */
static inline double roz_math_sin(double x)
{
    double hi, lo;
    if (roz__math_isnan(x) || roz__math_isinf(x))
        return x - x;
    if (roz_math_fabs(x) < 0x1p-26) /* x^3/6 is below half an ulp of x; keeps -0 */
        return x;
    switch (roz__math_rem_pio2(x, &hi, &lo)) {
    case 0:  return roz__math_sin_kernel(hi, lo);
    case 1:  return roz__math_cos_kernel(hi, lo);
    case 2:  return -roz__math_sin_kernel(hi, lo);
    default: return -roz__math_cos_kernel(hi, lo);
    }
}

/** @brief Cosine of x (radians). < 1 ulp, any finite x; NaN for inf and NaN. */
static inline double roz_math_cos(double x)
{
    double hi, lo;
    if (roz__math_isnan(x) || roz__math_isinf(x))
        return x - x;
    switch (roz__math_rem_pio2(x, &hi, &lo)) {
    case 0:  return roz__math_cos_kernel(hi, lo);
    case 1:  return -roz__math_sin_kernel(hi, lo);
    case 2:  return -roz__math_cos_kernel(hi, lo);
    default: return roz__math_sin_kernel(hi, lo);
    }
}

/* ---- atan2 ---------------------------------------------------------------------- */

/* atan(t + tl) for 0 <= t <= 1, tl tiny, as hi + *lo: above tan(pi/8) it is
 * pi/4 + atan(u) with u = (t - 1)/(t + 1) kept as two doubles; then the
 * series u + u s to u^45 (|u| <= 0.4143: the next term is below 2^-60 of the
 * result), and atan(u + ul) = atan(u) + ul/(1 + u^2). */
static inline double roz__math_atan01(double t, double tl, double *lo)
{
    double base_hi = 0.0, base_lo = 0.0, u = t, ul = tl, z, s;
    if (t > 0.41421356237309503) {
        double ea, eb, p, pe;
        double a = roz__math_two_sum(t, -1.0, &ea), b = roz__math_two_sum(t, 1.0, &eb);
        ea += tl;
        eb += tl;
        u = a / b;
        p = roz__math_two_prod(u, b, &pe);
        ul = (((a - p) - pe) + ea - u * eb) / b;
        base_hi = 0x1.921fb54442d18p-1; /* pi/4 */
        base_lo = 0x1.1a62633145c07p-55;
    }
    z = u * u; /* s = sum over n = 1..22 of (-1)^n u^2n / (2n + 1) */
    s = z * (-1.0 / 3.0 + z * (1.0 / 5.0 + z * (-1.0 / 7.0 + z * (1.0 / 9.0 + z * (
        -1.0 / 11.0 + z * (1.0 / 13.0 + z * (-1.0 / 15.0 + z * (1.0 / 17.0 + z * (
        -1.0 / 19.0 + z * (1.0 / 21.0 + z * (-1.0 / 23.0 + z * (1.0 / 25.0 + z * (
        -1.0 / 27.0 + z * (1.0 / 29.0 + z * (-1.0 / 31.0 + z * (1.0 / 33.0 + z * (
        -1.0 / 35.0 + z * (1.0 / 37.0 + z * (-1.0 / 39.0 + z * (1.0 / 41.0 + z * (
        -1.0 / 43.0 + z * (1.0 / 45.0))))))))))))))))))))));
    z = base_hi + u; /* exact when base_hi is 0; else |u| < base_hi */
    return roz__math_fast_two_sum(z, ((base_hi - z) + u) + (u * s + ul / (1.0 + u * u) + base_lo),
                                  lo);
}

/** @brief The angle of the point (x, y) from the x axis, in [-pi, pi].
 *  < 1 ulp; C99's cases for zeros and infinities; NaN for a NaN. */
static inline double roz_math_atan2(double y, double x)
{
    double ax = roz_math_fabs(x), ay = roz_math_fabs(y), th, tl, r, rl, t, te, p, pe;
    if (roz__math_isnan(x) || roz__math_isnan(y))
        return x + y;
    if (ay == 0.0) /* y = +-0: +-0 toward +x, +-pi toward -x (and x = -0) */
        return roz__math_to_bits(x) & ROZ__MATH_SIGN ? roz_math_copysign(ROZ_MATH_PI, y) : y;
    if (roz__math_isinf(ax) && roz__math_isinf(ay))
        return roz_math_copysign(x > 0.0 ? ROZ_MATH_PI_4 : 3.0 * ROZ_MATH_PI_4, y);
    if (ax == 0.0 || roz__math_isinf(ay))
        return roz_math_copysign(ROZ_MATH_PI_2, y);
    if (roz__math_isinf(ax))
        return roz_math_copysign(x > 0.0 ? 0.0 : ROZ_MATH_PI, y);
    /* the ratio of the smaller to the larger, as two doubles; both scaled
     * alike (exactly) away from overflow and underflow first */
    {
        double big = ay > ax ? ay : ax, small = ay > ax ? ax : ay;
        if (big > 0x1p900) {
            big *= 0x1p-600;
            small *= 0x1p-600;
        } else if (big < 0x1p-400) {
            big *= 0x1p600;
            small *= 0x1p600;
        }
        t = small / big;
        te = 0.0; /* the rounding of t; it matters only when the products below do not underflow */
        if (small > 0x1p-900) {
            p = roz__math_two_prod(t, big, &pe);
            te = ((small - p) - pe) / big;
        }
    }
    th = roz__math_atan01(t, te, &tl);
    if (ay > ax) { /* pi/2 - atan(x/y) */
        th = roz__math_two_sum(ROZ__MATH_PIO2_HI, -th, &r);
        tl = r + (ROZ__MATH_PIO2_LO - tl);
    }
    if (x < 0.0) { /* pi - the angle */
        th = roz__math_two_sum(2.0 * ROZ__MATH_PIO2_HI, -th, &rl);
        tl = rl + (2.0 * ROZ__MATH_PIO2_LO - tl);
    }
    return roz_math_copysign(th + tl, y);
}

/* ---- exp, log, pow, tanh ------------------------------------------------------- */

/* log(2) in three parts: 42 bits (k times it is exact for |k| < 2^11), then
 * two of 53 */
#define ROZ__MATH_LN2_1 0x1.62e42fefa38p-1
#define ROZ__MATH_LN2_2 0x1.ef35793c7673p-45
#define ROZ__MATH_LN2_3 0x1.f97b57a079a19p-103
#define ROZ__MATH_INV_LN2 0x1.71547652b82fep+0

/* exp(r) - 1 - r for |r| <= log(2)/2 + a little: Taylor to r^15 (the next
 * term is below 2^-63 of exp(r) - 1) */
static inline double roz__math_expm1_rest(double r)
{
    double q = 1.0 / 2.0 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0 + r * (1.0 / 720.0 +
               r * (1.0 / 5040.0 + r * (1.0 / 40320.0 + r * (1.0 / 362880.0 + r * (1.0 / 3628800.0 +
               r * (1.0 / 39916800.0 + r * (1.0 / 479001600.0 + r * (1.0 / 6227020800.0 +
               r * (1.0 / 87178291200.0 + r * (1.0 / 1307674368000.0)))))))))))));
    return r * r * q;
}

/* exp(hi + lo) = 2^k * (1 + p + *pl) for |hi| <= 746: returns p, with
 * |p| < 0.42 and *pl below an ulp of p. hi - k log(2) = r + c exactly
 * enough, and exp(r + c) - 1 = P(r) + c (1 + P(r)), P(r) = r + r^2 q. */
static inline double roz__math_exp_reduce(double hi, double lo, int *k, double *pl)
{
    double kd = (hi * ROZ__MATH_INV_LN2 + ROZ__MATH_ROUNDER) - ROZ__MATH_ROUNDER;
    double r_hi = hi - kd * ROZ__MATH_LN2_1; /* both exact */
    double r_lo = lo - kd * ROZ__MATH_LN2_2;
    double c, r = roz__math_two_sum(r_hi, r_lo, &c), q, p, e;
    q = roz__math_expm1_rest(r);
    p = roz__math_fast_two_sum(r, q, &e);
    *k = (int)kd;
    *pl = e + (c + c * p);
    return p;
}

/** @brief e^x. < 1 ulp; inf above 709.78, +0 below -745.13. */
static inline double roz_math_exp(double x)
{
    int k;
    double p, pl, e;
    if (roz__math_isnan(x))
        return x;
    if (x > 710.0)
        return roz__math_from_bits(ROZ__MATH_INF);
    if (x < -746.0)
        return 0.0;
    p = roz__math_exp_reduce(x, 0.0, &k, &pl);
    p = roz__math_fast_two_sum(1.0, p, &e);
    return roz__math_scale(p + (e + pl), k);
}

/* log(x) = *hi + *lo (relative error below 2^-62) for finite x > 0:
 * x = 2^e * m, m in [sqrt(2)/2, sqrt(2)], f = m - 1 (exact), s = f/(2 + f)
 * kept as two doubles, log(m) = 2 atanh(s) = 2s + s * R(s^2) */
static inline double roz__math_log_dd(double x, double *lo)
{
    unsigned long long u;
    int e = 0;
    double m, f, d, dl, s, sl, p, pe, z, zl, c3, c3l, rr, t, tl, l_hi, l_lo, a_hi, a_lo, b_hi,
        b_lo, h, l;
    if (x < 0x1p-1022) { /* subnormal */
        x *= 0x1p54;
        e = -54;
    }
    u = roz__math_to_bits(x);
    e += (int)(u >> 52) - 1023;
    m = roz__math_from_bits((u & ROZ__MATH_MANT) | 0x3FF0000000000000ULL);
    if (m > 1.4142135623730951) {
        m *= 0.5;
        e++;
    }
    f = m - 1.0;
    d = roz__math_fast_two_sum(2.0, f, &dl);
    s = f / d;
    p = roz__math_two_prod(s, d, &pe);
    sl = (((f - p) - pe) - s * dl) / d;
    /* 2s + (2/3) s^3 in two doubles each, the rest (below 2^-12 of the
     * result) in one: s^5 (2/5 + 2z/7 + ... + 2z^10/25) */
    z = roz__math_two_prod(s, s, &zl);
    zl += 2.0 * s * sl;
    c3 = roz__math_two_prod(s, z, &c3l);
    c3l += s * zl + sl * z;
    t = roz__math_two_prod(0x1.5555555555555p-1, c3, &tl); /* 2/3 = hi + lo */
    tl += 0x1.5555555555555p-55 * c3 + 0x1.5555555555555p-1 * c3l;
    rr = 2.0 / 5.0 + z * (2.0 / 7.0 + z * (2.0 / 9.0 + z * (2.0 / 11.0 + z * (2.0 / 13.0 +
         z * (2.0 / 15.0 + z * (2.0 / 17.0 + z * (2.0 / 19.0 + z * (2.0 / 21.0 +
         z * (2.0 / 23.0 + z * (2.0 / 25.0))))))))));
    l_hi = roz__math_fast_two_sum(2.0 * s, t, &l_lo);
    l_lo += 2.0 * sl + (tl + c3 * z * rr);
    /* + e * log(2), in parts */
    a_hi = (double)e * ROZ__MATH_LN2_1; /* exact */
    b_hi = roz__math_two_prod((double)e, ROZ__MATH_LN2_2, &b_lo);
    h = roz__math_two_sum(a_hi, l_hi, &a_lo);
    l = a_lo + (l_lo + (b_hi + (b_lo + (double)e * ROZ__MATH_LN2_3)));
    h = roz__math_fast_two_sum(h, l, lo);
    return h;
}

/** @brief Natural logarithm. < 1 ulp; log(+-0) = -inf, x < 0: NaN, log(inf) = inf. */
static inline double roz_math_log(double x)
{
    double lo, hi;
    if (roz__math_isnan(x) || x == roz__math_from_bits(ROZ__MATH_INF))
        return x;
    if (x == 0.0)
        return -roz__math_from_bits(ROZ__MATH_INF);
    if (x < 0.0)
        return roz__math_from_bits(ROZ__MATH_NAN);
    hi = roz__math_log_dd(x, &lo);
    return hi + lo;
}

/* -1 when y is an odd integer, 1 when an even one, 0 when not an integer */
static inline int roz__math_parity(double y)
{
    if (roz_math_floor(y) != y)
        return 0;
    if (roz_math_fabs(y) >= 0x1p53)
        return 1;
    return roz_math_floor(0.5 * y) != 0.5 * y ? -1 : 1;
}

/** @brief x raised to the power y. < 1 ulp; C99's special cases: pow(x, +-0)
 *  = 1 and pow(1, y) = 1 (even for NaN), a negative x needs an integer y
 *  (else NaN), zeros and infinities as C99 Annex F says. */
static inline double roz_math_pow(double x, double y)
{
    const double inf = roz__math_from_bits(ROZ__MATH_INF);
    double ax = roz_math_fabs(x), lh, ll, ph, pl, p, r;
    int parity, k, neg;
    if (y == 0.0 || x == 1.0)
        return 1.0;
    if (roz__math_isnan(x) || roz__math_isnan(y))
        return x + y;
    parity = roz__math_isinf(y) ? 1 : roz__math_parity(y);
    if (roz__math_isinf(y)) {
        if (ax == 1.0)
            return 1.0;
        return (ax < 1.0) == (y < 0.0) ? inf : 0.0;
    }
    if (roz__math_isinf(x)) {
        r = y < 0.0 ? 0.0 : inf;
        return x < 0.0 && parity < 0 ? -r : r;
    }
    if (ax == 0.0) {
        r = y < 0.0 ? inf : 0.0;
        return parity < 0 ? roz_math_copysign(r, x) : r;
    }
    if (x < 0.0 && parity == 0)
        return roz__math_from_bits(ROZ__MATH_NAN);
    neg = x < 0.0 && parity < 0;
    if (ax == 1.0) /* x = -1 and an integer y */
        r = 1.0;
    else if (roz_math_fabs(y) > 0x1p64) /* then |y log x| > 2^11 */
        r = (ax < 1.0) == (y < 0.0) ? inf : 0.0;
    else {
        lh = roz__math_log_dd(ax, &ll);
        ph = roz__math_two_prod(y, lh, &pl);
        pl += y * ll;
        ph = roz__math_fast_two_sum(ph, pl, &pl);
        if (ph > 710.0)
            r = inf;
        else if (ph < -746.0)
            r = 0.0;
        else {
            p = roz__math_exp_reduce(ph, pl, &k, &pl);
            p = roz__math_fast_two_sum(1.0, p, &ph);
            r = roz__math_scale(p + (ph + pl), k);
        }
    }
    return neg ? -r : r;
}

/** @brief Hyperbolic tangent. < 1 ulp; +-1 beyond |x| = 22. */
static inline double roz_math_tanh(double x)
{
    double ax = roz_math_fabs(x), p, pl, eh, el, dh, dl, q, qh, qe;
    int k;
    if (roz__math_isnan(x))
        return x;
    if (ax > 22.0)
        return roz_math_copysign(1.0, x);
    if (ax < 0x1p-28) /* x^3/3 is below half an ulp of x */
        return x;
    /* tanh = e / (e + 2) with e = exp(2|x|) - 1 = 2^k (1 + p) - 1, kept
     * as two doubles, and the quotient corrected by its remainder */
    p = roz__math_exp_reduce(2.0 * ax, 0.0, &k, &pl);
    eh = roz__math_two_sum(1.0 - roz__math_pow2(-k), p, &el); /* exact for k <= 53 */
    el += pl;
    eh *= roz__math_pow2(k);
    el *= roz__math_pow2(k);
    eh = roz__math_fast_two_sum(eh, el, &el);
    dh = roz__math_two_sum(eh, 2.0, &dl);
    dl += el;
    q = eh / dh;
    qh = roz__math_two_prod(q, dh, &qe);
    q += (((eh - qh) - qe) + el - q * dl) / dh;
    return roz_math_copysign(q, x);
}

/* ---- float32, for neural-network activations ------------------------------------ */

/* The activations of roz_nn.h (and of the host's nn.act import, which uses
 * these very functions): float in, float out, computed in double and
 * rounded once to float, so that each result is the correctly rounded one
 * but for rare ties within 2^-40 of a float's half ulp (< 1 ulp in all;
 * test/sdk/test_roz_math_f32.c sweeps every finite float against libm).
 * Double arithmetic only, no FMA: the same bits on every target. NaN comes
 * back as given, bit for bit.
 *
 *   function        bound   special values
 *   expf            < 1     inf above 88.73, +0 below -103.98
 *   expm1f          < 1     -1 below -17.33
 *   tanhf           < 1     +-1 beyond |x| = 9.01; tanhf(-0) = -0
 *   sigmoidf        < 1     1 / (1 + e^-x): 0 below -103.98, 1 above 16.64
 *   eluf            < 1     x for x > 0, else expm1f(x) (alpha 1); eluf(-0) = -0
 *   reluf           exact   x < 0: +0; NaN and -0 stay */

/* e^x = 2^k (1 + p) for |x| <= 110 in double: r = x - k log 2 (|r| <=
 * 0.347), p = e^r - 1 by Taylor to r^12 (the rest below 2^-50 of p) */
static inline double roz__math_expm1_f32(double x, int *k)
{
    double kd = (x * ROZ__MATH_INV_LN2 + ROZ__MATH_ROUNDER) - ROZ__MATH_ROUNDER;
    double r = (x - kd * ROZ__MATH_LN2_1) - kd * ROZ__MATH_LN2_2;
    double q = 1.0 / 2.0 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0 +
               r * (1.0 / 720.0 + r * (1.0 / 5040.0 + r * (1.0 / 40320.0 +
               r * (1.0 / 362880.0 + r * (1.0 / 3628800.0 + r * (1.0 / 39916800.0 +
               r * (1.0 / 479001600.0))))))))));
    *k = (int)kd;
    return r + r * r * q;
}

/* e^x - 1 in double for -110 <= x <= 110, relative error about 2^-52 */
static inline double roz__math_expm1_d32(double x)
{
    int k;
    double p = roz__math_expm1_f32(x, &k);
    if (k == 0)
        return p;
    return (roz__math_pow2(k) - 1.0) + roz__math_pow2(k) * p;
}

/** @brief e^x in float. < 1 ulp. */
static inline float roz_math_expf(float x)
{
    int k;
    double p;
    if (x != x)
        return x;
    if (x > 89.0f)
        return (float)roz__math_from_bits(ROZ__MATH_INF);
    if (x < -104.0f)
        return 0.0f;
    p = roz__math_expm1_f32((double)x, &k);
    return (float)((1.0 + p) * roz__math_pow2(k));
}

/** @brief e^x - 1 in float. < 1 ulp. */
static inline float roz_math_expm1f(float x)
{
    if (x != x || x == 0.0f)
        return x;
    if (x > 89.0f)
        return (float)roz__math_from_bits(ROZ__MATH_INF);
    if (x < -104.0f)
        return -1.0f;
    return (float)roz__math_expm1_d32((double)x);
}

/** @brief Hyperbolic tangent in float. < 1 ulp. */
static inline float roz_math_tanhf(float x)
{
    double ax = roz_math_fabs((double)x), e;
    if (x != x)
        return x;
    if (ax > 9.5)
        return x < 0.0f ? -1.0f : 1.0f;
    e = roz__math_expm1_d32(2.0 * ax); /* tanh |x| = e / (e + 2) */
    return (float)roz_math_copysign(e / (e + 2.0), (double)x);
}

/** @brief The logistic function 1 / (1 + e^-x) in float. < 1 ulp. */
static inline float roz_math_sigmoidf(float x)
{
    int k;
    double p;
    if (x != x)
        return x;
    if (x < -104.0f)
        return 0.0f;
    if (x > 104.0f)
        return 1.0f;
    p = roz__math_expm1_f32(-(double)x, &k);
    return (float)(1.0 / (1.0 + (1.0 + p) * roz__math_pow2(k)));
}

/** @brief ELU with alpha 1: x for x > 0, else e^x - 1. < 1 ulp. */
static inline float roz_math_eluf(float x)
{
    return x > 0.0f ? x : roz_math_expm1f(x);
}

/** @brief ReLU: +0 for x < 0, else x (NaN and -0 as given). Exact. */
static inline float roz_math_reluf(float x)
{
    return x < 0.0f ? 0.0f : x;
}

/* ---- the nn imports' rule for tiny numbers ------------------------------------- */

/* The nn imports (roz/abi.h) and roz_nn.h's native loops read every float32
 * of magnitude below 2^-51 (the subnormals among them) as zero of its sign,
 * and nn.act's exp and sigmoid give +0 wherever their result would be
 * subnormal (x below ROZ_MATH_NN_EXP_MIN). So no float operation of theirs
 * ever takes or makes a subnormal number (the slow path of many CPUs): a
 * product of two numbers of 2^-51 or more is 2^-102 or more, a multiple of
 * 2^-126 as every sum of such numbers is, and a nonzero multiple of 2^-126
 * is a normal float. The rest is plain float arithmetic, the same bits on
 * every target (test/nn/test_nn_abi.c, test_nn_tiny_numbers). */
#define ROZ_MATH_NN_TINY_BITS 0x26000000u       /**< 2^-51, as float32 bits */
#define ROZ_MATH_NN_EXP_MIN   (-0x1.5d589ep+6f) /**< exp, sigmoid: below, +0 */

typedef union roz__math_bits_f32 {
    float        f;
    unsigned int u;
} roz__math_bits_f32_t;

typedef char roz__math_check_f32[sizeof(unsigned int) == 4 && sizeof(float) == 4 ? 1 : -1];

/** @brief x as the nn imports read it: zero of its sign below 2^-51. */
static inline float roz_math_nn_inputf(float x)
{
    roz__math_bits_f32_t b;
    b.f = x;
    if ((b.u & 0x7FFFFFFFu) < ROZ_MATH_NN_TINY_BITS)
        b.u &= 0x80000000u;
    return b.f;
}

/** @brief One element of nn.act: kind 0 relu, 1 tanh, 2 sigmoid, 3 elu,
 *  4 exp (roz/abi.h's roz_abi_nn_act_t), on roz_math_nn_inputf(x). */
static inline float roz_math_nn_actf(int kind, float x)
{
    x = roz_math_nn_inputf(x);
    switch (kind) {
    case 0:
        return roz_math_reluf(x);
    case 1:
        return roz_math_tanhf(x);
    case 2:
        return x < ROZ_MATH_NN_EXP_MIN ? 0.0f : roz_math_sigmoidf(x);
    case 3:
        return roz_math_eluf(x);
    default:
        return x < ROZ_MATH_NN_EXP_MIN ? 0.0f : roz_math_expf(x);
    }
}

#ifdef __cplusplus
}
#endif

#endif /* ROZ_MATH_H */
