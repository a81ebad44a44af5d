;; SPDX-License-Identifier: Apache-2.0
;; Hold: every command at zero. The smallest useful controller, in WAT.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (import "command" "count" (func $count (result i32)))
  (func (export "process") (param $tick i64)
    (local $i i32) (local $n i32)
    (local.set $n (call $count))
    (block $done
      (loop $next
        (br_if $done (i32.ge_s (local.get $i) (local.get $n)))
        (drop (call $set (local.get $i) (f64.const 0)))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $next)))))
