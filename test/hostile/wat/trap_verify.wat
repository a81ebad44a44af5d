;; SPDX-License-Identifier: Apache-2.0
;; Hostile: reaches `unreachable` at tick 5, inside verification.
(module
  (func (export "process") (param $tick i64)
    (if (i64.eq (local.get $tick) (i64.const 5)) (then unreachable))))
