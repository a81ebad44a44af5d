;; SPDX-License-Identifier: Apache-2.0
;; From tick 150 on: a call-free infinite loop, (loop (br 0)). Only roz's
;; fuel charged by work done (cmake/wasm3/02-metering.patch) stops it.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.ge_s (local.get $tick) (i64.const 150))
      (then (loop $forever (br $forever))))))
