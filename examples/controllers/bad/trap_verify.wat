;; SPDX-License-Identifier: Apache-2.0
;; Traps at tick 3: verification must refuse it.
(module
  (func (export "process") (param $tick i64)
    (if (i64.eq (local.get $tick) (i64.const 3)) (then unreachable))))
