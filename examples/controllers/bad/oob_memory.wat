;; SPDX-License-Identifier: Apache-2.0
;; Reads far outside its one page of memory at tick 150.
(module
  (memory 1)
  (func (export "process") (param $tick i64)
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then (drop (i64.load (i32.const 0x7ffffff0)))))))
