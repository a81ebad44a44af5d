# SPDX-License-Identifier: Apache-2.0
"""rozgen-urdf (rozgen.urdf): robot.toml from URDFs the team wrote
(codegen/tests/data/urdf/): a 7-joint arm with a gripper, a mobile base
with continuous wheels, a prismatic lift, an arm with a <ros2_control>
tag, a 12-joint biped in the shape of a legged-robot training URDF. Each result passes rozgen's rules and generates C that compiles; each
refusal names the element and its line."""

import subprocess
import sys
import tomllib

import pytest

from conftest import CODEGEN, DATA, LIB_INCLUDE, run_rozgen
from rozgen import urdf
from rozgen.urdf import CONTINUOUS_LIMIT, UrdfError, convert
from test_compile import COMPILERS, FEATURES_STUB, FLAGS

URDFS = DATA / "urdf"
ALL = ["arm7_gripper", "mobile_base", "lift", "ros2_control_arm"]


def imported(name, **options):
    text = convert((URDFS / f"{name}.urdf").read_bytes(), f"{name}.urdf", **options)
    return text, tomllib.loads(text)["manifest"]


def by_name(channels):
    return {c["name"]: c for c in channels}


def run_urdf(*args, cwd):
    return subprocess.run([sys.executable, "-m", "rozgen.urdf", *map(str, args)], cwd=cwd,
                          env={"PYTHONPATH": str(CODEGEN), "PATH": "/usr/bin:/bin"},
                          capture_output=True, text=True)


def test_arm_with_gripper():
    text, m = imported("arm7_gripper")
    assert m["robot_id"] == "arm7_gripper"  # from <robot name="Arm7-Gripper">
    commands, states = by_name(m["commands"]), by_name(m["states"])
    joints = [f"joint{i}" for i in range(1, 8)] + ["finger_left"]
    assert list(commands) == [f"{j}/velocity" for j in joints]
    assert list(states) == [f"{j}/position" for j in joints] + [f"{j}/velocity" for j in joints]
    assert commands["joint1/velocity"]["limits"] == [-2.175, 2.175]
    assert states["joint4/position"]["limits"] == [-3.1416, 0.0]
    assert states["joint6/position"]["default"] == 0.0873  # 0 is outside: the nearer limit
    # the gripper finger is prismatic: metres
    assert states["finger_left/position"]["unit"] == "m"
    assert states["finger_left/position"]["limits"] == [0.0, 0.04]
    assert commands["finger_left/velocity"]["unit"] == "m/s"
    # every command paired with its own joint's position state
    positions = [s["name"] for s in m["states"]]
    for c in m["commands"]:
        assert positions[c["position_state_index"]] == c["name"].replace("velocity", "position")
    # the mimic finger and the fixed flange have no channels; the mimic is noted
    assert "finger_right" not in text.replace("mimic joint finger_right", "")
    assert "# mimic joint finger_right (line 45) follows finger_left (x 1 + 0): not commanded" \
        in text
    assert "flange" not in text


def test_mobile_base_with_continuous_wheels():
    text, m = imported("mobile_base", robot_class="mobile")
    assert m["robot_class"] == "mobile"
    commands, states = by_name(m["commands"]), by_name(m["states"])
    assert list(commands) == ["left_wheel_joint/velocity", "right_wheel_joint/velocity"]
    wheel = states["left_wheel_joint/position"]
    assert wheel["limits"] == [-CONTINUOUS_LIMIT, CONTINUOUS_LIMIT]
    # a wheel's velocity is not paired: it would stop at the wide limits
    assert all("position_state_index" not in c for c in m["commands"])
    assert "continuous joint: the URDF has no position limits" in text
    assert "not paired with left_wheel_joint/position" in text
    assert "caster" not in text


def test_prismatic_lift():
    _, m = imported("lift", rate=50)
    assert m["control_rate_hz"] == 50
    states = by_name(m["states"])
    assert states["lift/position"] == {
        "name": "lift/position", "interface_type": "position", "unit": "m",
        "limits": [0.05, 1.2], "default": 0.05}
    assert states["lift/velocity"]["unit"] == "m/s"
    assert states["pan/position"]["unit"] == "rad"


def test_default_command_option():
    _, m = imported("lift", command="effort")
    commands = by_name(m["commands"])
    assert commands["lift/effort"]["unit"] == "N"
    assert commands["lift/effort"]["limits"] == [-800.0, 800.0]
    assert commands["pan/effort"]["unit"] == "N*m"


