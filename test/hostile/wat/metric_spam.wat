;; SPDX-License-Identifier: Apache-2.0
;; Hostile: emits 4000 metrics every tick (the telemetry ring holds 256)
;; while driving joint 0 at 0.3 rad/s.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (import "telemetry" "emit_metric" (func $metric (param f64)))
  (func (export "process") (param $tick i64)
    (local $i i32)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (loop $spam
      (call $metric (f64.convert_i32_u (local.get $i)))
      (local.set $i (i32.add (local.get $i) (i32.const 1)))
      (br_if $spam (i32.lt_u (local.get $i) (i32.const 4000))))))
