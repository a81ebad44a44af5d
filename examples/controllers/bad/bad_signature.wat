;; SPDX-License-Identifier: Apache-2.0
;; Imports command.set with an f32 value instead of f64: refused at load.
(module
  (import "command" "set" (func $set (param i32 f32) (result i32)))
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f32.const 1)))))
