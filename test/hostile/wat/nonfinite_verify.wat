;; SPDX-License-Identifier: Apache-2.0
;; Hostile: sets +Inf on joint 2 at tick 7, inside verification.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (func (export "process") (param $tick i64)
    (if (i64.eq (local.get $tick) (i64.const 7))
      (then (drop (call $set (i32.const 2) (f64.const inf)))))))
