;; SPDX-License-Identifier: Apache-2.0
;; Recurses without end at tick 150: wasm3's stack check traps it.
(module
  (func $down (param $n i64) (result i64)
    (i64.add (call $down (i64.add (local.get $n) (i64.const 1))) (i64.const 1)))
  (func (export "process") (param $tick i64)
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then (drop (call $down (i64.const 0)))))))