def test_ros2_control_interfaces():
    text, m = imported("ros2_control_arm")
    commands, states = by_name(m["commands"]), by_name(m["states"])
    assert list(commands) == ["shoulder/position", "elbow/position", "elbow/velocity",
                              "wrist/velocity"]
    assert list(states) == ["shoulder/position", "elbow/position", "wrist/position",
                            "shoulder/velocity", "elbow/velocity", "wrist/velocity",
                            "shoulder/effort"]
    assert states["shoulder/effort"]["limits"] == [-150.0, 150.0]
    assert states["shoulder/effort"]["unit"] == "N*m"
    names = [s["name"] for s in m["states"]]
    # position commands hold their joint's position; the continuous wrist's
    # velocity is not paired
    assert names[commands["shoulder/position"]["position_state_index"]] == "shoulder/position"
    assert names[commands["elbow/velocity"]["position_state_index"]] == "elbow/position"
    assert "position_state_index" not in commands["wrist/velocity"]
    # what is not carried over is said
    assert "ros2_control hardware plugin and its parameters are not carried" in text
    assert "joint tool_spin (line 22): not in ros2_control; no channels" in text
    assert 'command_interface "mode" has no roz channel type' in text
    assert "flange_io" not in text and "rrbot_hardware" not in text


def test_ros2_control_min_max_tighten_the_limits():
    data = (URDFS / "ros2_control_arm.urdf").read_bytes().replace(
        b"<param name=\"min\">-3.14</param>", b"<param name=\"min\">-1.5</param>")
    m = tomllib.loads(convert(data, "arm.urdf"))["manifest"]
    assert by_name(m["commands"])["shoulder/position"]["limits"] == [-1.5, 3.14]
    assert by_name(m["states"])["shoulder/position"]["limits"] == [-3.14, 3.14]


