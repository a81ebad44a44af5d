;; SPDX-License-Identifier: Apache-2.0
;; Drives command 0 at 0.1 and traps at tick 150: verification (ticks 0-99)
;; passes, the trap latches at run time.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.1)))
    (if (i64.eq (local.get $tick) (i64.const 150)) (then unreachable))))
