# SPDX-License-Identifier: Apache-2.0
"""Warnings (rozgen.lint): a command paired with another joint's position
state is named on stderr, and refused only under --strict."""

import pytest

from conftest import MANIFESTS, MY_ARM, REPO, builtin_manifests, channel, robot_toml

WARNING = ('robot.toml: warning: manifest.commands[0] "joint1/velocity": position_state_index 1: '
           'paired with manifest.states[1] "joint2/position", a state of joint "joint2", '
           'not of "joint1"')


def write(tmp_path, command="joint1/velocity", state="joint2/position"):
    """robot.toml: @p command paired with its second state, @p state."""
    path = tmp_path / "robot.toml"
    path.write_text(robot_toml(
        "arm",
        channel("commands", command, "velocity", "rad/s", "[-1.0, 1.0]", "0.0",
                position_state_index="1"),
        channel("states", "joint1/position", "position", "rad", "[-3.0, 3.0]", "0.0"),
        channel("states", state, "position", "rad", "[-3.0, 3.0]", "0.0")), encoding="utf-8")
    return path


def test_mismatched_pairing_warns_and_generates(tmp_path, rozgen):
    write(tmp_path)
    result = rozgen("robot.toml", "-o", "out", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stderr.splitlines() == [WARNING]
    assert (tmp_path / "out" / "arm_manifest.c").exists()


@pytest.mark.parametrize("mode", [["--check"], ["--json"], ["--identity"]])
def test_every_mode_warns(tmp_path, rozgen, mode):
    write(tmp_path)
    result = rozgen(*mode, "robot.toml", cwd=tmp_path)
    assert result.returncode == 0
    assert result.stderr.splitlines() == [WARNING]


def test_strict_makes_it_an_error_and_writes_nothing(tmp_path, rozgen):
    write(tmp_path)
    result = rozgen("--strict", "robot.toml", "-o", "out", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.splitlines() == [WARNING.replace(": warning:", ": error (--strict):")]
    assert not (tmp_path / "out").exists()


def test_error_ids_prefix_the_warning(tmp_path, rozgen):
    write(tmp_path)
    result = rozgen("--check", "--error-ids", "robot.toml", cwd=tmp_path)
    assert result.stderr.splitlines() == ["[pairing-names] " + WARNING]


@pytest.mark.parametrize("command,state", [
    ("joint2/velocity", "joint2/position"),   # the same joint
    ("joint2_vel", "joint2/position"),        # a name without "/": not compared
    ("arm/joint2/velocity", "arm/joint2/position"),
])
def test_agreeing_or_uncomparable_names_do_not_warn(tmp_path, rozgen, command, state):
    write(tmp_path, command, state)
    result = rozgen("--check", "--strict", "robot.toml", cwd=tmp_path)
    assert (result.returncode, result.stderr) == (0, "")


def test_no_manifest_of_the_repository_warns(rozgen):
    files = builtin_manifests() + [MY_ARM] + sorted((REPO / "examples").glob("*/*.toml"))
    result = rozgen("--check", "--strict", *sorted(set(files)), cwd=MANIFESTS)
    assert (result.returncode, result.stderr) == (0, ""), result.stderr
