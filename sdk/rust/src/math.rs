// SPDX-License-Identifier: Apache-2.0
//! Freestanding math for controllers: the functions of the C SDK's
//! `roz_math.h`, the same algorithms in the same order of operations, so a
//! Rust controller gets the C controller's bits (test/sdk/math_probe.rs
//! against test/sdk/math_probe.c, test_rust_controller). The accuracy of
//! each function, its domain and special values are those of `roz_math.h`,
//! whose table is the reference.
//!
//! Rust does not contract `a * b + c` into a fused multiply-add, and Rust
//! 1.63 has no hexadecimal float literals: the constants below are written
//! in decimal, each the shortest form that reads back as the C header's
//! constant, which its comment names. Rust 1.63's `core` has no square root
//! or rounding instruction that a stable crate may call (`f64::sqrt` and
//! `f64::floor` are `std`), so `sqrt`, `floor`, `ceil` and `trunc` are
//! portable code on every target: exact, hence the bits of `f64.sqrt` and
//! friends (test/sdk/rust_math_native.rs checks them against the host's),
//! at a higher fuel cost (docs/rust.md).
//!
//! Every function is pure: no state, no side effect.

/// pi, rounded to double
pub const PI: f64 = 3.141592653589793;
/// pi/2
pub const PI_2: f64 = 1.5707963267948966;
/// pi/4
pub const PI_4: f64 = 0.7853981633974483;
/// 2 pi
pub const TWO_PI: f64 = 6.283185307179586;
/// e
pub const E: f64 = 2.718281828459045;
/// log(2)
pub const LN2: f64 = 0.6931471805599453;

// ---- private: bits, and sums and products without rounding error ------------

const SIGN: u64 = 0x8000_0000_0000_0000;
const MANT: u64 = 0x000F_FFFF_FFFF_FFFF;
const INF: u64 = 0x7FF0_0000_0000_0000;
const NAN: u64 = 0x7FF8_0000_0000_0000;
const ROUNDER: f64 = 6755399441055744.0; // 0x1.8p52: adding and subtracting it rounds to an integer

#[inline(always)]
fn to_bits(x: f64) -> u64 {
    x.to_bits()
}

#[inline(always)]
fn from_bits(u: u64) -> f64 {
    f64::from_bits(u)
}

#[inline(always)]
fn is_nan(x: f64) -> bool {
    (to_bits(x) & !SIGN) > INF
}

#[inline(always)]
fn is_inf(x: f64) -> bool {
    (to_bits(x) & !SIGN) == INF
}

// 2^k for -1022 <= k <= 1023
#[inline(always)]
fn pow2(k: i32) -> f64 {
    from_bits(((k + 1023) as u64) << 52)
}

// x * 2^k for any k in -2200..2200, rounded once
#[inline]
fn scale(mut x: f64, mut k: i32) -> f64 {
    if k > 1023 {
        x *= 8.98846567431158e+307; // 0x1p1023
        k -= 1023;
        if k > 1023 {
            x *= 8.98846567431158e+307;
            k -= 1023;
        }
        if k > 1023 {
            k = 1023;
        }
    } else if k < -1022 {
        // two steps, the first exact, so that a subnormal result is rounded only once
        x *= 2.004168360008973e-292; // 0x1p-969
        k += 969;
        if k < -1022 {
            x *= 2.004168360008973e-292;
            k += 969;
        }
        if k < -1022 {
            k = -1022;
        }
    }
    x * pow2(k)
}

// (s, err): s + err == a + b exactly (any magnitudes)
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

// (s, err): s + err == a + b exactly, when |a| >= |b|
#[inline(always)]
fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

// (p, err): p + err == a * b exactly (|a|, |b| below 2^995)
#[inline(always)]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let ca = 134217729.0 * a; // 2^27 + 1
    let cb = 134217729.0 * b;
    let ah = ca - (ca - a);
    let al = a - ah;
    let bh = cb - (cb - b);
    let bl = b - bh;
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

// ---- exact operations -------------------------------------------------------

/// |x|. Exact.
#[inline]
pub fn fabs(x: f64) -> f64 {
    from_bits(to_bits(x) & !SIGN)
}

/// |x| with the sign of `s`. Exact.
#[inline]
pub fn copysign(x: f64, s: f64) -> f64 {
    from_bits((to_bits(x) & !SIGN) | (to_bits(s) & SIGN))
}

