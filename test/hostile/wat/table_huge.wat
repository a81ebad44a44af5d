;; SPDX-License-Identifier: Apache-2.0
;; Hostile: declares a table of 1,000,000 function references and calls
;; through it. roz refuses tables above ROZ_CFG_WASM_MAX_TABLE_ENTRIES at load.
(module
  (type $v (func))
  (table 1000000 funcref)
  (func $nop)
  (elem (i32.const 0) $nop)
  (func (export "process") (param $tick i64)
    (call_indirect (type $v) (i32.const 0))))
