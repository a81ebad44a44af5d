# SPDX-License-Identifier: Apache-2.0
"""rozgen's checks of a DDS port robot's [hardware] keys beyond the shared
vectors (manifests/invalid/g1-*, ros2-*, unknown-key--g1/--ros2, which the
ports themselves open in test_port_vectors): the ROS 2 robots' joints, the
keys and the ranges are those of the ports' C sources (unitree/G1's are the
port's C rules themselves, run by the checker); the built-in robots pass;
several problems are all reported, the port's first one first; the number
parser reads what strtod reads."""

import re

import pytest

from conftest import REPO, run_rozgen
from rozgen import dds_ports
from rozgen.validate import validate


def _c(path: str) -> str:
    return (REPO / path).read_text(encoding="utf-8")


def _strings(c_array: str) -> tuple[str, ...]:
    return tuple(re.findall(r'"([^"]*)"', c_array))


def _array(text: str, name: str) -> str:
    found = re.search(name + r"\[[^\]]*\] = \{(.*?)\};", text, re.S)
    assert found, name
    return found.group(1)


def _define(text: str, name: str) -> int:
    found = re.search(r"#define " + name + r" ([0-9]+)u?\b", text)
    assert found, name
    return int(found.group(1))


def test_x2_groups_are_the_ports():
    text = _c("ports/agibot_x2/src/x2_port.c")
    groups = re.findall(r'\{ "(\w+)", "rt/[^"]*", "rt/[^"]*", (\w+), (\d+) \}', text)
    assert [g for g, _, _ in groups] == [g for g, _ in dds_ports.X2_GROUPS]
    for (group, array, n), (_, joints) in zip(groups, dds_ports.X2_GROUPS):
        assert _strings(_array(text, array)) == joints, group
        assert int(n) == len(joints), group


def test_pm01_joints_are_the_ports():
    text = _c("ports/engineai_pm01/src/pm01_port.c")
    joints = _strings(_array(text, r"roz_engineai_pm01_joints"))
    assert (("body", joints),) == dds_ports.PM01_GROUPS


def test_keys_are_the_ports():
    dds_h = _c("ports/dds/include/roz/port/dds.h")
    macro = re.search(r"#define ROZ_DDS_PARAM_KEYS(.*?)\n\n", dds_h, re.S).group(1)
    keys = _strings(macro)
    assert "ROZ_CMD_WATCHDOG_KEY" in macro
    watchdog = re.search(r'#define ROZ_CMD_WATCHDOG_KEY "(\w+)"',
                         _c("hal/include/roz/hal/cmd_watchdog.h")).group(1)
    assert dds_ports.DDS_KEYS == keys + (watchdog,)
    common = _array(_c("ports/ros2/src/ros2_bridge.c"), "common_keys")
    assert dds_ports.ROS2_KEYS == dds_ports.DDS_KEYS + _strings(common)
    for port, path in ((dds_ports.X2, "ports/agibot_x2/src/x2_port.c"),
                       (dds_ports.PM01, "ports/engineai_pm01/src/pm01_port.c")):
        own = _strings(_array(_c(path), "own_keys"))
        assert port.keys == dds_ports.ROS2_KEYS + own and own == (port.own,)


def test_limits_are_the_headers():
    dds_h = _c("ports/dds/include/roz/port/dds.h")
    wd_h = _c("hal/include/roz/hal/cmd_watchdog.h")
    assert dds_ports.IFNAME_MAX == _define(dds_h, "ROZ_DDS_IFNAME_MAX")
    assert dds_ports.MAX_DOMAIN == _define(dds_h, "ROZ_DDS_MAX_DOMAIN")
    assert dds_ports.MIN_PERIOD_US == _define(dds_h, "ROZ_DDS_MIN_PERIOD_US")
    assert dds_ports.MAX_PERIOD_US == _define(dds_h, "ROZ_DDS_MAX_PERIOD_US")
    assert dds_ports.MAX_SPIN_US == _define(dds_h, "ROZ_DDS_MAX_SPIN_US")
    assert dds_ports.WATCHDOG_DEFAULT_US == _define(wd_h, "ROZ_CMD_WATCHDOG_DEFAULT_US")
    assert dds_ports.WATCHDOG_DEFAULT_PERIODS == _define(wd_h,
                                                         "ROZ_CMD_WATCHDOG_DEFAULT_PERIODS")
    assert dds_ports.WATCHDOG_MIN_PERIODS == _define(wd_h, "ROZ_CMD_WATCHDOG_MIN_PERIODS")
    assert dds_ports.WATCHDOG_MAX_US == _define(wd_h, "ROZ_CMD_WATCHDOG_MAX_US")
    assert dds_ports.MAX_JOINTS == _define(_c("lib/include/roz/config.h"), "ROZ_CFG_MAX_JOINTS")


@pytest.mark.parametrize("name", ["unitree_g1", "unitree_g1_23dof", "agibot_x2",
                                  "engineai_pm01"])
def test_the_built_in_robots_pass(name):
    result = run_rozgen("--check", f"manifests/{name}.toml")
    assert result.returncode == 0, result.stderr


