#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
#
# Installs everything roz needs on a Debian 12 machine, idempotently:
#   1. Debian packages (only those missing; needs root then), the Cortex-M
#      cross compiler and QEMU among them,
#   2. a Python virtual environment in .venv with the pinned, hash-checked
#      tools of tools/requirements.txt and rozgen itself,
#   3. wasm3's C core: the pywasm3 0.5.0 source distribution, fetched with pip
#      into .cache/ and checked against its sha256 (CMake checks it again
#      before it extracts it into the build tree),
#   4. the wheels of rozgen's and the installed tools' run-time dependencies
#      (codegen/requirements.txt, tools/requirements-run.txt, hash-checked) in
#      .cache/wheels, which `cmake --install` installs beside rozgen without a
#      network,
#   5. the runner of toml-test, the official TOML test suite (a Go program),
#      built into .cache/go/bin from the module pinned in tools/toml-test/,
#   6. the crates of the strict MCAP checker (test/record/mcap_strict),
#      pinned by its Cargo.lock, fetched so the build compiles it offline,
#   7. with --ray only (make test, make campaign-ray): Ray, roz-campaign's engine
#      for clusters (tools/requirements-ray.txt, hash-checked; some 80 MB, so
#      not in the default set-up).
# Run from anywhere; a second run changes nothing and takes a second or two.
set -euo pipefail
with_ray=0
for arg in "$@"; do
    case $arg in
        --ray) with_ray=1 ;;
        *) printf 'setup: unknown option %s (known: --ray)\n' "$arg" >&2; exit 2 ;;
    esac
done

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

say() { printf 'setup: %s\n' "$*"; }
die() { printf 'setup: error: %s\n' "$*" >&2; exit 1; }

# ---- 1. Debian packages ---------------------------------------------------
# clang + lld build wasm32 controllers and the fuzz targets, wabt assembles
# .wat, cyclonedds-* serve the DDS ports, libcmocka-dev the C tests, g++ the
# test that roz's public headers compile as C++, iproute2 the loopback of the
# DDS tests' network namespace (test/run_netns.sh); gcc-arm-none-eabi with
# newlib (newlib-nano) cross-builds the Cortex-M firmware images and
# qemu-system-arm boots them (test/firmware/, make firmware); libzstd-dev
# compresses recordings' chunks (host/record/); libegl1 with Mesa's EGL and
# drivers renders MuJoCo's frames offscreen (tools/render_frames.py, make
# demo); rustc with libstd-rust-dev-wasm32 (its wasm32-unknown-unknown
# target) builds the Rust controllers (sdk/rust, cmake/RozRust.cmake picks
# the rustc on PATH that has the target, so a rustup one first on PATH
# without it does no harm), and cargo beside it runs docs/rust.md's cargo
# recipe. Without
# recommends: gcc-arm-none-eabi would pull in a 1.5 GB C++ library.
# chromium (headless) shows the campaign report in a real browser in its
# test (test/campaign/test_report_browser.py).
# gcc-aarch64-linux-gnu cross-builds roz for aarch64 Linux (a robot's own
# computer; cmake/toolchains/aarch64-linux-gnu.cmake) against the arm64
# packages of Debian's multiarch archive (arm64_packages below), and
# qemu-user runs its tests (test/aarch64/).
apt_packages=(
    ca-certificates cmake ninja-build make gcc g++ libc6-dev pkg-config patch
    clang lld llvm libclang-rt-14-dev wabt rustc libstd-rust-dev-wasm32 cargo
    libcmocka-dev cyclonedds-dev cyclonedds-tools iproute2 libzstd-dev
    gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm
    python3 python3-venv python3-pip
    libegl1 libegl-mesa0 libgl1-mesa-dri chromium
)
arm64_packages=()
# On an arm64 machine (the robot's computer itself, docs/robot-computer.md)
# the build is native and test/aarch64/ is not built: there is nothing to
# cross-build nor emulate, and gcc-aarch64-linux-gnu is only a name gcc
# provides, which dpkg-query never reports installed.
if [ "$(dpkg --print-architecture)" != arm64 ]; then
    apt_packages+=(gcc-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user)
    arm64_packages=(cyclonedds-dev:arm64 libcmocka-dev:arm64 libzstd-dev:arm64)
fi
missing=()
for p in "${apt_packages[@]}" "${arm64_packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
        missing+=("$p")
    fi
