;; SPDX-License-Identifier: Apache-2.0
;; Hostile: at tick 150 loads 8 bytes at address 0xfffffff8 plus a static
;; offset of 0xffffffff: an effective address beyond 4 GiB, which an engine
;; that adds in 32 bits would wrap into memory.
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (memory 1)
  (func (export "process") (param $tick i64)
    (drop (call $set (i32.const 0) (f64.const 0.3)))
    (if (i64.eq (local.get $tick) (i64.const 150))
      (then (drop (i64.load offset=0xffffffff (i32.const 0xfffffff8)))))))
