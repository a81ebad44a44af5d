;; SPDX-License-Identifier: Apache-2.0
;; Hostile: declares 65536 pages (4 GiB) of linear memory.
(module
  (memory 65536)
  (func (export "process") (param $tick i64)))
