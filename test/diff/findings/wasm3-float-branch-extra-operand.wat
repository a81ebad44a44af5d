;; SPDX-License-Identifier: Apache-2.0
;; Finding of the differential test (fuzz/diff/diff_run.py), minimised by hand
;; from generated seeds (about half of wasmgen's modules before the
;; allowlist). Class "float-branch" of fuzz/diff/allowlist.txt (wasm3 #465).
;;
;; A branch that carries an f64 (or f32) value out of a block while another
;; operand sits below the value on the block's own stack crashes roz's wasm3
;; 0.5.0: SEGV in op_CopySlot_64 (m3_exec.h) when $f runs. The same with an
;; i32/i64 value, or with the extra operand outside the block, is fine.
;; wasm-interp: f() => f64:5.000000 (both exports).
;; Run: wat2wasm this.wat -o f.wasm && build/test/diff/roz_wasm_run f.wasm
(module
  (memory 1 1)
  (func (export "f") (result f64)
    (f64.add (f64.const 1)
      (block $b (result f64)
        (i32.const 1)                 ;; the extra operand
        (br $b (f64.const 4)))))
  (func (export "g") (result f64)
    (block $b (result f64)
      (i64.const 1) (f64.const 5) (i32.const 1) br_if $b drop drop (f64.const 9)))
  (func (export "process") (param i64)))
