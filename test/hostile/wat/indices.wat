;; SPDX-License-Identifier: Apache-2.0
;; Hostile: every tick, 64 rounds of command.set, state.get and
;; command.limit_min/max on pseudo-random channel indices (a fixed LCG):
;; the whole i32 range, small negatives and just past the end, and the
;; extremes -2^31, -1, 6 and 2^31-1. Values are finite and mostly outside
;; the limits (up to +-2147), so they are clamped.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (import "command" "limit_min" (func $lmin (param i32) (result f64)))
  (import "command" "limit_max" (func $lmax (param i32) (result f64)))
  (import "state" "get" (func $get (param i32) (result f64)))
  (global $seed (mut i32) (i32.const 12345))
  (func $next (result i32)
    (global.set $seed (i32.add (i32.mul (global.get $seed) (i32.const 1103515245))
                               (i32.const 12345)))
    (global.get $seed))
  (func $index (result i32)
    (local $r i32) (local $pick i32)
    (local.set $r (call $next))
    (local.set $pick (i32.and (i32.shr_u (local.get $r) (i32.const 8)) (i32.const 7)))
    (if (result i32) (i32.lt_u (local.get $pick) (i32.const 3))
      (then (local.get $r))                                          ;; any i32
      (else
        (if (result i32) (i32.lt_u (local.get $pick) (i32.const 6))
          (then (i32.sub (i32.and (i32.shr_u (local.get $r) (i32.const 16)) (i32.const 15))
                         (i32.const 4)))                             ;; -4..11
          (else
            (if (result i32) (i32.eq (local.get $pick) (i32.const 6))
              (then (select (i32.const -2147483648) (i32.const -1)
                      (i32.and (local.get $r) (i32.const 0x10000))))
              (else (select (i32.const 2147483647) (i32.const 6)
                      (i32.and (local.get $r) (i32.const 0x10000))))))))))
  (func (export "process") (param $tick i64)
    (local $k i32)
    (loop $round
      (drop (call $set (call $index)
        (f64.mul (f64.convert_i32_s (call $next)) (f64.const 1e-6))))
      (drop (call $get (call $index)))
      (drop (call $lmin (call $index)))
      (drop (call $lmax (call $index)))
      (local.set $k (i32.add (local.get $k) (i32.const 1)))
      (br_if $round (i32.lt_u (local.get $k) (i32.const 64))))))
