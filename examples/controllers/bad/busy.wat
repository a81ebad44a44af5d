;; SPDX-License-Identifier: Apache-2.0
;; Slow but finite: every tick counts to 1000 in a call-free loop, so every
;; tick uses the same fuel. The budget tests set the budget just above and
;; just below it.
(module
  (func (export "process") (param $tick i64)
    (local $i i32)
    (loop $again
      (local.set $i (i32.add (local.get $i) (i32.const 1)))
      (br_if $again (i32.lt_u (local.get $i) (i32.const 1000))))))
