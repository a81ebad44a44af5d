// SPDX-License-Identifier: Apache-2.0
//! Reach (UR5) in Zig: the twin of reach.c, built for wasm32-freestanding
//! by Zig from PyPI (the ziglang wheel; docs/rust.md, "Other toolchains").
//! The math is the C SDK's roz_math.h, compiled by Zig's own C compiler into
//! the same module (reach_math.c), so it commands the C twin's bits
//! (test_rust_controller compares them every tick).
//!
//! Two rules of Zig that matter for bits: the constants are typed f64, so
//! that L1 * L1 is a double product as in C (untyped, Zig would fold it at
//! compile time in 128-bit precision); and nothing uses @mulAdd.

extern "command" fn set(index: i32, value: f64) i32;
extern "state" fn get(index: i32) f64;
extern "timing" fn sim_time_ns() i64;
extern "telemetry" fn emit_metric(value: f64) void;

extern fn reach_sin(x: f64) f64;
extern fn reach_cos(x: f64) f64;
extern fn reach_atan2(y: f64, x: f64) f64;
extern fn reach_sqrt(x: f64) f64;
extern fn reach_exp(x: f64) f64;
extern fn reach_tanh(x: f64) f64;
extern fn reach_clamp(x: f64, lo: f64, hi: f64) f64;

// ur5_channels.h: ROZ_UR5_STATE_SHOULDER_PAN_JOINT_POSITION,
// ROZ_UR5_CMD_SHOULDER_PAN_JOINT_VELOCITY, ROZ_UR5_CONTROL_RATE_HZ
const STATE_POSITION_0: i32 = 0;
const CMD_VELOCITY_0: i32 = 0;
const CONTROL_RATE_HZ: f64 = 100;

const L1: f64 = 0.425; // m, shoulder to elbow
const L2: f64 = 0.39225; // m, elbow to wrist
const KP: f64 = 3.0; // 1/s
const VMAX: f64 = 1.0; // rad/s
const TAU: f64 = 0.5; // s, fade-in
const OMEGA: f64 = 0.5; // rad/s along the circle
const DT: f64 = 1.0 / CONTROL_RATE_HZ;

/// The joint targets at time t (s).
fn targets(t: f64, q: *[6]f64) void {
    const r = 0.55 + 0.10 * reach_cos(OMEGA * t);
    const h = 0.15 + 0.10 * reach_sin(OMEGA * t);
    const c = reach_clamp((r * r + h * h - L1 * L1 - L2 * L2) / (2.0 * L1 * L2), -1.0, 1.0);
    const elbow = reach_atan2(reach_sqrt(1.0 - c * c), c);
    const lift = reach_atan2(h, r) + reach_atan2(L2 * reach_sin(elbow), L1 + L2 * reach_cos(elbow));
    q[0] = 0.4 * reach_sin(0.2 * t);
    q[1] = -lift;
    q[2] = elbow;
    q[3] = lift - elbow;
    q[4] = 0.0;
    q[5] = 0.0;
}

export fn process(tick: i64) void {
    _ = tick;
    const t = @as(f64, @floatFromInt(sim_time_ns())) * 1e-9;
    const fade = 1.0 - reach_exp(-t / TAU);
    var now: [6]f64 = undefined;
    var next: [6]f64 = undefined;
    var err2: f64 = 0.0;
    targets(t, &now);
    targets(t + DT, &next);
    for (0..6) |j| {
        const i: i32 = @intCast(j);
        const e = now[j] - get(STATE_POSITION_0 + i);
        const v = (next[j] - now[j]) / DT + VMAX * reach_tanh(KP * e / VMAX);
        _ = set(CMD_VELOCITY_0 + i, fade * v);
        err2 += e * e;
    }
    emit_metric(reach_sqrt(err2));
}
