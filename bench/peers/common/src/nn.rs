// SPDX-License-Identifier: Apache-2.0
//! roz's neural-network imports (`nn.matvec`, `nn.act`) as lib/src/abi.c
//! has them, over an instance's linear memory: the same range and overlap
//! refusals (nothing written, counted), each output row summed in the same
//! order (float32, a product then a sum, never fused), every value read by
//! roz_math.h's rule for tiny numbers and the activations roz_math.h's: the
//! Rust SDK's math, which restates them bit for bit, so that the results are
//! roz's bit for bit.

use crate::Abi;

pub const NN_BIAS: i32 = 1;
pub const NN_ACCUMULATE: i32 = 2;
/// ROZ_ABI_NN_RELU .. ROZ_ABI_NN_EXP
pub const NN_ACT_COUNT: i32 = 5;

// Each value read, and each activation, is the Rust SDK's (sdk/rust/src/math.rs),
// which restates roz_math.h's float functions bit for bit.
use roz_controller::math::{nn_actf, nn_inputf};

fn range_ok(len: usize, at: u32, bytes: u64) -> bool {
    bytes <= len as u64 && at as u64 <= len as u64 - bytes
}

fn overlap(a: u32, an: u64, b: u32, bn: u64) -> bool {
    an != 0 && bn != 0 && (a as u64) < b as u64 + bn && (b as u64) < a as u64 + an
}

/// The float32 at `at`, as stored.
fn raw(mem: &[u8], at: usize) -> f32 {
    f32::from_le_bytes(mem[at..at + 4].try_into().unwrap())
}

/// A value as the imports read it (roz_math.h, roz_math_nn_inputf).
fn ld(mem: &[u8], at: usize) -> f32 {
    nn_inputf(raw(mem, at))
}

fn st(mem: &mut [u8], at: usize, v: f32) {
    mem[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

impl Abi {
    fn nn_refuse(&mut self) -> i32 {
        self.counters.nn_refused += 1;
        -1
    }

    /// nn.matvec: y = W x (+ b) (y +=, with ACCUMULATE); 0, or -1 with
    /// nothing written.
    #[allow(clippy::too_many_arguments)]
    pub fn nn_matvec(&mut self, mem: Option<&mut [u8]>, w: u32, x: u32, b: u32, y: u32,
                     rows: i32, cols: i32, flags: i32) -> i32 {
        self.counters.nn_calls += 1;
        let mem = match mem {
            Some(m) if rows >= 0 && cols >= 0 && flags & !(NN_BIAS | NN_ACCUMULATE) == 0 => m,
            _ => return self.nn_refuse(),
        };
        let wn = 4 * rows as u64 * cols as u64;
        let (xn, yn) = (4 * cols as u64, 4 * rows as u64);
        let bn = if flags & NN_BIAS != 0 { yn } else { 0 };
        let len = mem.len();
        if !range_ok(len, w, wn) || !range_ok(len, x, xn) || (bn != 0 && !range_ok(len, b, bn))
            || !range_ok(len, y, yn) || overlap(y, yn, w, wn) || overlap(y, yn, x, xn)
            || overlap(y, yn, b, bn)
        {
            return self.nn_refuse();
        }
        let (w, x, b, y, cols) = (w as usize, x as usize, b as usize, y as usize, cols as usize);
        for i in 0..rows as usize {
            let row = w + 4 * i * cols;
            let mut s = 0.0f32;
            for j in 0..cols {
                s = s + ld(mem, row + 4 * j) * ld(mem, x + 4 * j);
            }
            if flags & NN_BIAS != 0 {
                s = s + ld(mem, b + 4 * i);
            }
            if flags & NN_ACCUMULATE != 0 {
                s = ld(mem, y + 4 * i) + s;
            }
            st(mem, y + 4 * i, s);
        }
        0
    }

    /// nn.act: an activation in place on `count` floats; count, or -1.
    pub fn nn_act(&mut self, mem: Option<&mut [u8]>, kind: i32, ptr: u32, count: i32) -> i32 {
        self.counters.nn_calls += 1;
        let mem = match mem {
            Some(m) if (0..NN_ACT_COUNT).contains(&kind) && count >= 0
                && range_ok(m.len(), ptr, 4 * count as u64) => m,
            _ => return self.nn_refuse(),
        };
        for i in 0..count as usize {
            let at = ptr as usize + 4 * i;
            st(mem, at, nn_actf(kind, raw(mem, at)));
        }
        count
    }
}
