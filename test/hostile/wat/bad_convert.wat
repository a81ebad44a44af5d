;; SPDX-License-Identifier: Apache-2.0
;; Hostile: converts NaN to an integer at tick 150 (a trap in WebAssembly).
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (import "state" "get" (func $get (param i32) (result f64)))
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then (drop (i32.trunc_f64_s (call $get (i32.const -1))))))))
