# SPDX-License-Identifier: Apache-2.0
"""What roz refuses although tomllib reads it: integers beyond 64 bits and
nesting beyond MAX_DEPTH, at the place and in the words of roz's C reader
(test/toml/compare_vectors.py checks the C side on the shared vectors)."""

import pytest

from conftest import run_rozgen
from rozgen.load import load
from rozgen.toml_limits import DEPTH, INT_RANGE, MAX_DEPTH, first_refusal

ROBOT = """[manifest]
robot_id = "arm"
[[manifest.commands]]
name = "j/velocity"
interface_type = "velocity"
unit = "rad/s"
limits = [-1.0, 1.0]
default = {default}
"""


def problem_of(tmp_path, text: str) -> str:
    path = tmp_path / "robot.toml"
    path.write_text(text, encoding="utf-8")
    loaded = load(str(path))
    assert loaded.doc is None and len(loaded.problems) == 1
    assert loaded.problems[0].rule == "toml-syntax"
    return loaded.problems[0].message


def test_huge_integer_is_a_clear_error_exit_2(tmp_path):
    path = tmp_path / "robot.toml"
    path.write_text(ROBOT.format(default="1" + "0" * 309), encoding="utf-8")
    result = run_rozgen("--check", path)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert result.stderr == f"{path}:8:11: invalid TOML: {INT_RANGE}\n"


@pytest.mark.parametrize("value, refused", [
    ("9223372036854775807", False),
    ("-9223372036854775808", False),
    ("9223372036854775808", True),
    ("-9223372036854775809", True),
    ("+9_223_372_036_854_775_808", True),
    ("0x7fff_ffff_ffff_ffff", False),
    ("0x8000000000000000", True),
    ("0o1000000000000000000000", True),
    ("0b1" + "0" * 63, True),
    ("99999999999999999999.5", False),  # floats have no such limit
    ("99999999999999999999e3", False),
    ("-99999999999999999999E-3", False),
    ("9" * 400 + ".0", False),
])
def test_integer_range(tmp_path, value, refused):
    text = ROBOT.format(default=value)
    assert (first_refusal(text) is not None) == refused
    if refused:
        assert problem_of(tmp_path, text) == f":8:11: invalid TOML: {INT_RANGE}"


@pytest.mark.parametrize("text", [
    # digits that are not values: keys, strings, comments, dates, times
    '99999999999999999999 = 1\n"99999999999999999999".x = 2\n',
    'a = "99999999999999999999 [[[["\nb = \'99999999999999999999\'\n',
    'a = """\n99999999999999999999 \\""" [[[\n"""\nb = \'\'\'\n99999999999999999999\'\'\'\'\n',
    '# 99999999999999999999 [[[[[[\na = 1 # 99999999999999999999\n',
    'a = 1979-05-27 07:32:00Z\nb = 07:32:00.999999999999999999999\n',
    '[99999999999999999999."[[[".\'x\']\nv = [{k = [1, {}]}, [], [[]]]\n',
    'a = {b = 1, c = "}]"}\n[[t]]\nx = [1, 2,]\n',
])
def test_only_values_count(text):
    assert first_refusal(text) is None


def test_depth(tmp_path):
    at_limit = "a = " + "[" * MAX_DEPTH + "]" * MAX_DEPTH + "\n"
    assert first_refusal(at_limit) is None
    for inner in ("[]", "{}", "[1]", "{x = 1}"):
        text = "ok = [[1]]\nb = " + "[" * MAX_DEPTH + inner + "]" * MAX_DEPTH + "\n"
        assert first_refusal(text) == (len("ok = [[1]]\nb = ") + MAX_DEPTH, DEPTH)
    # inline tables count as much as arrays; what was closed does not count
    mixed = "a = " + "[{k = " * (MAX_DEPTH // 2) + "1" + "}]" * (MAX_DEPTH // 2) + "\n"
    assert first_refusal(mixed) is None
    wide = "a = [" + "[[]], {x = {}}, " * 3 * MAX_DEPTH + "]\n"
    assert first_refusal(wide) is None
    # deeper than tomllib's recursion: still a positioned problem
    deep = ROBOT.format(default="0.0") + "x = " + "[" * 5000 + "]" * 5000 + "\n"
    assert problem_of(tmp_path, deep) == f":9:{5 + MAX_DEPTH}: unsupported TOML: {DEPTH}"


def test_first_problem_in_the_file_wins(tmp_path):
    big = "99999999999999999999"
    # a refusal before a tomllib error (one that tomllib finds after the value)
    assert problem_of(tmp_path, f"a = 1\na = {big}\n") == f":2:5: invalid TOML: {INT_RANGE}"
    assert problem_of(tmp_path, f"a = {big}\nb = [1 2]\n") == f":1:5: invalid TOML: {INT_RANGE}"
    # an integer cut short by an error is still read first (as the C reader does)
    assert problem_of(tmp_path, f"a = {big}__1\n") == f":1:5: invalid TOML: {INT_RANGE}"
    # a tomllib error before a refusal
    assert problem_of(tmp_path, f"b = [1 2]\na = {big}\n").startswith(":1:8: invalid TOML: ")
    # (a literal string runs to the next quote, as both readers look for it)
    assert problem_of(tmp_path, "a = 'open\nb = " + "[" * 200).startswith(":2:205: invalid TOML")
    # columns in bytes, as the C reader counts them
    assert problem_of(tmp_path, f'a = ["é", {big}]\n') == f":1:12: invalid TOML: {INT_RANGE}"


def test_valid_documents_are_read_as_before(tmp_path):
    path = tmp_path / "robot.toml"
    path.write_text(ROBOT.format(default="-0.0") + "# [[[[ 99999999999999999999\n",
                    encoding="utf-8")
    loaded = load(str(path))
    assert loaded.problems == [] and loaded.doc is not None
