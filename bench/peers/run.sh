#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The peer engines' comparison, as `make bench` runs it:
#   run.sh BUILD_DIR OUT_DIR ROZGEN [CALLS]
# roz's side first (roz_bench_peers_roz: its figures, and the reference
# outputs the peers must match), then the Rust harnesses, built here with
# `cargo build --release --locked` (never by the tests), each checked
# against roz's outputs before it prints a figure. A harness that cannot be
# built, or whose outputs differ, leaves OUT_DIR/peer-NAME.skipped saying
# why; bench/report.py prints that instead of its figures.
set -u
build=$(cd "$1" && pwd) out=$(cd "$2" && pwd) rozgen=$3 calls=${4:-20000}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
wasm=$build/examples/controllers/g1_pd.wasm
bulk=$build/examples/controllers/g1_pd_bulk.wasm

"$rozgen" --json "$root/manifests/unitree_g1.toml" > "$out/g1.json" || exit 1
if ! "$build/bench/roz_bench_peers_roz" "$wasm" --bulk "$bulk" --calls "$calls" --reference "$out/g1.ref" \
        > "$out/peer-roz.json" 2> "$out/peer-roz.err"; then
    echo "roz_bench_peers_roz failed: $(tail -n 1 "$out/peer-roz.err")" > "$out/peer-roz.skipped"
    rm -f "$out/peer-roz.json"
    for p in wasmtime wasmi; do
        echo "no reference outputs from roz to check it against" > "$out/peer-$p.skipped"
    done
    exit 0
fi

if ! command -v cargo >/dev/null; then
    for p in wasmtime wasmi; do echo "cargo is not installed" > "$out/peer-$p.skipped"; done
    exit 0
fi
# -j: make bench's JOBS (the machine is shared; wasmtime's first build is long)
if ! (cd "$here" && cargo build --release --locked -j "${CARGO_JOBS:-2}" 2> "$out/cargo.log"); then
    for p in wasmtime wasmi; do
        echo "cargo build failed: $(grep -m1 '^error' "$out/cargo.log")" > "$out/peer-$p.skipped"
    done
    exit 0
fi
for p in wasmtime wasmi; do
    bin=$here/target/release/roz-peer-$p
    if "$bin" --wasm "$wasm" --wasm-bulk "$bulk" --manifest "$out/g1.json" --expect "$out/g1.ref" --calls "$calls" \
            > "$out/peer-$p.json" 2> "$out/peer-$p.err"; then
        echo "$p: $(grep -m1 '"checked"' "$out/peer-$p.json" | sed 's/.*: "//; s/",$//')"
    else
        echo "$(tail -n 1 "$out/peer-$p.err")" > "$out/peer-$p.skipped"
        rm -f "$out/peer-$p.json"
        cat "$out/peer-$p.skipped" >&2
    fi
done