/// Square root, correctly rounded; NaN for x < 0, -0 for -0.
///
/// roz_math.h's portable square root finds r = floor(sqrt(m * 2^54)) for
/// the mantissa m digit by digit, 54 steps (about 3,500 units of fuel in
/// wasm3); here the same r comes from a double estimate corrected in exact
/// 128-bit integers (a few hundred units), then both round it alike: the
/// same bits, which are f64.sqrt's.
pub fn sqrt(x: f64) -> f64 {
    let u = to_bits(x);
    if is_nan(x) || x == 0.0 || x == from_bits(INF) {
        return x;
    }
    if x < 0.0 {
        return from_bits(NAN);
    }
    let mut e = (u >> 52) as i32;
    let mut m = u & MANT;
    if e == 0 {
        // subnormal: make it m * 2^(e - 1075) with m in [2^52, 2^53)
        e = 1;
        while m & (1u64 << 52) == 0 {
            m <<= 1;
            e -= 1;
        }
    } else {
        m |= 1u64 << 52;
    }
    e -= 1075;
    if e & 1 != 0 {
        // an even exponent: m in [2^52, 2^54)
        m <<= 1;
        e -= 1;
    }
    // r = floor(sqrt(n)), n = m * 2^54 in [2^106, 2^108): 54 bits. The
    // estimate: 1/sqrt(m) from the exponent halved, four Newton steps
    // (relative error below 2^-50), times m, a Newton step on the root, and
    // 2^27: off by a few units, which the loops take back exactly, keeping
    // d = n - r^2.
    let y = m as f64; // exact: m has at most 53 significant bits
    let mut g = from_bits(0x5FE6_EB50_C7B5_37A9 - (to_bits(y) >> 1));
    let mut k = 0;
    while k < 4 {
        g = g * (1.5 - 0.5 * y * g * g);
        k += 1;
    }
    let s = y * g; // sqrt(m), and one Newton step on it with g = 1/s
    let s = s + (y - s * s) * (0.5 * g);
    let mut r = (s * 134217728.0) as u64; // 2^27
    let mut d = ((m as u128) << 54) as i128 - (r as u128 * r as u128) as i128;
    while d < 0 {
        // (r - 1)^2 = r^2 - 2r + 1
        d += 2 * r as i128 - 1;
        r -= 1;
    }
    while d >= 2 * r as i128 + 1 {
        // (r + 1)^2 = r^2 + 2r + 1 is still at most n
        d -= 2 * r as i128 + 1;
        r += 1;
    }
    r = (r >> 1) + (r & 1); // to 53 bits, to nearest
    from_bits((((e - 54) / 2 + 1076) as u64) << 52 | (r & MANT))
}

/// x rounded toward zero. Exact.
#[inline]
pub fn trunc(x: f64) -> f64 {
    let a = fabs(x);
    if !(a < 4503599627370496.0) {
        // 0x1p52: already integral, or inf or NaN
        return x;
    }
    // |x| + 2^52 is in [2^52, 2^53), where doubles are the integers: the
    // sum rounds |x| to the nearest one, exactly; one less if that is above
    let mut t = (a + 4503599627370496.0) - 4503599627370496.0;
    if t > a {
        t -= 1.0;
    }
    copysign(t, x)
}

/// The largest integer not above x. Exact.
#[inline]
pub fn floor(x: f64) -> f64 {
    let t = trunc(x);
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// The smallest integer not below x. Exact.
#[inline]
pub fn ceil(x: f64) -> f64 {
    let t = trunc(x);
    if t < x {
        t + 1.0
    } else {
        t
    }
}

/// The smaller of a and b; the other when one is NaN; -0 below +0.
#[inline]
pub fn fmin(a: f64, b: f64) -> f64 {
    if is_nan(a) {
        return b;
    }
    if is_nan(b) {
        return a;
    }
    if a == b {
        return if to_bits(a) & SIGN != 0 { a } else { b };
    }
    if a < b {
        a
    } else {
        b
    }
}

/// The larger of a and b; the other when one is NaN; +0 above -0.
#[inline]
pub fn fmax(a: f64, b: f64) -> f64 {
    if is_nan(a) {
        return b;
    }
    if is_nan(b) {
        return a;
    }
    if a == b {
        return if to_bits(a) & SIGN != 0 { b } else { a };
    }
    if a > b {
        a
    } else {
        b
    }
}

/// x limited to [lo, hi] (lo <= hi); NaN stays NaN.
#[inline]
pub fn clamp(x: f64, lo: f64, hi: f64) -> f64 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}

