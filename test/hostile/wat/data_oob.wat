;; SPDX-License-Identifier: Apache-2.0
;; Hostile: a data segment that runs past the end of its one page of memory.
(module
  (memory 1)
  (data (i32.const 65530) "0123456789abcdef")
  (func (export "process") (param $tick i64)))
