;; SPDX-License-Identifier: Apache-2.0
;; A controller declaring two pages of linear memory: a host's roz loads it
;; (16 pages at most by default), a firmware configured for one page
;; (ROZ_CFG_WASM_MAX_PAGES 1) refuses it, and so must rozaot when it
;; compiles the controller for that firmware (test_aot_target_limits).
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (memory 2)
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.load (i32.const 65536))))))