// ---- sin, cos ----------------------------------------------------------------

// pi/2 in four parts: three of 29 bits (k times one is exact for |k| < 2^24)
// and the rest, 141 bits in all
const PIO2_1: f64 = 1.570796325802803; // 0x1.921fb54p+0
const PIO2_2: f64 = 9.920935774287987e-10; // 0x1.10b4611p-30
const PIO2_3: f64 = 2.2517417706346578e-18; // 0x1.4c4c662p-59
const PIO2_4: f64 = 3.5215598651832e-27; // 0x1.1701b839a2520p-88
// pi/2 as a sum of two doubles (107 bits)
const PIO2_HI: f64 = 1.5707963267948966; // 0x1.921fb54442d18p+0
const PIO2_LO: f64 = 6.123233995736766e-17; // 0x1.1a62633145c07p-54

// Bits of 2/pi after the binary point, 32 a word: enough for any double.
static TWO_OVER_PI: [u32; 40] = [
    0xa2f9836e, 0x4e441529, 0xfc2757d1, 0xf534ddc0, 0xdb629599, 0x3c439041, 0xfe5163ab,
    0xdebbc561, 0xb7246e3a, 0x424dd2e0, 0x06492eea, 0x09d1921c, 0xfe1deb1c, 0xb129a73e,
    0xe88235f5, 0x2ebb4484, 0xe99c7026, 0xb45f7e41, 0x3991d639, 0x835339f4, 0x9c845f8b,
    0xbdf9283b, 0x1ff897ff, 0xde05980f, 0xef2f118b, 0x5a0a6d1f, 0x6d367ecf, 0x27cb09b7,
    0x4f463f66, 0x9e5fea2d, 0x7527bac7, 0xebe5f17b, 0x3d0739f7, 0x8a5292ea, 0x6bfb5fb1,
    0x1f8d5d08, 0x56033046, 0xfc7b6bab, 0xf0cfbc20, 0x9af4361d,
];

// 64 bits of the 256-bit number w (w[0] its least significant word) from
// bit `at` up; bits above the top are 0
#[inline]
fn bits64(w: &[u64; 4], at: i32) -> u64 {
    let i = (at / 64) as usize;
    let o = (at % 64) as u32;
    let mut v = if i < 4 { w[i] >> o } else { 0 };
    if o != 0 && i + 1 < 4 {
        v |= w[i + 1] << (64 - o);
    }
    v
}

// |x| = n * pi/2 + (hi + lo), |hi| <= pi/4, for 2^24 <= |x| < inf:
// (n mod 4, hi, lo), as roz__math_rem_pio2_large() of roz_math.h
fn rem_pio2_large(x: f64) -> (i32, f64, f64) {
    let u = to_bits(x);
    let mant = (u & MANT) | (1u64 << 52);
    let e = ((u >> 52) & 0x7FF) as i32 - 1075; // |x| = mant * 2^e, e >= -28
    let first = if e - 1 > 1 { e - 1 } else { 1 }; // first bit of 2/pi that matters
    let word = ((first - 1) / 32) as usize;
    let off = ((first - 1) % 32) as u32;
    let mut t = [0u32; 6];
    let mut p = [0u32; 8];
    let mut w = [0u64; 4];
    let mut sign = 1.0;

    let mut k = 0;
    while k < 6 {
        // the window, most significant word first
        t[k] = if off == 0 {
            TWO_OVER_PI[word + k]
        } else {
            (TWO_OVER_PI[word + k] << off) | (TWO_OVER_PI[word + k + 1] >> (32 - off))
        };
        k += 1;
    }
    let m = [mant >> 32, mant & 0xFFFF_FFFF]; // 21 bits, 32 bits
    // p = mant * t in 32-bit words, p[0] the most significant
    let mut j = 2;
    while j > 0 {
        j -= 1;
        let mut carry: u64 = 0;
        let mut k = 6;
        while k > 0 {
            k -= 1;
            let v = m[j] * t[k] as u64 + p[j + k + 1] as u64 + carry;
            p[j + k + 1] = v as u32;
            carry = v >> 32;
        }
        p[j] = (p[j] as u64 + carry) as u32;
    }
    let mut k = 0;
    while k < 4 {
        w[k] = ((p[6 - 2 * k] as u64) << 32) | p[7 - 2 * k] as u64;
        k += 1;
    }
    // |x| * 2/pi = p * 2^(e - first - 191): its binary point is `point`
    // bits above bit 0 of p
    let point = first + 191 - e;
    let mut n = (bits64(&w, point) & 3) as i32;
    let mut f_hi = bits64(&w, point - 64);
    let mut f_lo = bits64(&w, point - 128);
    if f_hi >> 63 != 0 {
        // a half or more: the next quadrant, from below
        n = (n + 1) & 3;
        f_lo = (!f_lo).wrapping_add(1);
        f_hi = (!f_hi).wrapping_add(if f_lo == 0 { 1 } else { 0 });
        sign = -1.0;
    }
    // the fraction (128 bits) as a sum of two doubles, times pi/2
    let fh = (f_hi >> 11) as f64 * 1.1102230246251565e-16; // 0x1p-53
    let fl = ((f_hi & 0x7FF) as f64 * 1.8446744073709552e+19 + f_lo as f64)
        * 2.938735877055719e-39; // 0x1p64, 0x1p-128
    let (fh, fl) = two_sum(fh, fl);
    let (ph, pe) = two_prod(fh, PIO2_HI);
    let pe = pe + (fh * PIO2_LO + fl * PIO2_HI);
    let (ph, pe) = fast_two_sum(ph, pe);
    (n, sign * ph, sign * pe)
}

