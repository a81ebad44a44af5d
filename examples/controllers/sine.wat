;; SPDX-License-Identifier: Apache-2.0
;; Sine wave on control time, in WebAssembly text: command i =
;; A * sin(2*pi*0.5*t + i*pi/3), A half the channel's upper limit, t from
;; timing.sim_time_ns. The same behaviour as sine.c.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (import "command" "count" (func $count (result i32)))
  (import "command" "limit_max" (func $max (param i32) (result f64)))
  (import "math" "sin" (func $sin (param f64) (result f64)))
  (import "timing" "sim_time_ns" (func $now (result i64)))
  (func (export "process") (param $tick i64)
    (local $i i32) (local $n i32) (local $t f64)
    (local.set $t (f64.mul (f64.convert_i64_s (call $now)) (f64.const 1e-9)))
    (local.set $n (call $count))
    (block $done
      (loop $next
        (br_if $done (i32.ge_s (local.get $i) (local.get $n)))
        (drop (call $set (local.get $i)
          (f64.mul
            (f64.mul (f64.const 0.5) (call $max (local.get $i)))
            (call $sin
              (f64.add
                (f64.mul (f64.const 3.141592653589793) (local.get $t))  ;; 2*pi*0.5*t
                (f64.mul (f64.convert_i32_s (local.get $i))
                         (f64.const 1.0471975511965976)))))))          ;; i*pi/3
        (local.set $i (i32.add (local.get $i) (i32.const 1)))
        (br $next)))))
