;; SPDX-License-Identifier: Apache-2.0
;; Hostile: drives joint 0 at 0.3 rad/s; at tick 150 stores 4 bytes at
;; 0xfffffffc, the top of the 32-bit address space, far past its one page.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (memory 1)
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then (i32.store (i32.const 0xfffffffc) (i32.const 0x0badf00d))))))