@pytest.mark.parametrize("name", ALL)
def test_output_passes_rozgen_and_generates_c(tmp_path, name):
    toml = tmp_path / f"{name}.toml"
    result = run_urdf(URDFS / f"{name}.urdf", "-o", toml, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stderr.startswith(f"{toml}: ")
    check = run_rozgen("--check", "--strict", toml, cwd=tmp_path)
    assert check.returncode == 0 and check.stderr == "", check.stderr
    out = tmp_path / "gen"
    gen = run_rozgen(toml, "-o", out, cwd=tmp_path)
    assert gen.returncode == 0, gen.stderr
    sources = sorted(out.glob("*_manifest.c"))
    assert len(sources) == 1
    if not COMPILERS:
        pytest.skip("no C compiler")
    (tmp_path / "include" / "roz").mkdir(parents=True)
    (tmp_path / "include" / "roz" / "features.h").write_text(FEATURES_STUB)
    cc = subprocess.run([COMPILERS[0], *FLAGS, f"-I{LIB_INCLUDE}", f"-I{tmp_path / 'include'}",
                         f"-I{out}", "-c", str(sources[0]), "-o", str(tmp_path / "m.o")],
                        capture_output=True, text=True)
    assert cc.returncode == 0 and cc.stderr == "", cc.stderr


HUMANOID = ("--humanoid", "--imu", "imu_in_pelvis", "--kp-max", "200", "--kd-max", "10",
            "--rate", "500")


def test_humanoid_option_writes_what_a_policy_deployment_reads(tmp_path):
    """A 12-DoF training URDF (legs revolute, upper body fixed, no
    <ros2_control>): --humanoid writes the built-in humanoids' layout, the
    gains and the IMU included, and rozgen accepts it."""
    toml = tmp_path / "biped.toml"
    result = run_urdf(URDFS / "biped_12dof.urdf", *HUMANOID, "-o", toml, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    m = tomllib.loads(toml.read_text())["manifest"]
    assert m["robot_class"] == "humanoid" and m["control_rate_hz"] == 500
    legs = [f"{side}_{j}_joint" for side in ("left", "right")
            for j in ("hip_pitch", "hip_roll", "hip_yaw", "knee", "ankle_pitch", "ankle_roll")]
    assert [c["name"] for c in m["commands"]] == [
        f"{j}/{k}" for k in ("position", "velocity", "stiffness", "damping", "effort")
        for j in legs]
    imu = [f"base_imu/{q}.{a}" for q, axes in (("orientation", "xyzw"),
                                                ("angular_velocity", "xyz"),
                                                ("linear_acceleration", "xyz")) for a in axes]
    assert [c["name"] for c in m["states"]] == [
        f"{j}/{k}" for k in ("position", "velocity", "effort") for j in legs] + imu
    commands, states = by_name(m["commands"]), by_name(m["states"])
    kp, kd = commands["left_knee_joint/stiffness"], commands["right_ankle_roll_joint/damping"]
    assert (kp["interface_type"], kp["unit"], kp["limits"]) == ("stiffness", "N*m/rad", [0.0, 200.0])
    assert (kd["interface_type"], kd["unit"], kd["limits"]) == ("damping", "N*m*s/rad", [0.0, 10.0])
    assert "position_state_index" not in kp and "position_state_index" not in kd
    assert commands["left_knee_joint/effort"]["limits"] == [-139.0, 139.0]
    assert states["right_ankle_pitch_joint/effort"]["limits"] == [-50.0, 50.0]
    assert commands["left_knee_joint/effort"]["position_state_index"] == 3
    assert states["base_imu/orientation.w"]["default"] == 1.0
    assert states["base_imu/linear_acceleration.z"]["default"] == 9.81
    text = toml.read_text()
    assert "the IMU on link imu_in_pelvis (line " in text
    assert text.count("limits: --kp-max (a URDF has no gains)") == 1
    assert "waist_yaw_joint" not in text and "shoulder" not in text  # fixed: rigid
    check = run_rozgen("--check", "--strict", toml, cwd=tmp_path)
    assert check.returncode == 0 and check.stderr == "", check.stderr
    # the same through convert() with the options spelled out
    spelled = convert((URDFS / "biped_12dof.urdf").read_bytes(), "biped_12dof.urdf",
                      robot_class="humanoid", rate=500, command=urdf.HUMANOID_COMMANDS,
                      states_of=urdf.HUMANOID_STATES,
                      gains={"stiffness": 200.0, "damping": 10.0}, imu="imu_in_pelvis")
    assert spelled == text


@pytest.mark.parametrize("args, message", [
    (("--humanoid", "--kp-max", "200", "--kd-max", "10"), "--humanoid needs --imu LINK"),
    (("--humanoid", "--imu", "imu_in_pelvis", "--kd-max", "10"),
     "joint left_hip_pitch_joint: a stiffness command needs --kp-max"),
    (("--humanoid", "--imu", "chest", "--kp-max", "200", "--kd-max", "10"),
     "--imu chest: the URDF has no <link name=\"chest\">"),
    (("--command", "position,torque"), '"torque" is not one of position, velocity, stiffness'),
    (("--command", "position,damping"), "a damping command needs --kd-max"),
    (("--states", "position,stiffness"), '"stiffness" is not one of position, velocity, effort'),
    (("--command", "position", "--kp-max", "-1"), "--kp-max -1.0: expected a number above 0"),
])
def test_channel_options_refused(tmp_path, args, message):
    result = run_urdf(URDFS / "biped_12dof.urdf", *args, cwd=tmp_path)
    assert result.returncode == 2
    assert message in result.stderr, result.stderr


def test_command_and_states_lists(tmp_path):
    _, m = imported("lift", command=("position", "effort"), states_of=("position",))
    assert [c["name"] for c in m["commands"]] == ["lift/position", "pan/position",
                                                  "lift/effort", "pan/effort"]
    assert [c["name"] for c in m["states"]] == ["lift/position", "pan/position"]


def test_does_not_overwrite_without_force(tmp_path):
    toml = tmp_path / "robot.toml"
    toml.write_text("# my edits\n")
    result = run_urdf(URDFS / "lift.urdf", "-o", toml, cwd=tmp_path)
    assert result.returncode == 2
    assert "exists; it may hold your edits (--force overwrites it)" in result.stderr
    assert toml.read_text() == "# my edits\n"
    assert run_urdf(URDFS / "lift.urdf", "-o", toml, "--force", cwd=tmp_path).returncode == 0
    assert "lift/position" in toml.read_text()


def test_stdout_without_output(tmp_path):
    result = run_urdf(URDFS / "lift.urdf", cwd=tmp_path)
    assert result.returncode == 0
    assert result.stdout == convert((URDFS / "lift.urdf").read_bytes(), "lift.urdf")
    assert "Imported from lift.urdf by rozgen-urdf" in result.stdout  # no directory named


ARM = """<?xml version="1.0"?>
<robot name="r">
  <link name="a"/><link name="b"/>
  <joint name="j" type="{type}">
    <parent link="a"/><child link="b"/>
    {limit}
  </joint>
</robot>
"""


@pytest.mark.parametrize("kind,limit,line,message", [
    ("revolute", "", 4, '<joint name="j">: no <limit>; its position channel needs one'),
    ("revolute", '<limit upper="1" velocity="1" effort="1"/>', 6,
     '<joint name="j"> <limit>: no lower; a revolute joint\'s position needs both'),
    ("prismatic", '<limit lower="0.5" upper="0.1" velocity="1" effort="1"/>', 6,
     '<joint name="j"> <limit> lower="0.5" upper="0.1": lower must be below upper'),
    ("revolute", '<limit lower="-1" upper="1" velocity="0" effort="1"/>', 6,
     '<joint name="j"> <limit>: velocity="0", not a velocity limit above 0'),
    ("revolute", '<limit lower="-1" upper="1" effort="1"/>', 6,
     '<joint name="j"> <limit>: no velocity limit above 0'),
    ("continuous", "", 4, '<joint name="j">: no <limit>; its velocity channel needs one'),
    ("revolute", '<limit lower="-1" upper="nan" velocity="1" effort="1"/>', 6,
     '<limit> upper="nan": not a finite number'),
    ("screw", "", 4, '<joint name="j"> type="screw": expected revolute'),
])
def test_refusals_name_the_element_and_line(tmp_path, kind, limit, line, message):
    path = tmp_path / "robot.urdf"
    path.write_text(ARM.format(type=kind, limit=limit))
    result = run_urdf(path, cwd=tmp_path)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.startswith(f"{path}:{line}: "), result.stderr
    assert message in result.stderr


def test_unexpanded_xacro_is_refused(tmp_path):
    path = tmp_path / "robot.urdf.xacro"
    path.write_text('<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
                    '  <xacro:property name="len" value="1"/>\n</robot>\n')
    result = run_urdf(path, cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr == (f"{path}:3: <xacro:property>: an unexpanded xacro; expand it first "
                             "(xacro robot.urdf.xacro > robot.urdf)\n")
    path.write_text(ARM.format(type="revolute", limit='<limit lower="${-pi}" upper="1" '
                                                      'velocity="1" effort="1"/>'))
    result = run_urdf(path, cwd=tmp_path)
    assert result.stderr.startswith(f"{path}:6: <limit> lower=\"${{-pi}}\": an unexpanded xacro "
                                    "expression")


def test_malformed_xml_and_entities(tmp_path):
    with pytest.raises(UrdfError) as e:
        convert(b'<robot name="r">\n  <joint name="j">\n</robot>\n', "r.urdf")
    assert e.value.line == 3 and str(e.value).startswith("not well-formed XML: mismatched tag")
    with pytest.raises(UrdfError) as e:
        convert(b'<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY a "aaaa">]>\n<robot name="r"/>',
                "r.urdf")
    assert e.value.line == 2 and "entity" in str(e.value)


def test_ros2_control_naming_an_unknown_joint(tmp_path):
    data = (URDFS / "ros2_control_arm.urdf").read_bytes().replace(
        b'<joint name="elbow">\n      <command_interface name="position"/>',
        b'<joint name="elbw">\n      <command_interface name="position"/>')
    with pytest.raises(UrdfError) as e:
        convert(data, "arm.urdf")
    assert e.value.line == 41  # the <ros2_control> <joint> element
    assert str(e.value) == '<ros2_control> <joint name="elbw">: the URDF has no joint of that name'


def test_no_commands_and_what_rozgen_refuses(tmp_path):
    fixed = ARM.format(type="fixed", limit="").encode()
    with pytest.raises(UrdfError, match="no joint with a command interface"):
        convert(fixed, "r.urdf")
    long_name = ARM.format(type="revolute", limit='<limit lower="-1" upper="1" velocity="1" '
                                                  'effort="1"/>').replace('name="j"', 'name="' + "j" * 70 + '"')
    with pytest.raises(UrdfError) as e:
        convert(long_name.encode(), "r.urdf")
    assert "refused by rozgen" in str(e.value) and "name" in str(e.value)


def test_robot_id_of():
    assert urdf.robot_id_of("Arm7-Gripper") == "arm7_gripper"
    assert urdf.robot_id_of("7dof") == "robot_7dof"
    assert urdf.robot_id_of("") == "robot"
    assert len(urdf.robot_id_of("x" * 50)) == 32


def test_text_in_many_pieces_is_read_in_linear_time(monkeypatch):
    """expat hands an element's text over line by line: each element's text
    is set once, from all its pieces (adding each piece to the text was
    quadratic: 800 KB of lines took 20 s)."""
    sets = []

    class Counted(urdf.Element):
        def __setattr__(self, name, value):
            if name == "text":
                sets.append(len(value))
            super().__setattr__(name, value)

    monkeypatch.setattr(urdf, "Element", Counted)
    lines = 20000
    root = urdf.parse_xml(b"<robot name='r'><link name='a'>" + b"x\n" * lines
                          + b"</link><link name='b'/></robot>")
    assert root.find("link").text == "x\n" * lines
    # one text per element (the dataclass's default, then its joined text)
    assert len(sets) <= 2 * 3, len(sets)
