// SPDX-License-Identifier: Apache-2.0
//! The roz controller ABI for controllers written in Rust: the Rust twin of
//! the C SDK's `roz_controller.h` and `roz_math.h`, for the target
//! `wasm32-unknown-unknown`. `no_std`, no dependencies, no allocator; every
//! `unsafe` of a controller is in here, so a controller itself can be
//! `#![deny(unsafe_code)]`.
//!
//! ```ignore
//! #![no_std]
//! #![deny(unsafe_code)]
//! use roz_controller as roz;
//!
//! fn step(_tick: i64) {
//!     roz::command_set(0, 0.1);
//! }
//! roz::process!(step);
//! ```
//!
//! The imports keep the ABI's module and field names (`command.set`,
//! `state.get_all`, ...); `process!` exports the entry point `process(i64)`,
//! `fuel_per_tick!` declares a heavy controller's fuel (the custom section
//! `roz.fuel`), and a panic traps (`unreachable`), which roz counts as a
//! controller trap. Channel indices and the robot's identity come from the
//! module rozgen writes beside the C header, `<robot_id>_channels.rs`.
//! Building, the linker flags (a stack of 16 KiB; rustc's default of 1 MiB
//! is more memory than roz allows) and the other toolchains: docs/rust.md.
//!
//! Built for another target (a host test, a benchmark), the imports are
//! plain C functions of the C SDK's names (`roz_command_set`, ...), which
//! the host program provides, as with `roz_controller.h`.
#![no_std]

pub mod math;

/// `command_set` took the value.
pub const SET_TAKEN: i32 = 0;
/// `command_set` clamped the value to the channel's limits.
pub const SET_CLAMPED: i32 = 1;
/// `command_set` refused the value (bad index, NaN or infinity).
pub const SET_REFUSED: i32 = -1;

#[allow(clippy::missing_safety_doc)]
mod ffi {
    #[cfg_attr(target_arch = "wasm32", link(wasm_import_module = "command"))]
    extern "C" {
        #[cfg_attr(target_arch = "wasm32", link_name = "set")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_command_set")]
        pub fn command_set(index: i32, value: f64) -> i32;
        #[cfg_attr(target_arch = "wasm32", link_name = "count")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_command_count")]
        pub fn command_count() -> i32;
        #[cfg_attr(target_arch = "wasm32", link_name = "limit_min")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_command_limit_min")]
        pub fn command_limit_min(index: i32) -> f64;
        #[cfg_attr(target_arch = "wasm32", link_name = "limit_max")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_command_limit_max")]
        pub fn command_limit_max(index: i32) -> f64;
        #[cfg_attr(target_arch = "wasm32", link_name = "set_all")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_command_set_all")]
        pub fn command_set_all(values: *const f64, count: i32) -> i32;
    }
    #[cfg_attr(target_arch = "wasm32", link(wasm_import_module = "state"))]
    extern "C" {
        #[cfg_attr(target_arch = "wasm32", link_name = "get")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_state_get")]
        pub fn state_get(index: i32) -> f64;
        #[cfg_attr(target_arch = "wasm32", link_name = "count")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_state_count")]
        pub fn state_count() -> i32;
        #[cfg_attr(target_arch = "wasm32", link_name = "get_all")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_state_get_all")]
        pub fn state_get_all(values: *mut f64, count: i32) -> i32;
    }
    #[cfg_attr(target_arch = "wasm32", link(wasm_import_module = "math"))]
    extern "C" {
        #[cfg_attr(target_arch = "wasm32", link_name = "sin")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_sin")]
        pub fn sin(x: f64) -> f64;
        #[cfg_attr(target_arch = "wasm32", link_name = "cos")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_cos")]
        pub fn cos(x: f64) -> f64;
    }
    #[cfg_attr(target_arch = "wasm32", link(wasm_import_module = "safety"))]
    extern "C" {
        #[cfg_attr(target_arch = "wasm32", link_name = "request_estop")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_request_estop")]
        pub fn request_estop();
    }
    #[cfg_attr(target_arch = "wasm32", link(wasm_import_module = "timing"))]
    extern "C" {
        #[cfg_attr(target_arch = "wasm32", link_name = "now_ns")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_now_ns")]
        pub fn now_ns() -> i64;
        #[cfg_attr(target_arch = "wasm32", link_name = "sim_time_ns")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_sim_time_ns")]
        pub fn sim_time_ns() -> i64;
    }
    #[cfg_attr(target_arch = "wasm32", link(wasm_import_module = "telemetry"))]
    extern "C" {
        #[cfg_attr(target_arch = "wasm32", link_name = "emit_metric")]
        #[cfg_attr(not(target_arch = "wasm32"), link_name = "roz_emit_metric")]
        pub fn emit_metric(value: f64);
    }
}

