// SPDX-License-Identifier: Apache-2.0
//! The Rust twin (twin.h): twin.c computes the same, operation for operation.
#![no_std]
#![deny(unsafe_code)]

use roz_controller as roz;
use roz_controller::math;

include!(concat!(env!("OUT_DIR"), "/ur5_channels.rs"));
use ur5_channels::*;

const TWIN_FUEL: u64 = 200000; // twin.h

roz::fuel_per_tick!(TWIN_FUEL);

fn step(tick: i64) {
    let mut s = [0.0; ROZ_UR5_N_STATES];
    let mut c = [0.0; ROZ_UR5_N_COMMANDS];
    let t = roz::sim_time_ns() as f64 * 1e-9;
    if roz::state_get_all(&mut s) != ROZ_UR5_N_STATES as i32 {
        roz::request_estop();
        return;
    }
    for j in 0..ROZ_UR5_N_COMMANDS {
        let q = s[ROZ_UR5_STATE_SHOULDER_PAN_JOINT_POSITION as usize + j];
        let v = s[ROZ_UR5_STATE_SHOULDER_PAN_JOINT_VELOCITY as usize + j];
        let phase = 0.7 * t + 0.5 * j as f64;
        let target = 0.6 * math::sin(phase) * math::cos(0.3 * t) + 0.1 * math::atan2(q, 1.0 + v * v);
        let gain = math::sqrt(1.0 + math::fabs(q)) * math::exp(-0.1 * math::fabs(v));
        let e = target - q;
        c[j] = 2.5 * math::tanh(gain * e) + 0.05 * math::log(1.0 + e * e)
            - 0.01 * math::pow(math::fabs(e), 1.5)
            + 0.02 * (roz::sin(phase) - roz::cos(phase));
    }
    c[0] = 4.0 * math::sin(0.9 * t + math::copysign(0.25, c[0])); // beyond +-3.14
    roz::emit_metric(roz::command_set_all(&c) as f64);
    roz::emit_metric(
        roz::command_set(ROZ_UR5_CMD_WRIST_3_JOINT_VELOCITY, math::clamp(c[5] * 1.5, -0.5, 0.5))
            as f64,
    );
    roz::emit_metric(
        math::floor(t * 3.0) + math::ceil(-t) + math::trunc(t * 0.5) + math::fmin(t, 2.0)
            + math::fmax(t - 5.0, -0.0)
            + (tick % 7) as f64,
    );
}

roz::process!(step);
