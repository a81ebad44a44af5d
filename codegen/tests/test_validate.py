# SPDX-License-Identifier: Apache-2.0
"""Validation in process: defaults, the model, all problems at once."""

import dataclasses

import pytest

from conftest import channel, robot_toml
from rozgen.model import Maxima
from rozgen.validate import validate

GOOD = robot_toml(
    "arm",
    channel("commands", "j1/velocity", "velocity", "rad/s", "[-2, 2]", "0"),
    channel("states", "j1/position", "position", "rad", "[-3.14, 3.14]", "0.0"))


def check(text: str, maxima: Maxima = Maxima()):
    manifest, problems = validate(text, maxima)
    return manifest, [p.render("f.toml", with_id=True) for p in problems]


def test_defaults_and_conversions():
    m, problems = check(GOOD)
    assert problems == []
    assert (m.robot_id, m.robot_class, m.control_rate_hz) == ("arm", "generic", 100)
    c = m.commands[0]
    assert (c.min, c.max, c.default, c.max_rate, c.position_state) == (-2.0, 2.0, 0.0, 0.0, -1)
    assert all(isinstance(v, float) for v in (c.min, c.max, c.default, c.max_rate))
    assert m.states[0].position_state == -1
    assert m.hardware is None


def test_model_is_immutable():
    m, _ = check(GOOD)
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.robot_id = "x"
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.commands[0].max = 1e9
    assert isinstance(m.commands, tuple) and isinstance(m.states, tuple)


def test_states_are_optional():
    text = GOOD[:GOOD.index("[[manifest.states]]")]
    m, problems = check(text)
    assert problems == [] and m.states == ()


def test_hardware_params_sorted_joints_kept_in_order():
    m, problems = check(GOOD + """
[hardware]
port = "example/humanoid"
joints = ["z", "a"]

[hardware.params]
network_interface = "eth0"
dds_domain = "0"
""")
    assert problems == []
    assert m.hardware.joints == ("z", "a")
    assert m.hardware.params == (("dds_domain", "0"), ("network_interface", "eth0"))


def test_every_problem_is_reported_in_schema_order():
    text = """
[hardware]
port = 5
params = {a = 1}

[manifest]
control_rate_hz = true
robot_id = "Bad"
typo = 1
""" + channel("states", "s/velocity", "velocity", "m/s", "[1.0, -1.0]", "9.0") \
        + channel("commands", "c/velocity", "velocity", "m/s", "[-1, 1]", "2",
                  max_rate_of_change="-1", position_state_index="0")
    m, problems = check(text)
    assert m is None
    assert problems == [
        "[unknown-key] f.toml: manifest: typo: unknown key (known keys: robot_id, robot_class, "
        "control_rate_hz, commands, states, inputs, remote_estop, fall)",
        '[robot-id] f.toml: manifest: robot_id "Bad": must match [a-z][a-z0-9_]* '
        "(it names C symbols and files)",
        "[type] f.toml: manifest: control_rate_hz true: expected an integer, not a boolean",
        '[default-range] f.toml: manifest.commands[0] "c/velocity": default 2: '
        "must be within limits [-1.0, 1.0]",
        '[max-rate] f.toml: manifest.commands[0] "c/velocity": max_rate_of_change -1: '
        "must not be negative",
        '[pairing-type] f.toml: manifest.commands[0] "c/velocity": position_state_index 0: '
        'manifest.states[0] "s/velocity" is a velocity state, not a position state',
        '[limits-order] f.toml: manifest.states[0] "s/velocity": limits [1.0, -1.0]: '
        "min must be below max",
        "[type] f.toml: hardware: port 5: expected a string",
        "[type] f.toml: hardware.params: a 1: expected a string",
    ]


def test_problems_in_channels_without_a_usable_name():
    _, problems = check("""
[manifest]
robot_id = "r"
commands = [{name = 3, interface_type = "x", unit = "", limits = [0, 1], default = 0}, 7]
""")
    assert problems == [
        "[type] f.toml: manifest: commands[1] 7: expected a table",
        "[type] f.toml: manifest.commands[0]: name 3: expected a string",
        '[interface-type] f.toml: manifest.commands[0]: interface_type "x": unknown type '
        "(known types: position, velocity, effort, stiffness, damping, acceleration, orientation)",
    ]


