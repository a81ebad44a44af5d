;; SPDX-License-Identifier: Apache-2.0
;; A controller declaring a memory of no pages: both engines load it, and
;; its one access (at tick 1) traps as out of bounds on both
;; (test_aot_zero_pages).
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (memory 0)
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.5)))
    (if (i64.eq (local.get $tick) (i64.const 1))
      (then (drop (i32.load (i32.const 0)))))))