// The imports are safe to call with any argument: the host checks every
// index, pointer and count (roz/abi.h) and answers NaN or -1 for bad ones.

/// Write command channel `index`: `SET_TAKEN`, `SET_CLAMPED` or `SET_REFUSED`.
#[inline]
pub fn command_set(index: i32, value: f64) -> i32 {
    unsafe { ffi::command_set(index, value) }
}

/// Number of command channels.
#[inline]
pub fn command_count() -> i32 {
    unsafe { ffi::command_count() }
}

/// Lower limit of a command channel; NaN for a bad index.
#[inline]
pub fn command_limit_min(index: i32) -> f64 {
    unsafe { ffi::command_limit_min(index) }
}

/// Upper limit of a command channel; NaN for a bad index.
#[inline]
pub fn command_limit_max(index: i32) -> f64 {
    unsafe { ffi::command_limit_max(index) }
}

/// Value of state channel `index` in this tick's snapshot; NaN for a bad index.
#[inline]
pub fn state_get(index: i32) -> f64 {
    unsafe { ffi::state_get(index) }
}

/// Number of state channels.
#[inline]
pub fn state_count() -> i32 {
    unsafe { ffi::state_count() }
}

/// Sine, answered by the host with the same bits as `math::sin`.
#[inline]
pub fn sin(x: f64) -> f64 {
    unsafe { ffi::sin(x) }
}

/// Cosine, answered by the host with the same bits as `math::cos`.
#[inline]
pub fn cos(x: f64) -> f64 {
    unsafe { ffi::cos(x) }
}

/// Ask for an emergency stop.
#[inline]
pub fn request_estop() {
    unsafe { ffi::request_estop() }
}

/// Wall-clock nanoseconds.
#[inline]
pub fn now_ns() -> i64 {
    unsafe { ffi::now_ns() }
}

/// Control time: tick * period, in nanoseconds.
#[inline]
pub fn sim_time_ns() -> i64 {
    unsafe { ffi::sim_time_ns() }
}

/// Record a scalar for observability.
#[inline]
pub fn emit_metric(value: f64) {
    unsafe { ffi::emit_metric(value) }
}

// A slice's length as the ABI's i32 count: a slice longer than i32::MAX
// (impossible in wasm32's memory) gives -1, which the host refuses.
#[inline]
fn count_of(len: usize) -> i32 {
    if len > i32::MAX as usize {
        -1
    } else {
        len as i32
    }
}

/// The bulk extension: copy state channels `0..values.len()` of this tick's
/// snapshot into `values`; returns the count, or -1 (nothing copied) for a
/// slice longer than the state count.
#[inline]
pub fn state_get_all(values: &mut [f64]) -> i32 {
    unsafe { ffi::state_get_all(values.as_mut_ptr(), count_of(values.len())) }
}

/// The bulk extension: set command channels `0..values.len()`, each as
/// `command_set(i, values[i])` would; returns how many were clamped or
/// refused, or -1 (no channel changed) for a slice longer than the command
/// count. Channels from `values.len()` on keep their values.
#[inline]
pub fn command_set_all(values: &[f64]) -> i32 {
    unsafe { ffi::command_set_all(values.as_ptr(), count_of(values.len())) }
}

/// A panic traps: roz counts it as a controller trap and latches a fault
/// (the filter drives every command to its safe default).
#[cfg(all(target_arch = "wasm32", not(test)))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    core::arch::wasm32::unreachable()
}

/// Exports `f` (a `fn(i64)`, the tick counting from 0) as the controller's
/// entry point `process`, called once per tick:
/// `roz_controller::process!(step);`
#[macro_export]
macro_rules! process {
    ($f:path) => {
        #[allow(unsafe_code)]
        #[no_mangle]
        pub extern "C" fn process(tick: i64) {
            let f: fn(i64) = $f;
            f(tick)
        }
    };
}

/// The fuel a heavy controller needs per tick, in work units (roz/runtime.h,
/// fuel_per_tick_max; the C SDK's ROZ_FUEL_PER_TICK): once, at item level,
/// with an integer constant: `roz_controller::fuel_per_tick!(60000);`.
/// It lands in the module's custom section "roz.fuel" (version 1, then the
/// units as a little-endian u64).
#[macro_export]
macro_rules! fuel_per_tick {
    ($units:expr) => {
        #[allow(unsafe_code)]
        #[cfg_attr(target_arch = "wasm32", link_section = "roz.fuel")]
        #[used]
        static ROZ_FUEL_PER_TICK: [u8; 9] = {
            let u: u64 = $units;
            let b = u.to_le_bytes();
            [1, b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]
        };
    };
}
