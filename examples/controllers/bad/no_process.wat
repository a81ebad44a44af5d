;; SPDX-License-Identifier: Apache-2.0
;; Exports "step" instead of "process": refused at load.
(module
  (func (export "step") (param $tick i64)))