// x = n * pi/2 + (hi + lo), |hi| <= pi/4 (a little more at most):
// (n mod 4, hi, lo). x finite.
#[inline]
fn rem_pio2(x: f64) -> (i32, f64, f64) {
    if fabs(x) <= PI_4 {
        return (0, x, 0.0);
    }
    if !(fabs(x) < 16777216.0) {
        // 0x1p24
        let (mut n, mut hi, mut lo) = rem_pio2_large(x);
        if x < 0.0 {
            // x = -n pi/2 - (hi + lo)
            hi = -hi;
            lo = -lo;
            n = (4 - n) & 3;
        }
        return (n, hi, lo);
    }
    let k = (x * 0.6366197723675814 + ROUNDER) - ROUNDER; // x * 2/pi, 0x1.45f306dc9c883p-1
    let r = x - k * PIO2_1; // both exact
    let (a, ea) = two_sum(r, -k * PIO2_2);
    let (b, eb) = two_sum(a, -k * PIO2_3);
    let l = (ea + eb) - k * PIO2_4;
    let (hi, lo) = two_sum(b, l);
    ((k as i64 & 3) as i32, hi, lo)
}

// sin(hi + lo) for |hi| <= pi/4 + a little, |lo| tiny: Taylor to x^17
#[inline]
fn sin_kernel(hi: f64, lo: f64) -> f64 {
    let z = hi * hi;
    let v = z * hi;
    let s = -1.0 / 6.0 + z * (1.0 / 120.0 + z * (-1.0 / 5040.0 + z * (1.0 / 362880.0
        + z * (-1.0 / 39916800.0 + z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0
        + z * (1.0 / 355687428096000.0)))))));
    hi + (v * s + lo * (1.0 - 0.5 * z))
}

// cos(hi + lo), same conditions: 1 - z/2 exactly split, Taylor to x^18
#[inline]
fn cos_kernel(hi: f64, lo: f64) -> f64 {
    let z = hi * hi;
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let c = 1.0 / 24.0 + z * (-1.0 / 720.0 + z * (1.0 / 40320.0 + z * (-1.0 / 3628800.0
        + z * (1.0 / 479001600.0 + z * (-1.0 / 87178291200.0 + z * (1.0 / 20922789888000.0
        + z * (-1.0 / 6402373705728000.0)))))));
    w + (((1.0 - w) - hz) + (z * z * c - hi * lo))
}

/// Sine of x (radians). < 1 ulp, any finite x; NaN for inf and NaN.
pub fn sin(x: f64) -> f64 {
    if is_nan(x) || is_inf(x) {
        return x - x;
    }
    if fabs(x) < 1.4901161193847656e-08 {
        // 0x1p-26: x^3/6 is below half an ulp of x; keeps -0
        return x;
    }
    match rem_pio2(x) {
        (0, hi, lo) => sin_kernel(hi, lo),
        (1, hi, lo) => cos_kernel(hi, lo),
        (2, hi, lo) => -sin_kernel(hi, lo),
        (_, hi, lo) => -cos_kernel(hi, lo),
    }
}

