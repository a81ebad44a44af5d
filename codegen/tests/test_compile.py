# SPDX-License-Identifier: Apache-2.0
"""Generated C compiles warning-free, and holds what --json says.

Needs a C compiler (cc, gcc or clang); skipped without one. The roz headers
come from lib/include; roz/features.h, which CMake generates, is a stub here.
"""

import json
import os
import shutil
import subprocess

import pytest

from conftest import DATA, LIB_INCLUDE, MY_ARM, REPO, builtin_manifests, run_rozgen

JSON_PRINTER = REPO / "tools" / "manifest_json" / "json.c"

FLAGS = ["-std=c11", "-Wall", "-Wextra", "-Werror", "-Wundef", "-pedantic"]
FEATURES_STUB = """/* SPDX-License-Identifier: Apache-2.0 */
/* Stand-in for the roz/features.h that CMake generates from features.h.in. */
#ifndef ROZ_FEATURES_H
#define ROZ_FEATURES_H
#define ROZ_VERSION_STRING "0.0.0-test"
#define ROZ_VERSION_MAJOR 0
#define ROZ_VERSION_MINOR 0
#define ROZ_VERSION_PATCH 0
#define ROZ_HAS_BUILTIN_MANIFESTS 1
#define ROZ_HAS_WASM3 0
#endif
"""


def _compilers() -> list[str]:
    found, seen = [], set()
    for name in ("cc", "gcc", "clang"):
        path = shutil.which(name)
        if path and os.path.realpath(path) not in seen:
            seen.add(os.path.realpath(path))
            found.append(name)
    return found


COMPILERS = _compilers()
pytestmark = pytest.mark.skipif(not COMPILERS, reason="no C compiler")
INPUTS = [*builtin_manifests(), MY_ARM, DATA / "tricky.toml"]


@pytest.fixture(scope="module")
def build(tmp_path_factory):
    """(work dir, output dir) with every test manifest generated."""
    root = tmp_path_factory.mktemp("compile")
    (root / "include" / "roz").mkdir(parents=True)
    (root / "include" / "roz" / "features.h").write_text(FEATURES_STUB)
    out = root / "out"
    result = run_rozgen("-o", out, "--registry", "--source-root", REPO, *INPUTS)
    assert result.returncode == 0, result.stderr
    return root, out


def _includes(root, out) -> list[str]:
    return [f"-I{LIB_INCLUDE}", f"-I{root / 'include'}", f"-I{out}"]


def _compile(compiler, args):
    result = subprocess.run([compiler, *args], capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr == "", result.stderr
    return result


@pytest.mark.parametrize("compiler", COMPILERS)
def test_generated_c_compiles(build, compiler):
    root, out = build
    sources = sorted(out.glob("*.c"))
    assert len(sources) == len(INPUTS) + 1
    for source in sources:
        _compile(compiler, [*FLAGS, *_includes(root, out), "-c", str(source),
                            "-o", str(root / f"{source.stem}.{compiler}.o")])


@pytest.mark.parametrize("compiler", COMPILERS)
def test_fall_rule_needs_fall_detection(build, compiler):
    """A table with a fall rule does not compile against a roz configured
    without fall detection (ROZ_CFG_FALL 0), the error naming the option;
    one without a rule does."""
    root, out = build
    with_rule = 0
    for source in sorted(out.glob("*_manifest.c")):
        has_rule = "roz_fall_rule_t" in source.read_text()
        result = subprocess.run([compiler, *FLAGS, *_includes(root, out), "-DROZ_CFG_FALL=0",
                                 "-fsyntax-only", str(source)], capture_output=True, text=True)
        if has_rule:
            with_rule += 1
            assert result.returncode != 0, source.name
            assert "ROZ_CFG_FALL 0" in result.stderr and "[manifest.fall]" in result.stderr
        else:
            assert result.returncode == 0 and result.stderr == "", result.stderr
    assert 0 < with_rule < len(INPUTS)


@pytest.mark.parametrize("compiler", COMPILERS)
def test_channel_headers_are_freestanding(build, compiler, tmp_path):
    _, out = build
    unit = tmp_path / "controller.c"
    lines = [f'#include "{h.name}"' for h in sorted(out.glob("*_channels.h"))]
    for h in sorted(out.glob("*_channels.h")):
        prefix = "ROZ_" + h.name[:-len("_channels.h")].upper()
        lines.append(f"int {prefix.lower()}_set[{prefix}_N_COMMANDS + {prefix}_N_STATES "
                     f"+ ({prefix}_CONTROL_RATE_HZ > 0)];")
    unit.write_text("\n".join(lines) + "\n")
    _compile(compiler, [*FLAGS, "-ffreestanding", "-nostdinc", f"-I{out}", "-fsyntax-only",
                        str(unit)])


def test_channel_headers_for_wasm32(build, tmp_path):
    clang = shutil.which("clang")
    if clang is None or "wasm32" not in subprocess.run(
            [clang, "--print-targets"], capture_output=True, text=True).stdout:
        pytest.skip("no clang with the wasm32 target")
    _, out = build
    unit = tmp_path / "controller.c"
    unit.write_text('#include "ur5_channels.h"\n'
                    "int channel(void) { return ROZ_UR5_CMD_WRIST_3_JOINT_VELOCITY; }\n")
    _compile(clang, ["--target=wasm32", "-nostdlib", *FLAGS, f"-I{out}", "-fsyntax-only",
                     str(unit)])


def test_c_tables_print_the_same_json(build):
    """A C program walking the tables prints exactly `rozgen --json`, and
    computes the interface hash `rozgen --identity` prints."""
    root, out = build
    exe = root / "print_manifest_json"
    # the JSON printer of tools/manifest_json, and the core's interface names
    _compile(COMPILERS[0], [*FLAGS, *_includes(root, out), f"-I{JSON_PRINTER.parent}",
                            "-o", str(exe), str(DATA / "print_manifest_json.c"),
                            str(JSON_PRINTER), str(REPO / "lib" / "src" / "manifest.c"),
                            str(REPO / "lib" / "src" / "identity.c"),
                            str(REPO / "lib" / "src" / "operator.c"),
                            str(REPO / "lib" / "src" / "format.c"),
                            *map(str, sorted(out.glob("*.c"))), "-lm"])
    registry = subprocess.run([exe, "--registry"], capture_output=True, text=True)
    assert registry.returncode == 0
    ids = registry.stdout.split()
    assert ids == sorted(ids) and len(ids) == len(INPUTS)
    for toml in INPUTS:
        expected = run_rozgen("--json", toml).stdout
        rid = json.loads(expected)["robot_id"]
        printed = subprocess.run([exe, rid], capture_output=True, text=True)
        assert printed.returncode == 0
        assert printed.stdout == expected, rid
        identity = subprocess.run([exe, "--identity", rid], capture_output=True, text=True)
        assert identity.returncode == 0
        assert identity.stdout == run_rozgen("--identity", toml).stdout, rid
