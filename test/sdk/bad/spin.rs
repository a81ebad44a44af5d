// SPDX-License-Identifier: Apache-2.0
//! A Rust controller that never returns from tick 150 on: roz stops it by
//! its fuel and latches the overrun fault.
#![no_std]
#![deny(unsafe_code)]

use roz_controller as roz;

fn step(tick: i64) {
    let mut x = 0.1;
    if tick >= 150 {
        // the state's NaN check keeps the optimiser from proving it endless
        while roz::state_get(0) == roz::state_get(0) {
            x = -x;
        }
    }
    roz::command_set(0, x);
}

roz::process!(step);
