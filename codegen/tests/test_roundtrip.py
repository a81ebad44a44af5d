# SPDX-License-Identifier: Apache-2.0
"""--json round-trips: JSON -> robot.toml -> JSON gives the same bytes."""

import decimal
import json

import pytest

from conftest import DATA, MY_ARM, REPO, builtin_manifests, run_rozgen

VECTORS = REPO / "test" / "vectors" / "good"


def toml_string(s: str) -> str:
    # JSON escapes other than surrogate pairs are TOML escapes too; keep
    # non-ASCII as is so no surrogate pair is ever written.
    return json.dumps(s, ensure_ascii=False)


def toml_float(d: decimal.Decimal) -> str:
    return repr(float(d))  # "-0.0", "1e-05", "1e+16", "inf" never occurs


def channel_lines(kind: str, c: dict) -> list[str]:
    """The keys every channel of canonical JSON has, as a [[manifest.<kind>]]."""
    low, high = c["limits"]
    return ["", f"[[manifest.{kind}]]",
            f"name = {toml_string(c['name'])}",
            f"interface_type = {toml_string(c['interface_type'])}",
            f"unit = {toml_string(c['unit'])}",
            f"limits = [{toml_float(low)}, {toml_float(high)}]",
            f"default = {toml_float(c['default'])}",
            f"max_rate_of_change = {toml_float(c['max_rate_of_change'])}"]


def json_to_toml(text: str) -> str:
    """A tiny robot.toml writer for canonical JSON."""
    doc = json.loads(text, parse_int=decimal.Decimal, parse_float=decimal.Decimal)
    out = [
        "[manifest]",
        f"robot_id = {toml_string(doc['robot_id'])}",
        f"robot_class = {toml_string(doc['robot_class'])}",
        f"control_rate_hz = {int(doc['control_rate_hz'])}",
    ]
    if "remote_estop" in doc:  # present only with one
        out.append("remote_estop = [" + ", ".join(map(toml_string, doc["remote_estop"])) + "]")
    for kind in ("commands", "states"):
        if kind == "states" and not doc[kind]:
            continue
        if not doc[kind]:
            out.append(f"{kind} = []")
        for c in doc[kind]:
            out += channel_lines(kind, c)
            out.append(f"position_state_index = {int(c['position_state_index'])}")
            # the margin worked out, written as the state's own: same JSON
            if c["limit_margin"] is not None:
                out.append(f"limit_margin = {toml_float(c['limit_margin'])}")
            out.append(f"safe_default = {toml_string(c['safe_default'])}")
    for c in doc.get("inputs", ()):  # present only when there are inputs
        out += channel_lines("inputs", c)
        out.append(f"stale_after_ms = {int(c['stale_after_ms'])}")
        if "source" in c:  # present only on an input with a source
            out += [f"source = {toml_string(c['source'])}", f"scale = {toml_float(c['scale'])}"]
    fall = doc.get("fall")  # present only with a fall rule
    if fall is not None:
        out += ["", "[manifest.fall]", f"orientation = {toml_string(fall['orientation'])}",
                f"max_tilt_rad = {toml_float(fall['max_tilt_rad'])}",
                f"for_ms = {int(fall['for_ms'])}"]
    hw = doc["hardware"]
    if hw is not None:
        out += ["", "[hardware]", f"port = {toml_string(hw['port'])}",
                "joints = [" + ", ".join(map(toml_string, hw["joints"])) + "]",
                "", "[hardware.params]"]
        out += [f"{toml_string(k)} = {toml_string(v)}" for k, v in hw["params"].items()]
    return "\n".join(out) + "\n"


def test_my_arm_values():
    result = run_rozgen("--json", MY_ARM)
    assert result.returncode == 0, result.stderr
    doc = json.loads(result.stdout)
    assert doc["robot_id"] == "my_arm"
    assert doc["robot_class"] == "manipulator"
    assert doc["control_rate_hz"] == 100
    assert doc["commands"] == [
        {"name": f"joint{i}/velocity", "interface_type": "velocity", "unit": "rad/s",
         "limits": [-2.0, 2.0], "default": 0, "max_rate_of_change": 0.2,
         "position_state_index": i - 1, "limit_margin": None, "safe_default": "follow"}
        for i in (1, 2)
    ]
    assert doc["states"] == [
        {"name": f"joint{i}/position", "interface_type": "position", "unit": "rad",
         "limits": [-3.14, 3.14], "default": 0, "max_rate_of_change": 0,
         "position_state_index": -1, "limit_margin": margin, "safe_default": "follow"}
        for i, margin in ((1, 0.05), (2, 0.1))  # the default; joint2's own
    ]
    assert doc["hardware"] is None
    assert list(doc) == ["robot_id", "robot_class", "control_rate_hz", "commands", "states",
                         "hardware"]
    assert result.stdout.splitlines()[5] == (
        '    {"name": "joint1/velocity", "interface_type": "velocity", "unit": "rad/s", '
        '"limits": [-2, 2], "default": 0, "max_rate_of_change": 0.2, "position_state_index": 0, '
        '"limit_margin": null, "safe_default": "follow"},')


@pytest.mark.parametrize("toml", [MY_ARM, DATA / "tricky.toml", VECTORS / "margins.toml",
                                  *builtin_manifests()],
                         ids=lambda p: p.stem if p.stem != "robot" else p.parent.name)
def test_round_trip(tmp_path, toml):
    first = run_rozgen("--json", toml)
    assert first.returncode == 0, first.stderr
    rewritten = tmp_path / "robot.toml"
    rewritten.write_text(json_to_toml(first.stdout), encoding="utf-8")
    second = run_rozgen("--json", rewritten)
    assert second.returncode == 0, second.stderr
    assert second.stdout == first.stdout
