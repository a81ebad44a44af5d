# SPDX-License-Identifier: Apache-2.0
"""Float, string and name formatting (rozgen.fmt, rozgen.names)."""

import math
import struct

import pytest

from rozgen.fmt import c_comment, c_double, c_string, json_string, shortest_g, toml_value
from rozgen.names import command_constant, constant_suffix, state_constant


@pytest.mark.parametrize("value, text", [
    (0.0, "0"),
    (-0.0, "-0"),
    (1.0, "1"),
    (-2.0, "-2"),
    (0.5, "0.5"),
    (0.1, "0.1"),
    (3.14, "3.14"),
    (100.0, "100"),
    (-120.0, "-120"),
    (150000.0, "150000"),
    (1e15, "1000000000000000"),
    (9007199254740993.0, "9007199254740992"),  # 2**53 + 1 is not a double
    (1e16, "1e+16"),
    (1.2345678901234568e17, "1.2345678901234568e+17"),
    (0.0001, "0.0001"),
    (1e-05, "1e-05"),
    (1.5e-07, "1.5e-07"),
    (6.283185307179586, "6.283185307179586"),
    (2.0 / 3.0, "0.6666666666666666"),
    (5e-324, "5e-324"),
    (1.7976931348623157e308, "1.7976931348623157e+308"),
    (math.inf, "inf"),
    (-math.inf, "-inf"),
    (math.nan, "nan"),
])
def test_shortest_g(value, text):
    assert shortest_g(value) == text


def _significant_digits(text: str) -> str:
    mantissa = text.lstrip("-").partition("e")[0]
    return mantissa.replace(".", "").lstrip("0").rstrip("0") or "0"


def test_shortest_g_round_trips_with_the_shortest_digits():
    # A deterministic spread of finite doubles, both signs. Python's repr()
    # gives the shortest digits that round-trip; shortest_g must give the
    # same digits (written differently at times: 100 where repr has 100.0).
    step = 0x7FF0000000000000 // 4099
    for bits in range(0, 0x7FF0000000000000, step):
        x = struct.unpack("<d", struct.pack("<Q", bits))[0]
        for value in (x, -x):
            text = shortest_g(value)
            assert float(text) == value
            assert math.copysign(1.0, float(text)) == math.copysign(1.0, value)
            assert _significant_digits(text) == _significant_digits(repr(value)), text


@pytest.mark.parametrize("value, text", [
    (0.0, "0.0"),
    (-0.0, "-0.0"),
    (2.0, "2.0"),
    (100.0, "100.0"),
    (0.2, "0.2"),
    (1e-05, "1e-05"),
    (1e16, "1e+16"),
    (math.inf, "inf"),
])
def test_c_double(value, text):
    assert c_double(value) == text


@pytest.mark.parametrize("text, literal", [
    ("rad/s", '"rad/s"'),
    ("", '""'),
    ('say "hi"', '"say \\"hi\\""'),
    ("back\\slash", '"back\\\\slash"'),
    ("a\nb\tc\rd", '"a\\nb\\tc\\rd"'),
    ("\u00b0/s", '"\\302\\260/s"'),
    ("x\x01" + "7", '"x\\0017"'),  # three octal digits: the 7 stays a 7
    ("\x7f", '"\\177"'),
    ("??=", '"?\\?="'),
    ("???/", '"?\\?\\?/"'),
])
def test_c_string(text, literal):
    assert c_string(text) == literal


def test_c_comment_cannot_close_or_nest():
    for text in ("a*/b", "a/*b", "*/*/", "/*/", "x\n*/"):
        safe = c_comment(text)
        assert "*/" not in safe and "/*" not in safe and "\n" not in safe
        assert safe.isascii()


@pytest.mark.parametrize("text, literal", [
    ("a", '"a"'),
    ('q"\\', '"q\\"\\\\"'),
    ("\b\f\n\r\t", '"\\b\\f\\n\\r\\t"'),
    ("\x00\x1f\x7f", '"\\u0000\\u001f\\u007f"'),
    ("\u00e9/", '"\\u00e9/"'),
    ("\U0001f600", '"\\ud83d\\ude00"'),
])
def test_json_string(text, literal):
    assert json_string(text) == literal


@pytest.mark.parametrize("value, text", [
    (True, "true"),
    (False, "false"),
    (7, "7"),
    (2.0, "2.0"),
    (-math.inf, "-inf"),
    ("x\ty\"", '"x\\ty\\""'),
    ("\x00", '"\\u0000"'),
    ([2.0, -2.0], "[2.0, -2.0]"),
    ([1, "a", True], '[1, "a", true]'),
    ({"a": 1}, "{...}"),
    (list(range(10)), "[0, 1, 2, 3, 4, 5, 6, 7, ...]"),
    ([[[1]]], "[[[...]]]"),
])
def test_toml_value(value, text):
    assert toml_value(value) == text


@pytest.mark.parametrize("name, suffix", [
    ("shoulder_pan_joint/velocity", "SHOULDER_PAN_JOINT_VELOCITY"),
    ("base_imu/orientation.x", "BASE_IMU_ORIENTATION_X"),
    ("base/linear.x", "BASE_LINEAR_X"),
    ("body/yaw_rate", "BODY_YAW_RATE"),
    ("joint1/velocity", "JOINT1_VELOCITY"),
    ("__a//b..c__", "A_B_C"),
    ("a-b c", "A_B_C"),
    ("1st joint", "1ST_JOINT"),
    ("/./", ""),
])
def test_constant_suffix(name, suffix):
    assert constant_suffix(name) == suffix


def test_constants():
    assert command_constant("ur5", "shoulder_pan_joint/velocity") == \
        "ROZ_UR5_CMD_SHOULDER_PAN_JOINT_VELOCITY"
    assert state_constant("unitree_g1", "base_imu/orientation.w") == \
        "ROZ_UNITREE_G1_STATE_BASE_IMU_ORIENTATION_W"
