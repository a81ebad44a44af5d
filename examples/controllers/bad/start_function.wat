;; SPDX-License-Identifier: Apache-2.0
;; Has a start function: refused at load.
(module
  (func $init)
  (start $init)
  (func (export "process") (param $tick i64)))
