;; SPDX-License-Identifier: Apache-2.0
;; Hostile: divides by zero at tick 150.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then (drop (i32.div_s (i32.const 1) (i32.wrap_i64 (i64.sub (local.get $tick)
                                                                   (i64.const 150)))))))))
