;; SPDX-License-Identifier: Apache-2.0
;; Exports process(i32): refused at load.
(module
  (func (export "process") (param $tick i32)))
