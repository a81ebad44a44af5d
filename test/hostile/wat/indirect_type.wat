;; SPDX-License-Identifier: Apache-2.0
;; Hostile: at tick 150 calls a (func (param i32) (result i32)) through a
;; call_indirect typed (func (result f64)): a signature mismatch.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (type $f (func (result f64)))
  (table 1 funcref)
  (func $id (param i32) (result i32) (local.get 0))
  (elem (i32.const 0) $id)
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then (drop (call_indirect (type $f) (i32.const 0)))))))