def test_maxima_are_options():
    two = GOOD + GOOD[GOOD.index("[[manifest.states]]"):].replace("j1/", "j2/")
    _, problems = check(two, Maxima(commands=1, states=1, name_len=8))
    assert problems == [
        "[too-many-channels] f.toml: manifest: states: 2 channels, more than the maximum "
        "of 1 (ROZ_CFG_MAX_STATES)",
        '[name] f.toml: manifest.commands[0]: name "j1/velocity": 11 bytes, more than the '
        "maximum of 8 (ROZ_CFG_MAX_NAME_LEN)",
        '[name] f.toml: manifest.states[0]: name "j1/position": 11 bytes, more than the '
        "maximum of 8 (ROZ_CFG_MAX_NAME_LEN)",
        '[name] f.toml: manifest.states[1]: name "j2/position": 11 bytes, more than the '
        "maximum of 8 (ROZ_CFG_MAX_NAME_LEN)",
    ]


def test_names_are_compared_among_the_first_maximum_channels():
    state = GOOD[GOOD.index("[[manifest.states]]"):]
    states = "".join(state.replace("j1/", f"j{i}/") for i in (0, 1, 0, 2, 1))
    _, problems = check(GOOD[:GOOD.index("[[manifest.states]]")] + states,
                        Maxima(commands=8, states=3))
    assert problems == [
        "[too-many-channels] f.toml: manifest: states: 5 channels, more than the maximum "
        "of 3 (ROZ_CFG_MAX_STATES)",
        '[duplicate-name] f.toml: manifest.states[2]: name "j0/position": duplicate of '
        "manifest.states[0]",
    ]  # states[4] repeats states[1] too, beyond the maximum: not compared


def test_same_name_in_commands_and_states_is_fine():
    m, problems = check(GOOD.replace('"j1/position"', '"j1/velocity"').replace(
        'interface_type = "position"', 'interface_type = "velocity"'))
    assert problems == [] and m.states[0].name == m.commands[0].name


def test_negative_zero_is_kept():
    m, problems = check(GOOD.replace("default = 0\n", "default = -0.0\n", 1))
    assert problems == []
    assert str(m.commands[0].default) == "-0.0"


def _with_command(**raw: str) -> str:
    """GOOD with its command's keys replaced by (or added as) raw TOML."""
    keys = {"name": '"j1/velocity"', "interface_type": '"velocity"', "unit": '"rad/s"',
            "limits": "[-2, 2]", "default": "0"}
    keys.update(raw)
    command = "".join(f"{k} = {v}\n" for k, v in keys.items())
    head, tail = GOOD.split("[[manifest.states]]")
    head = head[:head.index("[[manifest.commands]]")]
    return f"{head}[[manifest.commands]]\n{command}\n[[manifest.states]]{tail}"


@pytest.mark.parametrize("key, value, rule", [
    ("position_state_index", "1.0", "[type]"),
    ("position_state_index", "true", "[type]"),
    ("limits", '"-1..1"', "[limits-shape]"),
    ("limits", "[-1, 0, 1]", "[limits-shape]"),
    ("limits", "[]", "[limits-shape]"),
    ("limits", "[nan, 1]", "[not-finite]"),
    ("default", '"0"', "[type]"),
    ("interface_type", "1", "[type]"),
    ("max_rate_of_change", "-inf", "[not-finite]"),
    ("name", '"a\\"b"', "[name]"),
])
def test_bad_values(key, value, rule):
    _, problems = check(_with_command(**{key: value}))
    assert len(problems) == 1 and problems[0].startswith(rule), problems


def test_good_command_variants():
    m, problems = check(_with_command(max_rate_of_change="0.25", position_state_index="0",
                                      unit='""', limits="[-1e-05, 1e16]"))
    assert problems == []
    c = m.commands[0]
    assert (c.unit, c.min, c.max, c.max_rate, c.position_state) == ("", -1e-05, 1e16, 0.25, 0)


