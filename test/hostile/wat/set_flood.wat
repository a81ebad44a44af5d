;; SPDX-License-Identifier: Apache-2.0
;; Hostile: drives joint 0 at 0.3 rad/s; at tick 150 calls command.set
;; 1,000,000 times, cycling over the six joints with +-10 (clamped), and
;; finally sets joint 0 to 0.25.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (func (export "process") (param $tick i64)
    (local $i i32)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then
        (loop $flood
          (drop (call $set (i32.rem_u (local.get $i) (i32.const 6))
            (select (f64.const 10) (f64.const -10)
              (i32.and (local.get $i) (i32.const 1)))))
          (local.set $i (i32.add (local.get $i) (i32.const 1)))
          (br_if $flood (i32.lt_u (local.get $i) (i32.const 1000000))))
        (drop (call $set (i32.const 0) (f64.const 0.25)))))))
