# SPDX-License-Identifier: Apache-2.0
"""The rozgen command line: modes, exit status, file handling."""

import os
import random
import tomllib

import pytest

from conftest import CODEGEN, MY_ARM, REPO, channel, robot_toml, run_rozgen
from rozgen import __version__
from rozgen.problems import RULES

def minimal(robot_id):
    """A robot of one command."""
    return robot_toml(robot_id, channel("commands", "j/velocity", "velocity", "rad/s",
                                        "[-1.0, 1.0]", "0.0"))


def write_robot(directory, robot_id, name=None):
    path = directory / (name or f"{robot_id}.toml")
    path.write_text(minimal(robot_id), encoding="utf-8")
    return path


def test_version_matches_pyproject():
    with open(CODEGEN / "pyproject.toml", "rb") as f:
        assert tomllib.load(f)["project"]["version"] == __version__
    result = run_rozgen("--version")
    assert (result.returncode, result.stdout) == (0, f"rozgen {__version__}\n")


def test_list_rules():
    result = run_rozgen("--list-rules")
    assert result.returncode == 0
    assert [line.split()[0] for line in result.stdout.splitlines()] == list(RULES)


@pytest.mark.parametrize("args", [
    [],
    ["--json", "a.toml", "b.toml"],
    ["--json", "--check", "a.toml"],
    ["--json", "--registry", "a.toml"],
    ["--max-commands", "0", "a.toml"],
    ["--max-states", "x", "a.toml"],
    ["--no-such-option", "a.toml"],
])
def test_usage_errors_exit_2(args):
    result = run_rozgen(*args)
    assert result.returncode == 2
    assert "usage: rozgen" in result.stderr and "Traceback" not in result.stderr


def test_unreadable_files(tmp_path):
    result = run_rozgen("--check", tmp_path / "absent.toml", tmp_path)
    assert result.returncode == 2
    assert result.stderr == (f"{tmp_path / 'absent.toml'}: cannot read: No such file or directory\n"
                             f"{tmp_path}: cannot read: Is a directory\n")


@pytest.mark.parametrize("data", [
    b"",
    b"\xef\xbb\xbf[manifest]\n",
    b"a = " + b"[" * 100000,
    b"[manifest]\nrobot_id = 1979-02-30\n",
    b"[manifest]\nrobot_id = 1979-05-27T07:32:00Z\n",
    b"\x00\x01\x02",
    b"[manifest]\ncommands = [[], [{}], 'x', {a = []}]\n",
    b"[manifest]\ncommands = [{name = 'a', limits = [[1, [2]], {}]}]\n",
    b"[[hardware]]\n[manifest.commands.x]\n",
    b"manifest = 5\nhardware = []\n",
    b"[hardware]\njoints = 'a'\nparams = 3\n",
    b'[hardware]\njoints = [1, "\\u0000"]\n[hardware.params]\n"\\u0000" = "a"\nb = {c = "d"}\n',
])
def test_odd_input_never_crashes(tmp_path, data):
    path = tmp_path / "odd.toml"
    path.write_bytes(data)
    result = run_rozgen("--check", path)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert result.stderr.startswith(f"{path}:")


def test_random_mutations_never_crash(tmp_path):
    """Randomly damaged copies of a real manifest: problems, never a crash."""
    from rozgen.cli import main

    source = MY_ARM.read_bytes()
    rng = random.Random(1234)
    for i in range(300):
        data = bytearray(source)
        for _ in range(rng.randint(1, 4)):
            pos = rng.randrange(len(data))
            data[pos:pos + rng.randint(0, 3)] = bytes(rng.choice(b'[]{}"=.,-+0123456789 \nxe\xff'))
        path = tmp_path / f"m{i}.toml"
        path.write_bytes(bytes(data))
        assert main(["--check", str(path)]) in (0, 2)


def test_check_writes_nothing(tmp_path):
    out = tmp_path / "out"
    result = run_rozgen("--check", "-o", out, MY_ARM)
    assert (result.returncode, result.stderr) == (0, "")
    # one line per file that passed, and nothing written
    assert result.stdout == f"{MY_ARM}: ok: my_arm, 2 commands, 2 states\n"
    assert not out.exists()


