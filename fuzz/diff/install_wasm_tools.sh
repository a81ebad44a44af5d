#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
#
# Installs wasm-tools (for `wasm-tools smith`, a second generator of modules
# for the long differential run and fuzz_controller's seeds) into
# .cache/wasm-tools, pinned, from the crate registry, with only the features
# the long run uses (smith, validate, print). Idempotent: a second run
# finds the binary and does nothing. Optional: without cargo it says so and
# exits 1; the long run then goes on with roz's own generator only.
# Not part of `make test`. Compiling takes several minutes on 2 cores.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
version=1.263.0
dest=$root/.cache/wasm-tools
bin=$dest/bin/wasm-tools

if [ -x "$bin" ] && [ "$("$bin" --version 2>/dev/null | cut -d' ' -f2)" = "$version" ]; then
    echo "$bin"
    exit 0
fi
if ! command -v cargo >/dev/null 2>&1; then
    echo "install_wasm_tools: no cargo on PATH; install Rust (rustup or Debian's cargo) to use wasm-tools smith" >&2
    exit 1
fi
echo "install_wasm_tools: building wasm-tools $version into $dest (takes minutes)" >&2
mkdir -p "$dest"
CARGO_TARGET_DIR=$dest/target cargo install wasm-tools --version "$version" --locked \
    --no-default-features --features smith,validate,print,parse --root "$dest" >&2
rm -rf "$dest/target"
echo "$bin"
