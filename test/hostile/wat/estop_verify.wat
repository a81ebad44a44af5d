;; SPDX-License-Identifier: Apache-2.0
;; Hostile: requests an e-stop at tick 42, inside verification.
(module
  (import "safety" "request_estop" (func $estop))
  (func (export "process") (param $tick i64)
    (if (i64.eq (local.get $tick) (i64.const 42)) (then (call $estop)))))
