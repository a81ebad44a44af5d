;; SPDX-License-Identifier: Apache-2.0
;; Hostile: drives joint 0 at 0.3 rad/s; at tick 150 recurses without end,
;; with a few locals per frame so the stack fills fast.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (func $deeper (param $n i64) (result i64)
    (local $a i64) (local $b i64) (local $c i64)
    (local.set $a (i64.add (local.get $n) (i64.const 1)))
    (i64.add (call $deeper (local.get $a)) (local.get $a)))
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then (drop (call $deeper (i64.const 0)))))))
