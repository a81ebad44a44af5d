;; SPDX-License-Identifier: Apache-2.0
;; Constant velocity, in WebAssembly text: every command channel at a fifth
;; of its upper limit. The same behaviour as constant_velocity.c.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (import "command" "count" (func $count (result i32)))
  (import "command" "limit_max" (func $max (param i32) (result f64)))
  (func (export "process") (param $tick i64)
    (local $i i32) (local $n i32)
    (local.set $n (call $count))
    (block $done
      (loop $next
        (br_if $done (i32.ge_s (local.get $i) (local.get $n)))
        (drop (call $set (local.get $i)
                         (f64.mul (f64.const 0.2) (call $max (local.get $i)))))
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $next)))))
