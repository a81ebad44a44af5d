// SPDX-License-Identifier: Apache-2.0
//! reach.c in Rust: built for wasm32 by roz_add_rust_controller() with the
//! Rust SDK roz provides and the module rozgen makes from the consumer's
//! robot.toml: joint2 goes to 1 rad, joint1 stays where it is.
#![no_std]
#![deny(unsafe_code)]

use roz_controller as roz;

include!(concat!(env!("OUT_DIR"), "/my_arm_channels.rs"));
use my_arm_channels::*;

fn step(_tick: i64) {
    let q = roz::state_get(ROZ_MY_ARM_STATE_JOINT2_POSITION);
    roz::command_set(ROZ_MY_ARM_CMD_JOINT2_VELOCITY, 2.0 * (1.0 - q));
    roz::command_set(ROZ_MY_ARM_CMD_JOINT1_VELOCITY, 0.0);
}

roz::process!(step);
