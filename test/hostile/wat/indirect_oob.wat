;; SPDX-License-Identifier: Apache-2.0
;; Hostile: at tick 150 calls table entry 1000000 of a 4-entry table.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (type $v (func))
  (table 4 funcref)
  (func $nop)
  (elem (i32.const 0) $nop)
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then (call_indirect (type $v) (i32.const 1000000))))))
