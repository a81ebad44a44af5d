;; SPDX-License-Identifier: Apache-2.0
;; Hostile: every tick asks memory.grow for 0xffffffff pages, a count that
;; wraps a 32-bit page total, and reports the result as command 0 (0.1 per
;; page, so a refusal, -1, reads -0.1) and the memory size after it as
;; command 1 (0.1 per page). A correct engine refuses the grow and keeps its
;; two pages: -0.1 and 0.2 every tick.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (memory 2)
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0)
      (f64.mul (f64.convert_i32_s (memory.grow (i32.const -1))) (f64.const 0.1))))
    (drop (call $set (i32.const 1)
      (f64.mul (f64.convert_i32_s (memory.size)) (f64.const 0.1))))))
