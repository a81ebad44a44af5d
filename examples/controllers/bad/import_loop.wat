;; SPDX-License-Identifier: Apache-2.0
;; From tick 150 on: calls an import forever (state.count), never returning.
(module
  (import "state" "count" (func $count (result i32)))
  (func (export "process") (param $tick i64)
    (if (i64.ge_s (local.get $tick) (i64.const 150))
      (then (loop $forever (drop (call $count)) (br $forever))))))
