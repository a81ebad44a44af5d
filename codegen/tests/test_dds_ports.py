# SPDX-License-Identifier: Apache-2.0
"""rozgen's checks of a DDS port robot's [hardware] keys beyond the shared
vectors (manifests/invalid/g1-*, ros2-*, unknown-key--g1/--ros2, which the
ports themselves open in test_port_vectors): the ports' own C rules
(ports/unitree_g1/src/g1_rules.c, ports/ros2/src/ros2_rules.c and each ROS 2
robot's), run by the checker. The built-in robots pass; several problems
are all reported, the port's first one first; the numbers read are what
strtod reads."""

import pytest

from conftest import knee_toml, run_rozgen
from rozgen.validate import validate


@pytest.mark.parametrize("name", ["unitree_g1", "unitree_g1_23dof", "agibot_x2",
                                  "engineai_pm01"])
def test_the_built_in_robots_pass(name):
    result = run_rozgen("--check", f"manifests/{name}.toml")
    assert result.returncode == 0, result.stderr


def _problems(port="unitree/G1", joints='"left_knee_joint"', params="", damping="0.5, 10.0"):
    _, problems = validate(knee_toml(port, joints=joints, damping=damping) + params)
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
                   "network_interface dds_domain enable_monitor exit_stop "
                   "command_writer_period_us command_writer_spin_us state_decimation "
                   "command_writer_sched command_writer_priority command_writer_cpus "
                   "command_writer_stack_kib dds_threads_sched dds_threads_priority "
                   "dds_threads_stack_kib command_timeout_us peer_timeout_ms startup_damping "
                   "shutdown_damping link_check cmd_vel_topic joy_topic joy_map "
                   "joint_state_layout)")]


def test_the_ros2_ports_report_every_parameter_step():
    # the open stops at link_check; the check goes on to the robot's own key
    robot = knee_toml("engineai/PM01", "J03_KNEE_PITCH_L", damping="0.5, 10.0")
    _, problems = validate(robot + '[hardware.params]\nlink_check = "sequence"\n'
                           'parallel_parser_type = "RL"\n')
    got = [(p.rule, p.message) for p in problems]
    assert [rule for rule, _ in got] == ["ros2-param", "ros2-param"]
    assert got[0][1].startswith(': parameter link_check = "sequence": expected stamp')
    assert got[1][1].startswith(': parameter parallel_parser_type = "RL": expected rl')


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
    # a gain within the damping channel's [0, 100] is taken, anything else refused
    got = _problems(params=f'[hardware.params]\nstartup_damping = "{text}"\n'.replace("\t", "\\t"),
                    damping="0.0, 100.0")
    taken = value is not None and 0.0 <= value <= 100.0
    assert got == ([] if taken else [("g1-param", f': parameter startup_damping = "{text}": '
                                      "expected a number in 0..100")])


@pytest.mark.parametrize("text,ok", [
    ("0", True), ("232", True), ("233", False), ("007", True), ("+1", False), (" 1", False),
    ("1 ", False), ("0x1", False), ("", False), ("99999999999999999999999", False),
    ("١", False),
])
def test_integers_as_the_port_reads_them(text, ok):
    got = _problems(params=f'[hardware.params]\ndds_domain = "{text}"\n')
    assert got == ([] if ok else [("g1-param", f': parameter dds_domain = "{text}": expected an '
                                   "integer in 0..232")])
