;; SPDX-License-Identifier: Apache-2.0
;; Hostile: a table of 4 entries with an element segment written at entry
;; 99999. wasm3 ignores the declared table size and would grow its table to
;; 100,000 entries; roz refuses a segment that does not fit the table.
(module
  (type $v (func))
  (table 4 funcref)
  (func $nop)
  (elem (i32.const 99999) $nop)
  (func (export "process") (param $tick i64)
    (call_indirect (type $v) (i32.const 0))))
