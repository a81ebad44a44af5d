# SPDX-License-Identifier: Apache-2.0
"""rozgen's checks of a socketcan robot's [hardware] keys beyond the
fixtures (manifests/invalid/can-*.toml): the example leg passes, the keys
are those the port documents, other ports' params are left alone, the bus
figures of a frame."""

import re

from conftest import REPO, run_rozgen
from rozgen import socketcan


def test_the_example_leg_passes():
    result = run_rozgen("--check", "examples/can_leg/leg.toml")
    assert result.returncode == 0, result.stderr


def test_keys_are_the_documented_ones():
    page = (REPO / "docs/ports/socketcan.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| ((?:`[a-z_]+`(?:, )?)+) \|", page, re.M)
    documented = [k.strip(" `") for row in rows for k in row.split(",")]
    assert sorted(documented) == sorted(socketcan.KEYS)


def test_frame_bits_worst_case():
    # 47 + 8n fixed bits and floor((34 + 8n - 1) / 4) stuff bits at most
    assert socketcan.frame_bits(8) == 135
    assert socketcan.frame_bits(6) == 115
    assert socketcan.frame_bits(0) == 55


def test_other_ports_params_are_not_checked(tmp_path):
    robot = tmp_path / "robot.toml"
    robot.write_text('''
[manifest]
robot_id = "other"

[[manifest.commands]]
name = "a/effort"
interface_type = "effort"
unit = "N.m"
limits = [-1.0, 1.0]
default = 0.0

[hardware]
port = "vendor/bus"
joints = ["a"]

[hardware.params]
can_id = "whatever"
''', encoding="utf-8")
    result = run_rozgen("--check", str(robot))
    assert result.returncode == 0, result.stderr
