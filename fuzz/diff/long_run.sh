#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
#
# The long differential run (fuzz/README.md), on demand, never in `make test`:
#   1. roz's generator (wasmgen.py) for SECONDS from a random first seed
#      (ROZ_DIFF_SEED=N picks it), every module through roz's wasm3 and
#      wasm-interp (diff_run.py); every module roz accepts is kept as a seed
#      for fuzz_controller in build/fuzz/diff-corpus;
#   2. unless ROZ_DIFF_SMITH=0: wasm-tools smith (installed by
#      install_wasm_tools.sh into .cache/wasm-tools, pinned; skipped with a
#      note if it cannot be installed) writes SMITH_MODULES modules limited
#      to WebAssembly 1.0 + bulk memory, no imports, exporting process(i64);
#      they go through the same comparison and into the corpus too;
#   3. if the ASan build has it (make test-asan), fuzz_controller fuzzes for
#      SECONDS from that corpus (on top of its own), on both cores.
# Usage: fuzz/diff/long_run.sh [SECONDS]   (default 600 per stage)
# Findings: build/fuzz/diff/findings/ (modules), build-asan/fuzz/controller/artifacts/.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
seconds=${1:-600}
smith_modules=${SMITH_MODULES:-500}
py=.venv/bin/python
runner=build/test/diff/roz_wasm_run
work=build/fuzz/diff
corpus=build/fuzz/diff-corpus
status=0

[ -x "$runner" ] || { echo "long_run: $runner missing: run make build first" >&2; exit 2; }
mkdir -p "$work" "$corpus"
first=${ROZ_DIFF_SEED:-$(( (RANDOM << 15 | RANDOM) + 1000000 ))}
echo "long_run: generated modules from seed $first for ${seconds}s"
"$py" fuzz/diff/diff_run.py --runner "$runner" --seeds "$first:$((first + 100000000))" \
    --seconds "$seconds" --work "$work/gen" --corpus "$corpus" || status=1

if [ "${ROZ_DIFF_SMITH:-1}" != 0 ]; then
    if wt=$(fuzz/diff/install_wasm_tools.sh); then
        sm=$work/smith
        rm -rf "$sm" && mkdir -p "$sm/in"
        # the exports every smith module must have: process(i64), and functions
        # without parameters that both engines call
        printf '%s\n' '(module (func (export "process") (param i64))' \
            '(func (export "e_i32") (result i32) i32.const 0) (func (export "e_i64") (result i64) i64.const 0)' \
            '(func (export "e_f32") (result f32) f32.const 0) (func (export "e_f64") (result f64) f64.const 0)' \
            '(func (export "e_void")))' > "$sm/exports.wat"
        wat2wasm "$sm/exports.wat" -o "$sm/exports.wasm"
        echo "long_run: $smith_modules wasm-tools smith modules"
        for i in $(seq 1 "$smith_modules"); do
            head -c 4096 /dev/urandom > "$sm/seed.bin"
            "$wt" smith "$sm/seed.bin" -o "$sm/in/smith$i.wasm" \
                --exports "$sm/exports.wasm" --max-imports 0 --max-memories 1 \
                --max-tables 1 --max-memory32-bytes 1048576 --min-funcs 1 \
                --canonicalize-nans true --ensure-termination \
                --bulk-memory-enabled true --reference-types-enabled false \
                --multi-value-enabled false --simd-enabled false --relaxed-simd-enabled false \
                --saturating-float-to-int-enabled true --sign-extension-ops-enabled true \
                --tail-call-enabled false --threads-enabled false --exceptions-enabled false \
                --gc-enabled false --custom-page-sizes-enabled false --memory64-enabled false \
                --wide-arithmetic-enabled false --extended-const-enabled false \
                --allow-start-export false 2>/dev/null || rm -f "$sm/in/smith$i.wasm"
        done
        # roz refuses some smith modules for its own limits (e.g. a table
        # export, data beyond roz's pages): skipped, counted, not findings
        "$py" fuzz/diff/diff_run.py --runner "$runner" --seeds 1:0 --modules "$sm/in" \
            --work "$sm/out" --corpus "$corpus" || status=1
    else
        echo "long_run: wasm-tools not available; smith stage skipped (see install_wasm_tools.sh)"
    fi
fi

fuzzer=build-asan/fuzz/fuzz_controller
if [ -x "$fuzzer" ]; then
    echo "long_run: fuzz_controller for ${seconds}s from $(ls "$corpus" | wc -l) generated seeds"
    mkdir -p build-asan/fuzz/controller/corpus build-asan/fuzz/controller/artifacts
    "$fuzzer" -fork=2 -ignore_crashes=1 -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
        -artifact_prefix=build-asan/fuzz/controller/artifacts/ \
        build-asan/fuzz/controller/corpus "$corpus" || status=1
else
    echo "long_run: $fuzzer missing (make test-asan builds it); fuzz stage skipped"
fi
exit $status
