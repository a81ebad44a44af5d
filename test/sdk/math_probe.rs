// SPDX-License-Identifier: Apache-2.0
//! The math probe in Rust: the twin of math_probe.c and math_probe.h, the
//! same inputs each tick and every function of roz_controller::math in the
//! same order, emitted as metrics, for test_rust_controller.c to compare
//! bit for bit with the C probe (roz_math.h). It commands nothing.
#![no_std]
#![deny(unsafe_code)]

use roz_controller as roz;
use roz_controller::math;

const COUNT: usize = 15; // PROBE_COUNT

const SPECIALS: [f64; 22] = [
    0.0, -0.0, 1.0, -1.0, 0.5, -2.5, 3.0, 1e300, -1e300, 1.7976931348623157e308,
    2.2250738585072014e-308, 5e-324, -1e-310, 1e-300, f64::INFINITY, f64::NEG_INFINITY, f64::NAN,
    1.5707963267948966, 3.141592653589793, 709.78, -745.1, 0.41421356237309503,
];

/// probe_input() of math_probe.h
fn input(t: i64, k: i32) -> f64 {
    let mut u = (t as u64).wrapping_mul(0x9E3779B97F4A7C15).wrapping_add(k as u64);
    if t < SPECIALS.len() as i64 {
        return SPECIALS[((t + k as i64) % SPECIALS.len() as i64) as usize];
    }
    u ^= u >> 31;
    u = u.wrapping_mul(0xBF58476D1CE4E5B9);
    u ^= u >> 29;
    match t % 4 {
        0 => f64::from_bits(u & 0xFFEF_FFFF_FFFF_FFFF), // any double, every exponent
        1 => ((u >> 11) as f64 * 1.1102230246251565e-16 - 0.5) * 20.0, // 0x1p-53; -10 .. 10
        2 => ((u >> 11) as f64 * 1.1102230246251565e-16 - 0.5) * 1500.0, // -750 .. 750
        _ => (u >> 11) as f64 * 2.220446049250313e-16, // 0x1p-52; 0 .. 2
    }
}

fn step(t: i64) {
    let x = input(t, 0);
    let y = input(t, 1);
    let r: [f64; COUNT] = [
        math::fabs(x),
        math::sqrt(x),
        math::floor(x),
        math::ceil(x),
        math::trunc(x),
        math::fmin(x, y),
        math::fmax(x, y),
        math::clamp(x, -1.0, 2.0),
        math::sin(x),
        math::cos(x),
        math::atan2(y, x),
        math::exp(x),
        math::log(x),
        math::pow(if t % 2 != 0 { math::fabs(x) } else { x }, if t % 4 == 2 { y / 64.0 } else { y }),
        math::tanh(x),
    ];
    for v in r.iter() {
        roz::emit_metric(*v);
    }
}

roz::process!(step);
