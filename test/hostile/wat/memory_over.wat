;; SPDX-License-Identifier: Apache-2.0
;; Hostile: declares 17 pages, one more than the default
;; ROZ_CFG_WASM_MAX_PAGES (16).
(module
  (memory 17)
  (func (export "process") (param $tick i64)))
