;; SPDX-License-Identifier: Apache-2.0
;; From tick 150 on, reads the wall clock 20000 times per tick: with a test
;; clock that advances on every read this overruns any budget below 20000
;; clock steps, deterministically.
(module
  (import "timing" "now_ns" (func $now (result i64)))
  (func (export "process") (param $tick i64)
    (local $i i32)
    (if (i64.ge_s (local.get $tick) (i64.const 150))
      (then
        (loop $again
          (drop (call $now))
          (local.set $i (i32.add (local.get $i) (i32.const 1)))
          (br_if $again (i32.lt_u (local.get $i) (i32.const 20000))))))))
