# SPDX-License-Identifier: Apache-2.0
"""Shared paths and helpers of the rozgen tests.

Paths are computed from this file, so the tests run from any checkout and
any working directory.
"""

import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
CODEGEN = TESTS.parent
REPO = CODEGEN.parent
MANIFESTS = REPO / "manifests"
INVALID = MANIFESTS / "invalid"

# The least stack a thread may ask for, KiB, on the machine the checker's C
# runs on (hal/include/roz/hal/thread.h, ROZ_THREAD_STACK_MIN_KIB): glibc on
# aarch64 Linux refuses less than 128 KiB; 64 elsewhere. The shared vectors'
# .expected files hold an x86-64 machine's words, BUILD_STACK_RANGE.
STACK_LEAST_KIB = 128 if platform.system() == "Linux" and platform.machine() in (
    "aarch64", "arm64") else 64
STACK_RANGE = f"{STACK_LEAST_KIB}..65536"
BUILD_STACK_RANGE = "64..65536"
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


def channel(table: str, name: str, interface_type: str, unit: str, limits: str,
            default: str, **more: str) -> str:
    """One robot.toml channel, a ``[[manifest.<table>]]`` entry (table
    "commands" or "states"): name, interface type and unit as strings; limits,
    default and the keys of @p more as raw TOML, written as the test means
    them (``[-2, 2]`` is not ``[-2.0, 2.0]`` to a test that edits the text)."""
    keys = {"name": f'"{name}"', "interface_type": f'"{interface_type}"', "unit": f'"{unit}"',
            "limits": limits, "default": default, **more}
    return f"\n[[manifest.{table}]]\n" + "".join(f"{k} = {v}\n" for k, v in keys.items())


def robot_toml(robot_id: str, *channels: str, port: str | None = None, joints: str = "",
               **manifest: str) -> str:
    """A robot.toml: [manifest] with @p robot_id and the raw TOML keys of
    @p manifest, then @p channels (see channel()), then, given a @p port, a
    [hardware] table of it and the raw TOML @p joints list's items."""
    text = f'[manifest]\nrobot_id = "{robot_id}"\n'
    text += "".join(f"{k} = {v}\n" for k, v in manifest.items()) + "".join(channels)
    if port is not None:
        text += f'\n[hardware]\nport = "{port}"\njoints = [{joints}]\n'
    return text


def knee_toml(port: str = "unitree/G1", joint: str = "left_knee_joint",
              joints: str | None = None, damping: str | None = None) -> str:
    """A robot of one knee on a DDS port at 500 Hz: its position command,
    given @p damping (raw TOML limits, without the brackets) a damping
    command, and its position state; @p joints is [hardware] joints' raw
    items, the knee's own by default."""
    position = ("position", "rad", "[-0.09, 2.88]", "0.0")
    commands = [channel("commands", f"{joint}/position", *position)]
    if damping is not None:
        commands.append(channel("commands", f"{joint}/damping", "damping", "N.m.s/rad",
                                f"[{damping}]", "2.0"))
    return robot_toml("knee", *commands, channel("states", f"{joint}/position", *position),
                      port=port, joints=f'"{joint}"' if joints is None else joints,
                      control_rate_hz="500")


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
