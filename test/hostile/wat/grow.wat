;; SPDX-License-Identifier: Apache-2.0
;; Hostile: every tick calls memory.grow(1) until it is refused (at most
;; 100000 tries) and reports the pages it got as command 0 (0.01 per page);
;; command 1 reports memory.grow(0), the current size, at 0.1 per page.
;; roz fixes memory at its initial size, so the first grow is refused:
;; command 0 stays 0 and command 1 reads 0.1 (one page).
(module
  (import "command" "set" (func $set (param i32 f64) (result i32)))
  (memory 1 65536)
  (func (export "process") (param $tick i64)
    (local $got i32) (local $tries i32)
    (block $refused
      (loop $again
        (br_if $refused (i32.eq (memory.grow (i32.const 1)) (i32.const -1)))
        (local.set $got (i32.add (local.get $got) (i32.const 1)))
        (local.set $tries (i32.add (local.get $tries) (i32.const 1)))
        (br_if $again (i32.lt_u (local.get $tries) (i32.const 100000)))))
    (drop (call $set (i32.const 0)
      (f64.mul (f64.convert_i32_u (local.get $got)) (f64.const 0.01))))
    (drop (call $set (i32.const 1)
      (f64.mul (f64.convert_i32_u (memory.grow (i32.const 0))) (f64.const 0.1))))))
