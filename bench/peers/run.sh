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
# The engines run in processes of their own, one after the other, so a
# shared machine's slow spell can fall on one and not the others: they run
# PEER_ROUNDS times (3), roz, wasmtime, wasmi, roz, ..., and each engine's
# figures are those of its median round (by process() p50, metering off;
# bench/peers/median.py), in OUT_DIR/peer-NAME.json.
set -u
build=$(cd "$1" && pwd) out=$(cd "$2" && pwd) rozgen=$3 calls=${4:-20000}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
wasm=$build/examples/controllers/g1_pd.wasm
bulk=$build/examples/controllers/g1_pd_bulk.wasm
# the nn policy (bench/nn/policy.c), built where rozgen.nn ran: every engine
# runs it too, checked against roz's outputs
nn=$build/bench/bench_nn_policy.wasm
roz_nn=() peer_nn=()
if [ -e "$nn" ]; then
    roz_nn=(--nn "$nn" --nn-reference "$out/nn.ref")
    peer_nn=(--wasm-nn "$nn" --expect-nn "$out/nn.ref")
fi

"$rozgen" --json "$root/manifests/unitree_g1.toml" > "$out/g1.json" || exit 1
rounds=${PEER_ROUNDS:-3}
rm -f "$out"/peer-*.json "$out"/peer-*.skipped

# roz's round r; 1 when it failed (peer-roz.skipped says why)
roz_round() {
    if ! "$build/bench/roz_bench_peers_roz" "$wasm" --bulk "$bulk" --calls "$calls" \
            --reference "$out/g1.ref" "${roz_nn[@]}" > "$out/peer-roz.$1.json" \
            2> "$out/peer-roz.err"; then
        echo "roz_bench_peers_roz failed: $(tail -n 1 "$out/peer-roz.err")" > "$out/peer-roz.skipped"
        for p in wasmtime wasmi; do
            echo "no reference outputs from roz to check it against" > "$out/peer-$p.skipped"
        done
        return 1
    fi
}

if ! roz_round 1; then
    exit 0
fi
if ! command -v cargo >/dev/null; then
    for p in wasmtime wasmi; do echo "cargo is not installed" > "$out/peer-$p.skipped"; done
    peers=""
# -j: make bench's JOBS (the machine is shared; wasmtime's first build is long)
elif ! (cd "$here" && cargo build --release --locked -j "${CARGO_JOBS:-2}" 2> "$out/cargo.log"); then
    for p in wasmtime wasmi; do
        echo "cargo build failed: $(grep -m1 '^error' "$out/cargo.log")" > "$out/peer-$p.skipped"
    done
    peers=""
else
    peers="wasmtime wasmi"
fi
for r in $(seq 1 "$rounds"); do
    if [ "$r" -gt 1 ] && ! roz_round "$r"; then
        exit 0
    fi
    for p in $peers; do
        [ -e "$out/peer-$p.skipped" ] && continue
        if ! "$here/target/release/roz-peer-$p" --wasm "$wasm" --wasm-bulk "$bulk" --manifest "$out/g1.json" \
                --expect "$out/g1.ref" "${peer_nn[@]}" --calls "$calls" > "$out/peer-$p.$r.json" \
                2> "$out/peer-$p.err"; then
            tail -n 1 "$out/peer-$p.err" > "$out/peer-$p.skipped"
            cat "$out/peer-$p.skipped" >&2
        fi
    done
done
for p in roz $peers; do
    [ -e "$out/peer-$p.skipped" ] && { rm -f "$out"/peer-"$p".[0-9]*.json; continue; }
    python3 "$here/median.py" "$out/peer-$p.json" "$out"/peer-"$p".[0-9]*.json || exit 1
    rm -f "$out"/peer-"$p".[0-9]*.json
    [ "$p" = roz ] || echo "$p: $(grep -m1 '"checked"' "$out/peer-$p.json" | sed 's/.*: "//; s/",$//')"
done
