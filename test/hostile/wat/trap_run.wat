;; SPDX-License-Identifier: Apache-2.0
;; Hostile: drives joint 0 at 0.3 rad/s and reaches `unreachable` at
;; tick 150, after verification (ticks 0-99) has passed.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150)) (then unreachable))))