def _with_state(**raw: str) -> str:
    """GOOD with its state's keys replaced by (or added as) raw TOML."""
    keys = {"name": '"j1/position"', "interface_type": '"position"', "unit": '"rad"',
            "limits": "[-3.14, 3.14]", "default": "0.0"}
    keys.update(raw)
    head = GOOD[:GOOD.index("[[manifest.states]]")]
    return head + "[[manifest.states]]\n" + "".join(f"{k} = {v}\n" for k, v in keys.items())


def test_limit_margin_default_and_own():
    m, problems = check(GOOD)
    assert problems == []
    assert m.states[0].limit_margin == 0.0 and m.commands[0].limit_margin == 0.0
    assert m.states[0].margin == 0.05  # 5 % of 6.28 rad is more: capped at 0.05
    # the gripper of docs/robot-toml.md (limit_margin): 5 % of its 8 cm, not 5 cm of them
    m, problems = check(_with_state(unit='"m"', limits="[0, 0.08]", default="0.04"))
    assert problems == []
    assert m.states[0].margin == 0.05 * 0.08 and m.states[0].margin < 0.0041
    m, problems = check(_with_state(limit_margin="1"))
    assert problems == []
    assert m.states[0].limit_margin == 1.0 and isinstance(m.states[0].limit_margin, float)
    assert m.states[0].margin == 1.0
    m, problems = check(_with_state(limits="[-1e308, 1.5e308]"))  # max - min overflows
    assert problems == [] and m.states[0].margin == 0.05


@pytest.mark.parametrize("value, shown, rule, what", [
    ("0", "0", "[margin-range]", "must be above 0 (leave it out for the default)"),
    ("-0.0", "-0.0", "[margin-range]", "must be above 0 (leave it out for the default)"),
    ("-1e-9", "-1e-09", "[margin-range]", "must be above 0 (leave it out for the default)"),
    ("3.14", "3.14", "[margin-range]", "leaves no room to move within limits [-3.14, 3.14]: "
     "twice the margin must be below max - min"),
    ("1e308", "1e+308", "[margin-range]", "leaves no room to move"),
    ("nan", "nan", "[not-finite]", "must be finite"),
    ("-inf", "-inf", "[not-finite]", "must be finite"),
    ('"0.1"', '"0.1"', "[type]", "expected a number"),
    ("false", "false", "[type]", "expected a number, not a boolean"),
])
def test_bad_limit_margins(value, shown, rule, what):
    _, problems = check(_with_state(limit_margin=value))
    assert len(problems) == 1, problems
    assert problems[0].startswith(f'{rule} f.toml: manifest.states[0] "j1/position": '
                                  f"limit_margin {shown}: {what}"), problems


def test_limit_margin_just_below_half_the_range():
    m, problems = check(_with_state(limits="[0, 0.08]", default="0.04", limit_margin="0.0399"))
    assert problems == [] and m.states[0].margin == 0.0399
    _, problems = check(_with_state(limits="[0, 0.08]", default="0.04", limit_margin="0.04"))
    assert [p.split(": ")[-2] for p in problems] == ["leaves no room to move within limits "
                                                     "[0.0, 0.08]"]


@pytest.mark.parametrize("text", [
    _with_command(limit_margin="0.01"),
    _with_state(interface_type='"velocity"', limit_margin="0.01"),
    _with_state(interface_type='"velocity"', limit_margin="0"),
])
def test_limit_margin_only_on_position_states(text):
    _, problems = check(text)
    assert len(problems) == 1 and problems[0].startswith("[margin-channel]"), problems
    assert problems[0].endswith("only a position state has a limit margin (the filter keeps a "
                                "velocity command paired with it that far inside its limits)")


def test_canonical_json_shows_the_margin_worked_out():
    from rozgen import checker
    text = _with_state(unit='"m"', limits="[0, 0.08]", default="0.04")
    lines = checker.canonical_json(text.encode("utf-8"), checker.find()).splitlines()
    assert lines[5].endswith('"position_state_index": -1, "limit_margin": null, '
                             '"safe_default": "follow"}')  # command
    assert lines[8].endswith('"position_state_index": -1, "limit_margin": 0.004, '
                             '"safe_default": "follow"}')  # state
