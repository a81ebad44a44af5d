// SPDX-License-Identifier: Apache-2.0
//! The Rust SDK's exact functions (sdk/rust/src/math.rs) built for the host
//! against the host's own (Rust's std: the IEEE operations, correctly
//! rounded): sqrt, floor, ceil, trunc, fabs, copysign, fmin and fmax bit
//! for bit over millions of doubles of every exponent, the subnormals, the
//! perfect squares and their neighbours, and the special values. Run by
//! ctest as test_rust_math_native; exits 1 at the first difference.
#[path = "../../sdk/rust/src/math.rs"]
#[allow(dead_code)]
mod math;

use std::process::exit;

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn check(name: &str, x: f64, got: f64, want: f64, checked: &mut u64) {
    *checked += 1;
    if !same(got, want) {
        eprintln!("{}({:e} = {:#018x}): SDK {:e} ({:#018x}), std {:e} ({:#018x})", name, x,
                  x.to_bits(), got, got.to_bits(), want, want.to_bits());
        exit(1);
    }
}

fn exact(x: f64, n: &mut u64) {
    check("sqrt", x, math::sqrt(x), x.sqrt(), n);
    check("floor", x, math::floor(x), x.floor(), n);
    check("ceil", x, math::ceil(x), x.ceil(), n);
    check("trunc", x, math::trunc(x), x.trunc(), n);
    check("fabs", x, math::fabs(x), x.abs(), n);
    check("copysign", x, math::copysign(1.5, x), 1.5f64.copysign(x), n);
}

fn main() {
    let mut n = 0u64;
    let mut u: u64 = 0x243F_6A88_85A3_08D3; // splitmix64
    let mut next = || {
        u = u.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = u;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let specials = [0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 4.0, f64::MIN_POSITIVE, f64::MAX, f64::MIN,
                    f64::EPSILON, 5e-324, -5e-324, f64::INFINITY, f64::NEG_INFINITY, f64::NAN,
                    4503599627370495.5, 4503599627370496.0, -4503599627370497.0,
                    9007199254740993.0, 0.49999999999999994, -0.49999999999999994];
    for &x in specials.iter() {
        exact(x, &mut n);
    }
    for _ in 0..2_000_000 {
        exact(f64::from_bits(next()), &mut n); // every exponent, both signs, NaNs
    }
    for k in 0..1074 {
        // every subnormal power of two and its neighbours
        let x = f64::from_bits(1u64 << (k % 52)) * if k < 52 { 1.0 } else { 2f64.powi(k - 51) };
        for x in [x, f64::from_bits(x.to_bits() + 1), f64::from_bits(x.to_bits() + 3)] {
            exact(x, &mut n);
        }
    }
    for _ in 0..500_000 {
        // squares and their neighbours: where rounding a root is closest to a tie
        let r = f64::from_bits((next() & 0x000F_FFFF_FFFF_FFFF) | (((next() % 2000) + 24) << 52));
        let x = r * r;
        if x.is_finite() && x > 0.0 {
            for d in [0u64, 1, 2] {
                exact(f64::from_bits(x.to_bits() + d), &mut n);
                exact(f64::from_bits(x.to_bits() - d), &mut n);
            }
        }
        let i = (next() >> 11) as f64; // integers and half-integers up to 2^53
        exact(i, &mut n);
        exact(i * i, &mut n);
        exact(-(i + 0.5), &mut n);
    }
    for _ in 0..200_000 {
        let a = f64::from_bits(next());
        let b = if next() & 1 == 0 { a } else { f64::from_bits(next()) };
        let want_min = if a.is_nan() { b } else if b.is_nan() { a } else if a == b {
            if a.is_sign_negative() { a } else { b }
        } else { a.min(b) };
        let want_max = if a.is_nan() { b } else if b.is_nan() { a } else if a == b {
            if a.is_sign_negative() { b } else { a }
        } else { a.max(b) };
        check("fmin", a, math::fmin(a, b), want_min, &mut n);
        check("fmax", a, math::fmax(a, b), want_max, &mut n);
    }
    println!("rust_math_native: {} results, every one the host's bits", n);
}