def test_json_prints_and_writes_nothing(tmp_path):
    result = run_rozgen("--json", MY_ARM, cwd=tmp_path)
    assert result.returncode == 0 and result.stderr == ""
    assert result.stdout.startswith('{\n  "robot_id": "my_arm",\n')
    assert list(tmp_path.iterdir()) == []


def test_generate_creates_directory_and_four_files(tmp_path):
    out = tmp_path / "a" / "b"
    result = run_rozgen("-o", out, MY_ARM)
    assert (result.returncode, result.stdout, result.stderr) == (0, "", "")
    assert sorted(p.name for p in out.iterdir()) == [
        "my_arm_channels.h", "my_arm_channels.rs", "my_arm_manifest.c", "my_arm_manifest.h"]


def test_unchanged_files_are_not_rewritten(tmp_path):
    robot = write_robot(tmp_path, "r")
    out = tmp_path / "out"
    assert run_rozgen("-o", out, robot).returncode == 0
    old = 1_000_000_000
    for p in out.iterdir():
        os.utime(p, ns=(old, old))
    assert run_rozgen("-o", out, robot).returncode == 0
    assert all(p.stat().st_mtime_ns == old for p in out.iterdir())

    robot.write_text(minimal("r").replace("1.0]", "2.0]"), encoding="utf-8")
    assert run_rozgen("-o", out, robot).returncode == 0
    assert all(p.stat().st_mtime_ns != old for p in out.iterdir())
    assert "[-1.0, 2.0]" in (out / "r_channels.h").read_text()
    assert not [p for p in out.iterdir() if ".tmp" in p.name]


def test_nothing_is_written_when_any_file_is_invalid(tmp_path):
    good = write_robot(tmp_path, "good")
    bad = tmp_path / "bad.toml"
    bad.write_text("[manifest]\n", encoding="utf-8")
    out = tmp_path / "out"
    result = run_rozgen("-o", out, "--registry", good, bad)
    assert result.returncode == 2
    assert result.stderr == (f"{bad}: manifest: robot_id: required key is missing\n"
                             f"{bad}: manifest: commands: required key is missing\n")
    assert not out.exists()


def test_duplicate_robot_ids(tmp_path):
    first = write_robot(tmp_path, "twin", "a.toml")
    second = write_robot(tmp_path, "twin", "b.toml")
    result = run_rozgen("--check", "--error-ids", first, second)
    assert result.returncode == 2
    assert result.stderr == (f'[duplicate-robot-id] {second}: manifest: robot_id "twin": '
                             f"also the robot_id of {first}\n")


def test_output_directory_that_is_a_file(tmp_path):
    blocker = tmp_path / "out"
    blocker.write_text("")
    result = run_rozgen("-o", blocker, MY_ARM)
    assert result.returncode == 2
    assert result.stderr == f"{blocker}: cannot write: File exists\n"


def test_source_label(tmp_path):
    outside = write_robot(tmp_path, "r")
    out = tmp_path / "out"
    # Not under the current directory (the repository): the base name.
    assert run_rozgen("-o", out, outside).returncode == 0
    assert " from r.toml (sha256 " in (out / "r_manifest.c").read_text()
    # Under the current directory: relative to it.
    assert run_rozgen("-o", out, "r.toml", cwd=tmp_path).returncode == 0
    assert " from r.toml (sha256 " in (out / "r_manifest.c").read_text()
    assert run_rozgen("-o", out, "--source-root", tmp_path.parent, outside).returncode == 0
    assert f" from {tmp_path.name}/r.toml (sha256 " in (out / "r_manifest.c").read_text()
    # Not under --source-root: refused.
    result = run_rozgen("-o", out, "--source-root", REPO / "manifests", outside)
    assert result.returncode == 2
    assert result.stderr == f"{outside}: not under --source-root {REPO / 'manifests'}\n"
