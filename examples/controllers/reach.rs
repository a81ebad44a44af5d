// SPDX-License-Identifier: Apache-2.0
//! Reach (UR5) in Rust: the twin of reach.c, line for line, with the Rust
//! controller SDK (sdk/rust) and the robot's generated module. The wrist
//! follows a circle in the arm's vertical plane while the base sweeps
//! slowly, by inverse kinematics computed inside the sandbox with
//! roz_controller::math, so it commands the C twin's bits on every host
//! (test/sdk/test_rust_controller.c compares them every tick).
//!
//! Shoulder and elbow are a planar two-link arm (upper arm 0.425 m, forearm
//! 0.39225 m) reaching a point (r, h) from the shoulder; the first wrist
//! joint keeps the tool level, the other two hold. Each joint gets its
//! target's rate plus a saturating P law, v = VMAX tanh(KP (target - q) /
//! VMAX), all faded in by 1 - exp(-t / TAU). The tracking error (the norm
//! over the joints, rad) is emitted as a metric each tick.
#![no_std]
#![deny(unsafe_code)]

use roz_controller as roz;
use roz_controller::math;

include!(concat!(env!("OUT_DIR"), "/ur5_channels.rs"));
use ur5_channels::*;

const L1: f64 = 0.425; // m, shoulder to elbow
const L2: f64 = 0.39225; // m, elbow to wrist
const KP: f64 = 3.0; // 1/s
const VMAX: f64 = 1.0; // rad/s
const TAU: f64 = 0.5; // s, fade-in
const OMEGA: f64 = 0.5; // rad/s along the circle
const DT: f64 = 1.0 / ROZ_UR5_CONTROL_RATE_HZ as f64;

/// The joint targets at time t (s).
fn targets(t: f64) -> [f64; 6] {
    let r = 0.55 + 0.10 * math::cos(OMEGA * t); // m, from the shoulder
    let h = 0.15 + 0.10 * math::sin(OMEGA * t);
    let c = math::clamp((r * r + h * h - L1 * L1 - L2 * L2) / (2.0 * L1 * L2), -1.0, 1.0);
    let elbow = math::atan2(math::sqrt(1.0 - c * c), c); // bend, 0..pi
    let lift = math::atan2(h, r) + math::atan2(L2 * math::sin(elbow), L1 + L2 * math::cos(elbow));
    [
        0.4 * math::sin(0.2 * t), // base sweep
        -lift,                    // UR5: negative lifts the arm
        elbow,
        lift - elbow, // the tool stays level
        0.0,
        0.0,
    ]
}

fn step(_tick: i64) {
    let t = roz::sim_time_ns() as f64 * 1e-9;
    let fade = 1.0 - math::exp(-t / TAU);
    let now = targets(t);
    let next = targets(t + DT);
    let mut err2 = 0.0;
    for j in 0..6 {
        let e = now[j] - roz::state_get(ROZ_UR5_STATE_SHOULDER_PAN_JOINT_POSITION + j as i32);
        let v = (next[j] - now[j]) / DT + VMAX * math::tanh(KP * e / VMAX);
        roz::command_set(ROZ_UR5_CMD_SHOULDER_PAN_JOINT_VELOCITY + j as i32, fade * v);
        err2 += e * e;
    }
    roz::emit_metric(math::sqrt(err2));
}

roz::process!(step);
