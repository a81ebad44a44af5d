# SPDX-License-Identifier: Apache-2.0
"""Shared paths and helpers of the rozgen tests.

Paths are computed from this file, so the tests run from any checkout and
any working directory.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
CODEGEN = TESTS.parent
REPO = CODEGEN.parent
MANIFESTS = REPO / "manifests"
INVALID = MANIFESTS / "invalid"
GOLDEN = TESTS / "golden"
DATA = TESTS / "data"
MY_ARM = REPO / "examples" / "my_arm" / "robot.toml"
LIB_INCLUDE = REPO / "lib" / "include"

# Test this checkout's package even when it is not installed.
if str(CODEGEN) not in sys.path:
    sys.path.insert(0, str(CODEGEN))

# The rules' one implementation, roz_manifest_json (rozgen.checker): found,
# or built from this checkout, once for the session rather than per run.
from rozgen import checker as _checker  # noqa: E402

os.environ[_checker.ENV] = _checker.find()


def builtin_manifests() -> list[Path]:
    """The built-in manifests: manifests/*.toml, sorted."""
    return sorted(MANIFESTS.glob("*.toml"))


def run_rozgen(*args: object, cwd: Path = REPO) -> subprocess.CompletedProcess:
    """Run ``python -m rozgen`` (this checkout's package) as a user would."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(CODEGEN) + os.pathsep + env.get("PYTHONPATH", "")
    return subprocess.run(
        [sys.executable, "-m", "rozgen", *map(str, args)],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        encoding="utf-8",
        errors="backslashreplace",
    )


@pytest.fixture
def rozgen():
    return run_rozgen
