;; SPDX-License-Identifier: Apache-2.0
;; Hostile: drives every joint at 0.3 rad/s, then from tick 150 sets
;; NaN, +Inf, -Inf, 1e308, -1e308 and the smallest denormal on joints 0-5.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (func (export "process") (param $tick i64)
    (local $i i32)
    (if (i64.lt_s (local.get $tick) (i64.const 150))
      (then
        (loop $all
          (drop (call $set (local.get $i) (f64.const 0.3)))
          (local.set $i (i32.add (local.get $i) (i32.const 1)))
          (br_if $all (i32.lt_u (local.get $i) (i32.const 6)))))
      (else
        (drop (call $set (i32.const 0) (f64.div (f64.const 0) (f64.const 0))))
        (drop (call $set (i32.const 1) (f64.const inf)))
        (drop (call $set (i32.const 2) (f64.const -inf)))
        (drop (call $set (i32.const 3) (f64.const 1e308)))
        (drop (call $set (i32.const 4) (f64.const -1e308)))
        (drop (call $set (i32.const 5) (f64.const 0x1p-1074)))))))
