;; SPDX-License-Identifier: Apache-2.0
;; Imports its memory: refused at load.
(module
  (import "env" "memory" (memory 1))
  (func (export "process") (param $tick i64)))
