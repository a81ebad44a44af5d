;; SPDX-License-Identifier: Apache-2.0
;; Hostile: drives joint 0 at 0.3 rad/s and at tick 150 calls
;; safety.request_estop 5000 times in one tick (within its fuel).
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (import "safety" "request_estop" (func $estop))
  (func (export "process") (param $tick i64)
    (local $i i32)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then
        (loop $spam
          (call $estop)
          (local.set $i (i32.add (local.get $i) (i32.const 1)))
          (br_if $spam (i32.lt_u (local.get $i) (i32.const 5000))))))))
