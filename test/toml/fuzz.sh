#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
#
# A longer fuzz run of roz's TOML reader and robot.toml loader:
#
#   test/toml/fuzz.sh [SECONDS]      (default 600; 0 = until Ctrl-C)
#
# Builds fuzz_toml in the clang ASan+UBSan build (build-asan, the one of
# `make test-asan`) and runs it with the shared vectors as seeds. New inputs
# go to build-asan/test/toml/fuzz_toml_corpus/, crashes to
# build-asan/test/toml/fuzz_toml_artifacts/ (reproduce one with
# `build-asan/test/toml/fuzz_toml <file>`). Set BUILD to use another folder.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
seconds=${1:-600}
build=${BUILD:-build}-asan
cd "$root"
make --no-print-directory "$build/build.ninja"
cmake --build "$build" --target fuzz_toml
out=$build/test/toml
mkdir -p "$out/fuzz_toml_corpus" "$out/fuzz_toml_artifacts"
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
exec "$out/fuzz_toml" -max_total_time="$seconds" -timeout=10 -print_final_stats=1 \
    -dict=test/toml/toml.dict -artifact_prefix="$out/fuzz_toml_artifacts/" \
    "$out/fuzz_toml_corpus" test/vectors/good test/vectors/bad manifests