/// Cosine of x (radians). < 1 ulp, any finite x; NaN for inf and NaN.
pub fn cos(x: f64) -> f64 {
    if is_nan(x) || is_inf(x) {
        return x - x;
    }
    match rem_pio2(x) {
        (0, hi, lo) => cos_kernel(hi, lo),
        (1, hi, lo) => -sin_kernel(hi, lo),
        (2, hi, lo) => -cos_kernel(hi, lo),
        (_, hi, lo) => sin_kernel(hi, lo),
    }
}

// ---- atan2 -------------------------------------------------------------------

// atan(t + tl) for 0 <= t <= 1, tl tiny, as (hi, lo); roz__math_atan01()
#[inline]
fn atan01(t: f64, tl: f64) -> (f64, f64) {
    let mut base_hi = 0.0;
    let mut base_lo = 0.0;
    let mut u = t;
    let mut ul = tl;
    if t > 0.41421356237309503 {
        let (a, ea) = two_sum(t, -1.0);
        let (b, eb) = two_sum(t, 1.0);
        let ea = ea + tl;
        let eb = eb + tl;
        u = a / b;
        let (p, pe) = two_prod(u, b);
        ul = (((a - p) - pe) + ea - u * eb) / b;
        base_hi = 0.7853981633974483; // pi/4, 0x1.921fb54442d18p-1
        base_lo = 3.061616997868383e-17; // 0x1.1a62633145c07p-55
    }
    let z = u * u; // s = sum over n = 1..22 of (-1)^n u^2n / (2n + 1)
    let s = z * (-1.0 / 3.0 + z * (1.0 / 5.0 + z * (-1.0 / 7.0 + z * (1.0 / 9.0 + z * (
        -1.0 / 11.0 + z * (1.0 / 13.0 + z * (-1.0 / 15.0 + z * (1.0 / 17.0 + z * (
        -1.0 / 19.0 + z * (1.0 / 21.0 + z * (-1.0 / 23.0 + z * (1.0 / 25.0 + z * (
        -1.0 / 27.0 + z * (1.0 / 29.0 + z * (-1.0 / 31.0 + z * (1.0 / 33.0 + z * (
        -1.0 / 35.0 + z * (1.0 / 37.0 + z * (-1.0 / 39.0 + z * (1.0 / 41.0 + z * (
        -1.0 / 43.0 + z * (1.0 / 45.0))))))))))))))))))))));
    let z = base_hi + u; // exact when base_hi is 0; else |u| < base_hi
    fast_two_sum(z, ((base_hi - z) + u) + (u * s + ul / (1.0 + u * u) + base_lo))
}

/// The angle of the point (x, y) from the x axis, in [-pi, pi].
/// < 1 ulp; C99's cases for zeros and infinities; NaN for a NaN.
pub fn atan2(y: f64, x: f64) -> f64 {
    let ax = fabs(x);
    let ay = fabs(y);
    if is_nan(x) || is_nan(y) {
        return x + y;
    }
    if ay == 0.0 {
        // y = +-0: +-0 toward +x, +-pi toward -x (and x = -0)
        return if to_bits(x) & SIGN != 0 { copysign(PI, y) } else { y };
    }
    if is_inf(ax) && is_inf(ay) {
        return copysign(if x > 0.0 { PI_4 } else { 3.0 * PI_4 }, y);
    }
    if ax == 0.0 || is_inf(ay) {
        return copysign(PI_2, y);
    }
    if is_inf(ax) {
        return copysign(if x > 0.0 { 0.0 } else { PI }, y);
    }
    // the ratio of the smaller to the larger, as two doubles; both scaled
    // alike (exactly) away from overflow and underflow first
    let mut big = if ay > ax { ay } else { ax };
    let mut small = if ay > ax { ax } else { ay };
    if big > 8.452712498170644e+270 {
        // 0x1p900, times 0x1p-600
        big *= 2.409919865102884e-181;
        small *= 2.409919865102884e-181;
    } else if big < 3.8725919148493183e-121 {
        // 0x1p-400, times 0x1p600
        big *= 4.149515568880993e+180;
        small *= 4.149515568880993e+180;
    }
    let t = small / big;
    let mut te = 0.0; // the rounding of t
    if small > 1.1830521861667747e-271 {
        // 0x1p-900
        let (p, pe) = two_prod(t, big);
        te = ((small - p) - pe) / big;
    }
    let (mut th, mut tl) = atan01(t, te);
    if ay > ax {
        // pi/2 - atan(x/y)
        let (h, r) = two_sum(PIO2_HI, -th);
        th = h;
        tl = r + (PIO2_LO - tl);
    }
    if x < 0.0 {
        // pi - the angle
        let (h, rl) = two_sum(2.0 * PIO2_HI, -th);
        th = h;
        tl = rl + (2.0 * PIO2_LO - tl);
    }
    copysign(th + tl, y)
}

