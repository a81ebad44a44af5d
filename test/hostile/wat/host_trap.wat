;; SPDX-License-Identifier: Apache-2.0
;; Hostile: calls every kind of roz import with bad arguments 20 calls deep
;; (bad indices, NaN, 300 metrics into a 256-entry ring, an e-stop), then on
;; odd ticks traps right after a host call returns. Checked by
;; test_wasm3_ub.c: every import returns (none can trap), the trap is the
;; wasm's own, the instance runs again after it and frees cleanly.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (import "command" "limit_min" (func $lmin (param i32) (result f64)))
  (import "state" "get" (func $get (param i32) (result f64)))
  (import "safety" "request_estop" (func $estop))
  (import "telemetry" "emit_metric" (func $emit (param f64)))
  (func $deep (param $n i32) (param $tick i64)
    (local $i i32)
    (if (local.get $n)
      (then
        (call $deep (i32.sub (local.get $n) (i32.const 1)) (local.get $tick))
        (return)))
    (call $emit (f64.convert_i32_s (call $set (i32.const -1) (f64.const 0.5))))
    (call $emit (f64.convert_i32_s (call $set (i32.const 0) (f64.const nan))))
    (call $emit (call $get (i32.const 0x7fffffff)))
    (call $emit (call $lmin (i32.const -2147483648)))
    (call $estop)
    (loop $more
      (call $emit (f64.convert_i32_u (local.get $i)))
      (local.set $i (i32.add (local.get $i) (i32.const 1)))
      (br_if $more (i32.lt_u (local.get $i) (i32.const 300))))
    (if (i64.eq (i64.and (local.get $tick) (i64.const 1)) (i64.const 1))
      (then
        (call $emit (f64.const 1))
        (unreachable))))
  (func (export "process") (param $tick i64)
    (call $deep (i32.const 20) (local.get $tick))))
