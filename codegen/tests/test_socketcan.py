# SPDX-License-Identifier: Apache-2.0
"""rozgen's checks of a socketcan robot's [hardware] keys beyond the
fixtures (manifests/invalid/can-*.toml), which are the port's own
(ports/socketcan/src/can_config.c, run by rozgen through roz_manifest_json):
the example leg passes, the keys are those the port documents, other
ports' params are left alone. The bus figures of a frame: test_can_config."""

import re

from conftest import REPO, channel, robot_toml, run_rozgen


def test_the_example_leg_passes():
    result = run_rozgen("--check", "examples/can_leg/leg.toml")
    assert result.returncode == 0, result.stderr


def test_keys_are_the_documented_ones(tmp_path):
    leg = (REPO / "examples/can_leg/leg.toml").read_text(encoding="utf-8")
    robot = tmp_path / "robot.toml"
    robot.write_text(leg.replace("\n[hardware.params]\n",
                                 '\n[hardware.params]\nnot_a_key = "1"\n'),
                     encoding="utf-8")
    result = run_rozgen("--check", str(robot))
    known = re.search(r"not_a_key: unknown key of the socketcan port \(known keys: ([^)]*)\)",
                      result.stderr)
    assert known is not None, result.stderr
    page = (REPO / "docs/ports/socketcan.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| ((?:`[a-z_]+`(?:, )?)+) \|", page, re.M)
    documented = [k.strip(" `") for row in rows for k in row.split(",")]
    assert sorted(documented) == sorted(known[1].split(", "))


def test_other_ports_params_are_not_checked(tmp_path):
    robot = tmp_path / "robot.toml"
    robot.write_text(robot_toml("other", channel("commands", "a/effort", "effort", "N.m",
                                                 "[-1.0, 1.0]", "0.0"),
                                port="vendor/bus", joints='"a"')
                     + '\n[hardware.params]\ncan_id = "whatever"\n', encoding="utf-8")
    result = run_rozgen("--check", str(robot))
    assert result.returncode == 0, result.stderr