// ---- exp, log, pow, tanh -----------------------------------------------------

// log(2) in three parts: 42 bits (k times it is exact for |k| < 2^11), then two of 53
const LN2_1: f64 = 0.6931471805598903; // 0x1.62e42fefa38p-1
const LN2_2: f64 = 5.497923018708371e-14; // 0x1.ef35793c7673p-45
const LN2_3: f64 = 1.94704509238075e-31; // 0x1.f97b57a079a19p-103
const INV_LN2: f64 = 1.4426950408889634; // 0x1.71547652b82fep+0

// exp(r) - 1 - r for |r| <= log(2)/2 + a little: Taylor to r^15
#[inline]
fn expm1_rest(r: f64) -> f64 {
    let q = 1.0 / 2.0 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0 + r * (1.0 / 720.0
        + r * (1.0 / 5040.0 + r * (1.0 / 40320.0 + r * (1.0 / 362880.0 + r * (1.0 / 3628800.0
        + r * (1.0 / 39916800.0 + r * (1.0 / 479001600.0 + r * (1.0 / 6227020800.0
        + r * (1.0 / 87178291200.0 + r * (1.0 / 1307674368000.0)))))))))))));
    r * r * q
}

// exp(hi + lo) = 2^k * (1 + p + pl) for |hi| <= 746: (p, k, pl)
#[inline]
fn exp_reduce(hi: f64, lo: f64) -> (f64, i32, f64) {
    let kd = (hi * INV_LN2 + ROUNDER) - ROUNDER;
    let r_hi = hi - kd * LN2_1; // both exact
    let r_lo = lo - kd * LN2_2;
    let (r, c) = two_sum(r_hi, r_lo);
    let q = expm1_rest(r);
    let (p, e) = fast_two_sum(r, q);
    (p, kd as i32, e + (c + c * p))
}

/// e^x. < 1 ulp; inf above 709.78, +0 below -745.13.
pub fn exp(x: f64) -> f64 {
    if is_nan(x) {
        return x;
    }
    if x > 710.0 {
        return from_bits(INF);
    }
    if x < -746.0 {
        return 0.0;
    }
    let (p, k, pl) = exp_reduce(x, 0.0);
    let (p, e) = fast_two_sum(1.0, p);
    scale(p + (e + pl), k)
}

// log(x) = hi + lo (relative error below 2^-62) for finite x > 0
fn log_dd(mut x: f64) -> (f64, f64) {
    let mut e: i32 = 0;
    if x < 2.2250738585072014e-308 {
        // 0x1p-1022: subnormal, times 0x1p54
        x *= 1.8014398509481984e+16;
        e = -54;
    }
    let u = to_bits(x);
    e += (u >> 52) as i32 - 1023;
    let mut m = from_bits((u & MANT) | 0x3FF0_0000_0000_0000);
    if m > 1.4142135623730951 {
        m *= 0.5;
        e += 1;
    }
    let f = m - 1.0;
    let (d, dl) = fast_two_sum(2.0, f);
    let s = f / d;
    let (p, pe) = two_prod(s, d);
    let sl = (((f - p) - pe) - s * dl) / d;
    let (z, zl) = two_prod(s, s);
    let zl = zl + 2.0 * s * sl;
    let (c3, c3l) = two_prod(s, z);
    let c3l = c3l + (s * zl + sl * z);
    let (t, tl) = two_prod(0.6666666666666666, c3); // 2/3 = hi + lo, 0x1.5555555555555p-1
    let tl = tl + (3.700743415417188e-17 * c3 + 0.6666666666666666 * c3l); // 0x1.5555555555555p-55
    let rr = 2.0 / 5.0 + z * (2.0 / 7.0 + z * (2.0 / 9.0 + z * (2.0 / 11.0 + z * (2.0 / 13.0
        + z * (2.0 / 15.0 + z * (2.0 / 17.0 + z * (2.0 / 19.0 + z * (2.0 / 21.0
        + z * (2.0 / 23.0 + z * (2.0 / 25.0))))))))));
    let (l_hi, l_lo) = fast_two_sum(2.0 * s, t);
    let l_lo = l_lo + (2.0 * sl + (tl + c3 * z * rr));
    // + e * log(2), in parts
    let a_hi = e as f64 * LN2_1; // exact
    let (b_hi, b_lo) = two_prod(e as f64, LN2_2);
    let (h, a_lo) = two_sum(a_hi, l_hi);
    let l = a_lo + (l_lo + (b_hi + (b_lo + e as f64 * LN2_3)));
    fast_two_sum(h, l)
}

