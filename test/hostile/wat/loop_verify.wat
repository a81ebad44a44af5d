;; SPDX-License-Identifier: Apache-2.0
;; Hostile: a call-free endless loop from its very first tick, so it never
;; gets past verification.
(module
  (func (export "process") (param $tick i64)
    (loop $spin (br $spin))))