_KNEE = """
[manifest]
robot_id = "knee"
control_rate_hz = 500

[[manifest.commands]]
name = "left_knee_joint/position"
interface_type = "position"
unit = "rad"
limits = [-0.09, 2.88]
default = 0.0

[[manifest.commands]]
name = "left_knee_joint/damping"
interface_type = "damping"
unit = "N.m.s/rad"
limits = [0.5, 10.0]
default = 2.0

[[manifest.states]]
name = "left_knee_joint/position"
interface_type = "position"
unit = "rad"
limits = [-0.09, 2.88]
default = 0.0

[hardware]
port = "{port}"
joints = [{joints}]
"""


def _problems(port="unitree/G1", joints='"left_knee_joint"', params=""):
    _, problems = validate(_KNEE.format(port=port, joints=joints) + params)
    return [(p.rule, p.message) for p in problems]


def test_a_valid_robot_with_every_key_passes():
    assert _problems(params="""
[hardware.params]
network_interface = "eth0"
dds_domain = "232"
enable_monitor = "off"
state_decimation = "1000"
command_writer_period_us = "0"
command_writer_spin_us = "10000"
command_timeout_us = "4000"
mode_pr = "ab"
peer_timeout_ms = "10"
startup_damping = "0.5"
shutdown_damping = "1e1"
""") == []


def test_every_problem_is_reported_the_ports_first():
    # the port stops at the unknown key; rozgen goes on to the values
    got = _problems(params="""
[hardware.params]
mode_pr = "PRR"
dds_domian = "0"
peer_timeout_ms = "9"
startup_damping = "0"
""")
    assert [rule for rule, _ in got] == ["unknown-key", "g1-param", "g1-param", "g1-param"]
    assert got[0][1].startswith(': unknown parameter "dds_domian" for port unitree/G1')
    assert got[1][1].startswith(': parameter mode_pr = "PRR": expected PR')
    assert got[2][1] == ': parameter peer_timeout_ms = "9": expected an integer in 10..60000'
    # the damping gains a damping channel allows: [0.5, 10], without 0
    assert got[3][1] == ': parameter startup_damping = "0": expected a number in 0.5..10'


def test_peer_unitree_mujoco_on_lo_only():
    assert _problems(params='[hardware.params]\npeer = "unitree_mujoco"\n') == []
    got = _problems(params='[hardware.params]\npeer = "unitree_mujoco"\n'
                    'network_interface = "eth0"\n')
    assert got == [("g1-param", ': parameter peer = "unitree_mujoco" with network_interface = '
                    '"eth0": the simulator\'s checks are off, so roz takes them only on lo '
                    "(unitree_mujoco's INTERFACE); a robot's network is refused")]
    got = _problems(params='[hardware.params]\npeer = "sim"\n')
    assert got == [("g1-param", ': parameter peer = "sim": expected robot (a G1: every check, '
                    "the default) or unitree_mujoco (Unitree's simulator on lo: no state CRC "
                    "or tick checks; never a robot)")]


def test_parameters_wait_for_the_binding():
    # the port binds joints and channels first and stops there
    got = _problems(joints='"left_knee_joint", "left_knee"',
                    params='[hardware.params]\nmode_pr = "PRR"\n')
    assert got == [("g1-joint", ': unitree/G1: [hardware] joints[1] "left_knee" is not one of '
                    "the robot's joints (the port's header lists them)")]


def test_command_timeout_follows_the_writer_period():
    # at 500 Hz and a 10 ms writer period: at least 2 x 10000 us, default 5 x
    got = _problems(params="""
[hardware.params]
command_writer_period_us = "10000"
command_timeout_us = "19999"
""")
    assert got == [("g1-param", ': parameter command_timeout_us = "19999": expected a time in '
                    "20000..60000000 us (at least 2 periods of the tick at 500 Hz and of the "
                    "command writer; default 50000)")]
    # a bad period: no timeout can be worked out from it, as in the port
    got = _problems(params="""
[hardware.params]
command_writer_period_us = "99"
command_timeout_us = "1"
""")
    assert [rule for rule, _ in got] == ["g1-param"]


def test_the_ros2_ports_own_keys():
    x2 = _problems(port="agibot/X2", params="""
[hardware.params]
link_check = "sequence"
joint_state_layout = "docs"
mode_pr = "PR"
""")
    assert x2 == [("unknown-key", ': unknown parameter "mode_pr" for port agibot/X2 (known: '
                   + " ".join(dds_ports.X2.keys) + ")")]


def test_other_ports_are_left_alone():
    assert _problems(port="vendor/humanoid", joints='"x"',
                     params='[hardware.params]\nmode_pr = "PRR"\n') == []


@pytest.mark.parametrize("text,value", [
    ("1", 1.0), ("-2.5", -2.5), (".5", 0.5), ("5.", 5.0), ("1e1", 10.0), ("+1E-1", 0.1),
    (" \t1", 1.0), ("0x10", 16.0), ("-0x1.8p1", -3.0), ("1e-400", 0.0),
    ("", None), ("1 ", None), ("1e", None), ("0x", None), ("1,5", None), ("--1", None),
    ("inf", None), ("nan", None), ("1e400", float("inf")), ("١", None),
])
def test_numbers_as_strtod_reads_them(text, value):
    assert dds_ports.strtod_whole(text) == value


@pytest.mark.parametrize("text,ok", [
    ("0", True), ("232", True), ("233", False), ("007", True), ("+1", False), (" 1", False),
    ("1 ", False), ("0x1", False), ("", False), ("99999999999999999999999", False),
    ("١", False),
])
def test_integers_as_the_port_reads_them(text, ok):
    assert (dds_ports.u32(text, 0, 232) is not None) == ok