/// Natural logarithm. < 1 ulp; log(+-0) = -inf, x < 0: NaN, log(inf) = inf.
pub fn log(x: f64) -> f64 {
    if is_nan(x) || x == from_bits(INF) {
        return x;
    }
    if x == 0.0 {
        return -from_bits(INF);
    }
    if x < 0.0 {
        return from_bits(NAN);
    }
    let (hi, lo) = log_dd(x);
    hi + lo
}

// -1 when y is an odd integer, 1 when an even one, 0 when not an integer
#[inline]
fn parity(y: f64) -> i32 {
    if floor(y) != y {
        return 0;
    }
    if fabs(y) >= 9007199254740992.0 {
        // 0x1p53
        return 1;
    }
    if floor(0.5 * y) != 0.5 * y {
        -1
    } else {
        1
    }
}

/// x raised to the power y. < 1 ulp; C99's special cases (see roz_math.h).
pub fn pow(x: f64, y: f64) -> f64 {
    let inf = from_bits(INF);
    let ax = fabs(x);
    let r;
    if y == 0.0 || x == 1.0 {
        return 1.0;
    }
    if is_nan(x) || is_nan(y) {
        return x + y;
    }
    let par = if is_inf(y) { 1 } else { parity(y) };
    if is_inf(y) {
        if ax == 1.0 {
            return 1.0;
        }
        return if (ax < 1.0) == (y < 0.0) { inf } else { 0.0 };
    }
    if is_inf(x) {
        let r = if y < 0.0 { 0.0 } else { inf };
        return if x < 0.0 && par < 0 { -r } else { r };
    }
    if ax == 0.0 {
        let r = if y < 0.0 { inf } else { 0.0 };
        return if par < 0 { copysign(r, x) } else { r };
    }
    if x < 0.0 && par == 0 {
        return from_bits(NAN);
    }
    let neg = x < 0.0 && par < 0;
    if ax == 1.0 {
        // x = -1 and an integer y
        r = 1.0;
    } else if fabs(y) > 1.8446744073709552e+19 {
        // 0x1p64: then |y log x| > 2^11
        r = if (ax < 1.0) == (y < 0.0) { inf } else { 0.0 };
    } else {
        let (lh, ll) = log_dd(ax);
        let (ph, pl) = two_prod(y, lh);
        let pl = pl + y * ll;
        let (ph, pl) = fast_two_sum(ph, pl);
        if ph > 710.0 {
            r = inf;
        } else if ph < -746.0 {
            r = 0.0;
        } else {
            let (p, k, pl) = exp_reduce(ph, pl);
            let (p, ph) = fast_two_sum(1.0, p);
            r = scale(p + (ph + pl), k);
        }
    }
    if neg {
        -r
    } else {
        r
    }
}

/// Hyperbolic tangent. < 1 ulp; +-1 beyond |x| = 22.
pub fn tanh(x: f64) -> f64 {
    let ax = fabs(x);
    if is_nan(x) {
        return x;
    }
    if ax > 22.0 {
        return copysign(1.0, x);
    }
    if ax < 3.725290298461914e-09 {
        // 0x1p-28: x^3/3 is below half an ulp of x
        return x;
    }
    // tanh = e / (e + 2) with e = exp(2|x|) - 1 = 2^k (1 + p) - 1, kept
    // as two doubles, and the quotient corrected by its remainder
    let (p, k, pl) = exp_reduce(2.0 * ax, 0.0);
    let (eh, el) = two_sum(1.0 - pow2(-k), p); // exact for k <= 53
    let el = el + pl;
    let eh = eh * pow2(k);
    let el = el * pow2(k);
    let (eh, el) = fast_two_sum(eh, el);
    let (dh, dl) = two_sum(eh, 2.0);
    let dl = dl + el;
    let q = eh / dh;
    let (qh, qe) = two_prod(q, dh);
    let q = q + (((eh - qh) - qe) + el - q * dl) / dh;
    copysign(q, x)
}

