;; SPDX-License-Identifier: Apache-2.0
;; Finding of the differential test (fuzz/diff/diff_run.py; seeds 38, 48, 93
;; among the first 100), minimised by hand. Class "stack-overflow-heap" of
;; fuzz/diff/allowlist.txt (wasm3 #477, call arguments past the value stack).
;;
;; $r recurses with 20 i64 parameters until wasm3's value stack (64 KiB, as
;; roz sets it: ROZ_CFG_WASM_STACK_BYTES) runs out. wasm3 reports
;; "[trap] stack overflow" for deep() but has already written the last
;; call's arguments past the end of the stack: the heap behind it is
;; corrupted, and the next call, after(), crashes (SEGV in
;; GetStackPointerForArgs: the runtime's own fields were overwritten); other
;; seeds abort in free() at exit ("munmap_chunk(): invalid pointer"). With
;; one parameter the trap is clean; with 200 the first call crashes.
;; wasm-interp: deep() => error: call stack exhausted, after() => i32:42,
;; after2() => i32:3.
;; In roz this is a controller that recurses deep with many parameters: the
;; trap faults the controller, but the process's heap is already damaged.
;; Run: wat2wasm this.wat -o s.wasm && build/test/diff/roz_wasm_run s.wasm
(module
  (func $r (param i32) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64) (param i64)  (result i32)
    (if (result i32) (i32.eqz (local.get 0)) (then (i32.const 0))
      (else (i32.add (i32.const 1) (call $r (i32.sub (local.get 0) (i32.const 1)) (local.get 1) (local.get 2) (local.get 3) (local.get 4) (local.get 5) (local.get 6) (local.get 7) (local.get 8) (local.get 9) (local.get 10) (local.get 11) (local.get 12) (local.get 13) (local.get 14) (local.get 15) (local.get 16) (local.get 17) (local.get 18) (local.get 19))))))
  (func (export "deep") (result i32) (call $r (i32.const 100000) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7)))
  (func (export "after") (result i32) (i32.const 42))
  (func (export "after2") (result i32) (call $r (i32.const 3) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7) (i64.const 7)))
  (func (export "process") (param i64)))
