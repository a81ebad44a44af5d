;; SPDX-License-Identifier: Apache-2.0
;; Tries to grow its memory every tick and records the result as a metric:
;; memory is fixed, so every grow returns -1 and the controller runs on.
(module
  (import "telemetry" "emit_metric" (func $metric (param f64)))
  (memory 1)
  (func (export "process") (param $tick i64)
    (call $metric (f64.convert_i32_s (memory.grow (i32.const 1))))))