// ---- float32, for neural-network activations ---------------------------------

// e^x = 2^k (1 + p) for |x| <= 110 in double: (p, k)
#[inline]
fn expm1_f32(x: f64) -> (f64, i32) {
    let kd = (x * INV_LN2 + ROUNDER) - ROUNDER;
    let r = (x - kd * LN2_1) - kd * LN2_2;
    let q = 1.0 / 2.0 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0
        + r * (1.0 / 720.0 + r * (1.0 / 5040.0 + r * (1.0 / 40320.0
        + r * (1.0 / 362880.0 + r * (1.0 / 3628800.0 + r * (1.0 / 39916800.0
        + r * (1.0 / 479001600.0))))))))));
    (r + r * r * q, kd as i32)
}

// e^x - 1 in double for -110 <= x <= 110
#[inline]
fn expm1_d32(x: f64) -> f64 {
    let (p, k) = expm1_f32(x);
    if k == 0 {
        return p;
    }
    (pow2(k) - 1.0) + pow2(k) * p
}

/// e^x in float. < 1 ulp.
pub fn expf(x: f32) -> f32 {
    if x != x {
        return x;
    }
    if x > 89.0 {
        return from_bits(INF) as f32;
    }
    if x < -104.0 {
        return 0.0;
    }
    let (p, k) = expm1_f32(x as f64);
    ((1.0 + p) * pow2(k)) as f32
}

/// e^x - 1 in float. < 1 ulp.
pub fn expm1f(x: f32) -> f32 {
    if x != x || x == 0.0 {
        return x;
    }
    if x > 89.0 {
        return from_bits(INF) as f32;
    }
    if x < -104.0 {
        return -1.0;
    }
    expm1_d32(x as f64) as f32
}

/// Hyperbolic tangent in float. < 1 ulp.
pub fn tanhf(x: f32) -> f32 {
    let ax = fabs(x as f64);
    if x != x {
        return x;
    }
    if ax > 9.5 {
        return if x < 0.0 { -1.0 } else { 1.0 };
    }
    let e = expm1_d32(2.0 * ax); // tanh |x| = e / (e + 2)
    copysign(e / (e + 2.0), x as f64) as f32
}

/// The logistic function 1 / (1 + e^-x) in float. < 1 ulp.
pub fn sigmoidf(x: f32) -> f32 {
    if x != x {
        return x;
    }
    if x < -104.0 {
        return 0.0;
    }
    if x > 104.0 {
        return 1.0;
    }
    let (p, k) = expm1_f32(-(x as f64));
    (1.0 / (1.0 + (1.0 + p) * pow2(k))) as f32
}

/// ELU with alpha 1: x for x > 0, else e^x - 1. < 1 ulp.
pub fn eluf(x: f32) -> f32 {
    if x > 0.0 {
        x
    } else {
        expm1f(x)
    }
}

/// ReLU: +0 for x < 0, else x (NaN and -0 as given). Exact.
pub fn reluf(x: f32) -> f32 {
    if x < 0.0 {
        0.0
    } else {
        x
    }
}

// ---- the nn imports' rule for tiny numbers -----------------------------------

/// ROZ_MATH_NN_TINY_BITS: 2^-51, as float32 bits
const NN_TINY_BITS: u32 = 0x2600_0000;
/// ROZ_MATH_NN_EXP_MIN: exp and sigmoid below it are +0 (their result would
/// be subnormal)
const NN_EXP_MIN: f32 = -87.33654; // -0x1.5d589ep+6

/// x as the nn imports read it (roz_math_nn_inputf): zero of its sign below
/// 2^-51, subnormals included. Exact.
pub fn nn_inputf(x: f32) -> f32 {
    let u = x.to_bits();
    f32::from_bits(if u & 0x7FFF_FFFF < NN_TINY_BITS { u & 0x8000_0000 } else { u })
}

/// One element of nn.act (roz_math_nn_actf): kind 0 relu, 1 tanh, 2 sigmoid,
/// 3 elu, anything else exp, on nn_inputf(x).
pub fn nn_actf(kind: i32, x: f32) -> f32 {
    let x = nn_inputf(x);
    match kind {
        0 => reluf(x),
        1 => tanhf(x),
        2 if x < NN_EXP_MIN => 0.0,
        2 => sigmoidf(x),
        3 => eluf(x),
        _ if x < NN_EXP_MIN => 0.0,
        _ => expf(x),
    }
}
