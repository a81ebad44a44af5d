;; SPDX-License-Identifier: Apache-2.0
;; Sets command 0 to NaN: verification must refuse it.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.div (f64.const 0) (f64.const 0))))))
