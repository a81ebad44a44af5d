;; SPDX-License-Identifier: Apache-2.0
;; Drives command 0 at 0.2 and requests an e-stop at tick 150.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (import "safety" "request_estop" (func $estop))
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.2)))
    (if (i64.eq (local.get $tick) (i64.const 150)) (then (call $estop)))))
