// SPDX-License-Identifier: Apache-2.0
//! A Rust controller that panics at tick 150 (an index out of bounds):
//! the SDK's panic handler traps, roz latches the trap fault.
#![no_std]
#![deny(unsafe_code)]

use roz_controller as roz;

fn step(tick: i64) {
    let gains = [0.1, 0.2, 0.3];
    // index 3 at tick 150: out of bounds, which Rust checks
    let i = if tick >= 150 { 3 } else { (tick % 3) as usize };
    roz::command_set(0, gains[i]);
}

roz::process!(step);