done
if ((${#missing[@]})); then
    [ "$(id -u)" = 0 ] || die "missing Debian packages (${missing[*]}); run as root or install them: apt-get install ${missing[*]}"
    say "installing Debian packages: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    if ((${#arm64_packages[@]})) && ! dpkg --print-foreign-architectures | grep -qx arm64; then
        say "adding the arm64 architecture (multiarch) for the aarch64 cross-build"
        dpkg --add-architecture arm64
    fi
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# ---- 2. Python virtual environment ------------------------------------------
# Debian's own interpreter, so the venv does not depend on whatever else is on
# PATH; PYTHON overrides it.
python=${PYTHON:-}
if [ -z "$python" ]; then
    if [ -x /usr/bin/python3 ]; then python=/usr/bin/python3; else python=python3; fi
fi
venv=.venv
if [ ! -x "$venv/bin/python" ]; then
    say "creating the Python virtual environment in $venv"
    "$python" -m venv "$venv"
fi
# the stamp names this checkout too: rozgen is installed editable, so a venv
# that another checkout installed into points at that checkout's codegen
stamp_want=$( (cat tools/requirements.txt codegen/pyproject.toml; pwd -P) | sha256sum | cut -d' ' -f1)
stamp_file=$venv/.roz-installed
if [ "$(cat "$stamp_file" 2>/dev/null)" != "$stamp_want" ]; then
    say "installing pinned Python packages (hash-checked)"
    "$venv/bin/python" -m pip install -q --disable-pip-version-check \
        --require-hashes -r tools/requirements.txt
    say "installing rozgen"
    "$venv/bin/python" -m pip install -q --disable-pip-version-check \
        --no-build-isolation --no-deps --editable codegen
    echo "$stamp_want" > "$stamp_file"
fi

# ---- 3. wasm3 sources ---------------------------------------------------------
wasm3_sha256=5a47c8a39f7f6ae71b3316b2e5d86c9d0db6e771a65f09a86e4d4aa3a19aefcc
sdist=.cache/pywasm3-0.5.0.tar.gz
check_sdist() { [ "$(sha256sum "$sdist" | cut -d' ' -f1)" = "$wasm3_sha256" ]; }
if [ -f "$sdist" ] && ! check_sdist; then
    die "$sdist has the wrong sha256 (want $wasm3_sha256); delete it to fetch it again"
fi
if [ ! -f "$sdist" ]; then
    say "fetching wasm3 0.5.0 sources (pywasm3 source distribution)"
    mkdir -p .cache
    req=$(mktemp)
    trap 'rm -f "$req"' EXIT
    echo "pywasm3==0.5.0 --hash=sha256:$wasm3_sha256" > "$req"
    "$venv/bin/python" -m pip download -q --disable-pip-version-check \
        --no-deps --no-binary :all: --no-build-isolation --require-hashes -r "$req" -d .cache
    check_sdist || die "$sdist: sha256 mismatch (want $wasm3_sha256)"
fi

# ---- 4. rozgen's and the tools' dependencies, for the installed package -------
# `cmake --install` puts rozgen, roz-plot, roz-recording and these wheels in
# <prefix>/lib/roz/python (cmake/RozInstallRozgen.cmake); having them here
# lets it work offline.
wheels=.cache/wheels
wheels_want=$(cat codegen/requirements.txt codegen/requirements-nn.txt tools/requirements-run.txt \
               | sha256sum | cut -d' ' -f1)
wheels_stamp=$wheels/.roz-downloaded
if [ "$(cat "$wheels_stamp" 2>/dev/null)" != "$wheels_want" ]; then
    say "fetching the wheels of rozgen's dependencies into $wheels"
    mkdir -p "$wheels"
    "$venv/bin/python" -m pip download -q --disable-pip-version-check \
        --no-deps --only-binary :all: --require-hashes -r codegen/requirements.txt \
        -r codegen/requirements-nn.txt -r tools/requirements-run.txt -d "$wheels"
    echo "$wheels_want" > "$wheels_stamp"
fi

# ---- 5. toml-test -------------------------------------------------------------
# roz's C TOML reader is checked against toml-test v1.6.0 (test/toml/). Its
# runner is built with Go from tools/toml-test/go.mod, which pins toml-test
# and, through go.sum, every module it uses; everything Go fetches or builds
# stays in .cache/go. Go 1.19 or later does (Debian 12's golang-go is 1.19).
# Without Go the toml-test ctest is skipped, nothing else needs it.
toml_test=.cache/go/bin/toml-test
toml_test_stamp=.cache/go/.toml-test-installed
toml_test_want=$(cat tools/toml-test/go.mod tools/toml-test/go.sum | sha256sum | cut -d' ' -f1)
go_ok() { # go1.19 or later?
    local v
    v=$("$1" env GOVERSION 2>/dev/null) || return 1
    v=${v#go}
    [ "${v%%.*}" -gt 1 ] || { v=${v#1.}; [ "${v%%[.a-z]*}" -ge 19 ]; }
}
if [ ! -x "$toml_test" ] || [ "$(cat "$toml_test_stamp" 2>/dev/null)" != "$toml_test_want" ]; then
    go_bin=$(command -v go || true)
    if [ -z "$go_bin" ] && [ "$(id -u)" = 0 ]; then
        say "installing Debian's Go (golang-go) to build toml-test"
        export DEBIAN_FRONTEND=noninteractive
        { apt-get update -qq && apt-get install -y -qq --no-install-recommends golang-go; } \
            >/dev/null || true
        go_bin=$(command -v go || true)
    fi
    if [ -z "$go_bin" ]; then
        say "warning: no Go toolchain; toml-test (the TOML suite ctest) will be skipped." \
            "Install Go 1.19 or later (Debian: apt-get install golang-go) and run this again."
    elif ! go_ok "$go_bin"; then
        say "warning: $("$go_bin" version) is too old for toml-test v1.6.0 (needs go1.19" \
            "or later); the TOML suite ctest will be skipped."
    else
        say "building toml-test v1.6.0 with $("$go_bin" env GOVERSION) into .cache/go/bin"
        mkdir -p .cache/go
        # -modcacherw: keep the module cache deletable (rm -rf .cache)
        (cd tools/toml-test && env GOTOOLCHAIN=local GOFLAGS="-mod=readonly -modcacherw" \
            GOBIN="$root/.cache/go/bin" GOPATH="$root/.cache/go/path" \
            GOMODCACHE="$root/.cache/go/mod" GOCACHE="$root/.cache/go/build" \
            "$go_bin" install github.com/toml-lang/toml-test/cmd/toml-test) ||
            die "building toml-test failed (see above)"
        echo "$toml_test_want" > "$toml_test_stamp"
    fi
fi
# ---- 6. the strict MCAP checker's crates ----------------------------------------
# Every recording the tests write is read by the mcap crate's strict reader
# (test/record/mcap_strict). Its crates come from crates.io, pinned by its
# Cargo.lock; fetched here (cargo's own cache), the test build compiles them
# with --offline. Without cargo those checks are skipped.
strict=test/record/mcap_strict
strict_stamp=.cache/.mcap-strict-fetched
strict_want=$(sha256sum "$strict/Cargo.lock" | cut -d' ' -f1)
if [ "$(cat "$strict_stamp" 2>/dev/null)" != "$strict_want" ]; then
    cargo_bin=$(command -v cargo || echo "$HOME/.cargo/bin/cargo")
    # its Cargo.lock (version 4) needs cargo 1.78 or later: Debian 12's is
    # 1.65 (installed above for docs/rust.md), rustup's is newer
    cargo_minor() { "$1" --version 2>/dev/null | sed -n 's/^cargo 1\.\([0-9]*\).*/\1/p'; }
    if [ -x "$HOME/.cargo/bin/cargo" ] && [ "$(cargo_minor "$cargo_bin")" -lt 78 ] 2>/dev/null; then
        cargo_bin=$HOME/.cargo/bin/cargo
    fi
    if [ ! -x "$cargo_bin" ] || ! [ "$(cargo_minor "$cargo_bin")" -ge 78 ] 2>/dev/null; then
        say "warning: no cargo 1.78 or later; the strict MCAP checks of the recording tests" \
            "will be skipped. Install Rust (rustup.rs) and run this again."
    else
        say "fetching the strict MCAP checker's crates (cargo fetch --locked)"
        (cd "$strict" && "$cargo_bin" fetch --locked -q) ||
            die "cargo fetch failed for $strict (see above)"
        mkdir -p .cache
        echo "$strict_want" > "$strict_stamp"
    fi
fi
# ---- 7. Ray (--ray) -------------------------------------------------------------
# roz-campaign --ray runs a campaign on a Ray cluster (docs/campaigns.md); its
# test starts a local cluster of two nodes. --no-deps: the file lists all.
if [ "$with_ray" = 1 ]; then
    ray_want=$(sha256sum tools/requirements-ray.txt | cut -d' ' -f1)
    ray_stamp=$venv/.roz-ray-installed
    if [ "$(cat "$ray_stamp" 2>/dev/null)" != "$ray_want" ]; then
        say "installing Ray (tools/requirements-ray.txt, hash-checked)"
        "$venv/bin/python" -m pip install -q --disable-pip-version-check --no-deps \
            --require-hashes -r tools/requirements-ray.txt
        echo "$ray_want" > "$ray_stamp"
    fi
fi
say "ready"
