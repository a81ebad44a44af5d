# SPDX-License-Identifier: Apache-2.0
"""The [hardware] keys of a robot on the mujoco port (physics) that need its
model. The rules of the keys that need none are the port's own, in C
(``ports/mujoco/src/mj_params.c``), run by rozgen's checker; the keys,
their values and defaults are documented in ``docs/ports/mujoco.md``.

``check_model(manifest, toml_path)`` reads the model the file names
(``rozgen.mjcf``; the path relative to the robot.toml) and checks what the
port's open checks against it, with its words: every joint bound to a
joint of the model and an actuator (by name, or ``joint_names``), the IMU's
sensors, and an actuator whose force range cannot give the manifest's
effort limit. A model that cannot be read is an error naming it. What only
MuJoCo's compiler can say (the timestep's fit, a keyframe) is still the
port's to check when it loads the model.

``check_open(manifest, toml_path)`` (``rozgen --check`` only) asks the port
itself: ``rozrun --robot FILE --port mujoco --check`` opens it as a run
would (MuJoCo compiles the model; a built-in robot's model is the port's
build's) and reports what it refuses, in its words, for the rules no second
implementation checks here: an effort channel wider than its motor's
``ctrlrange`` times gear and gain, a built-in robot's effort past what its
model gives. rozrun is ``$ROZ_ROZRUN``, else the one beside the command that
runs rozgen (an installed roz's ``bin/``), else on PATH; without one the
port checks at open, as before.
"""

import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

from rozgen import mjcf
from rozgen.model import Manifest

PORT = "mujoco"

def _g(x: float) -> str:
    """C's %g."""
    return f"{x:g}"


#: the robots the port has built-in models for (mujoco.c's builtins): a
#: robot.toml of one of them may leave ``model`` out, and the port loads
#: the model of its build
# The robots whose model the port's build carries: one descriptor each,
# ports/mujoco/models/<robot_id>.model.toml (test_mujoco_model.py,
# test_builtin_list_is_the_ports, holds the two equal).
BUILTIN = ("agibot_x2", "diff_drive", "engineai_pm01", "quadcopter", "unitree_g1",
           "unitree_g1_12dof", "unitree_g1_23dof", "ur5")

_WHEELS = (("linear.x", "angular.z"), ("odom.x", "odom.y", "odom.yaw"))
_AUTOPILOT = (("velocity.x", "velocity.y", "velocity.z", "yaw_rate"),
              ("position.x", "position.y", "position.z", "yaw"))


def _mobile(m: Manifest) -> str | None:
    """mujoco.c's detect_mobile(): "wheels", "autopilot" or None."""
    pre = m.commands[0].name.split("/", 1)[0] if "/" in m.commands[0].name else None
    if pre is None:
        return None
    def has(chs, names, kind):
        return all(any(c.name == f"{pre}/{n}" and c.interface_type == kind for c in chs)
                   for n in names)
    if (len(m.commands), len(m.states)) == (2, 3) and has(m.commands, _WHEELS[0], "velocity") \
            and has(m.states, _WHEELS[1], "position"):
        return "wheels"
    if (len(m.commands), len(m.states)) == (4, 4) and has(m.commands, _AUTOPILOT[0], "velocity") \
            and has(m.states, _AUTOPILOT[1], "position"):
        return "autopilot"
    return None


def _manifest_joints(m: Manifest) -> list[str]:
    """mujoco.c's manifest_joints(): [hardware] joints, else the joints the
    channels name (before the last '/'), base_imu not one."""
    if m.hardware is not None and m.hardware.joints:
        return list(m.hardware.joints)
    out: list[str] = []
    for c in list(m.commands) + list(m.states):
        if "/" not in c.name:
            continue
        j = c.name.rsplit("/", 1)[0]
        if j != "base_imu" and j not in out:
            out.append(j)
    return out


def _name_map(text: str | None, joints: list[str], robot_id: str):
    """``joint_names`` ("A=B, C=D") as a dict, or a refusal (rule, message)."""
    out: dict[str, str] = {}
    for item in (text or "").split(","):
        item = item.strip(" ")
        if not item:
            continue
        if "=" not in item:
            return None, ("mujoco-joint", f': hardware.params.joint_names: "{item}": expected '
                          "MANIFEST_JOINT=MJCF_JOINT")
        k, v = (x.strip(" ") for x in item.split("=", 1))
        if k not in joints:
            return None, ("mujoco-joint", f': hardware.params.joint_names: "{k}" is not a joint '
                          f"of manifest {robot_id}")
        out.setdefault(k, v)
    return out, None


def _effort(m: Manifest, joint: str) -> tuple[float, float] | None:
    """The joint's effort command's limits, else its effort state's."""
    for chs in (m.commands, m.states):
        for c in chs:
            if c.name == f"{joint}/effort" and c.interface_type == "effort":
                return (c.min, c.max)
    return None


def _bind(m: Manifest, model: mjcf.Model, name: str, mj: str) -> tuple[str, str] | None:
    """mujoco.c's bind_joint(): a refusal, or None."""
    path = model.path
    j = model.joints.get(mj)
    if j is None:
        mapped = f' ("{mj}")' if mj != name else ""
        return ("mujoco-joint", f': joint "{name}"{mapped}: no joint of that name in {path} '
                "(hardware.params.joint_names maps manifest joints to the model's)")
    if j.type not in ("hinge", "slide"):
        return ("mujoco-joint", f': joint "{name}": {path}\'s joint "{mj}" is not a hinge or a '
                "slide")
    act = next((a for a in model.actuators if a.joint == mj), None)
    if act is None:
        return ("mujoco-joint", f': joint "{name}": no actuator drives {path}\'s joint "{mj}"')
    lo, hi = -math.inf, math.inf
    if act.force_range is not None:
        f0, f1 = act.gear * act.force_range[0], act.gear * act.force_range[1]
        lo, hi = min(f0, f1), max(f0, f1)
    if j.frc_range is not None:
        lo, hi = max(lo, j.frc_range[0]), min(hi, j.frc_range[1])
    an = act.name if act.name is not None else "?"
    want = _effort(m, name)
    if want is not None:
        if want[0] < lo or want[1] > hi:
            return ("mujoco-effort", f': joint "{name}": the manifest\'s effort limits '
                    f"[{_g(want[0])}, {_g(want[1])}] N.m exceed what {path}'s actuator \"{an}\" "
                    f"can give, [{_g(lo)}, {_g(hi)}]")
    elif not (math.isfinite(lo) and math.isfinite(hi)):
        return ("mujoco-effort", f': joint "{name}": no effort limit: the manifest has no '
                f"{name}/effort channel and {path}'s actuator \"{an}\" has no force range")
    return None


def _imu(m: Manifest, model: mjcf.Model, params: dict) -> tuple[str, str] | None:
    """mujoco.c's bind_imu(): the gyro (on a site) and the accelerometer."""
    if not any(c.name.startswith("base_imu/") for c in m.states):
        return None
    for key, kind, what, none in (
            ("imu_gyro", "gyro", "not a gyro sensor", "no gyro sensor on a site"),
            ("imu_accelerometer", "accelerometer", "not an accelerometer",
             "no accelerometer sensor")):
        name = params.get(key)
        if name is not None:
            found = next((x for x in model.sensors if x.name == name), None)
        else:
            found = next((x for x in model.sensors if x.type == kind), None)
        bad = None
        if found is None or (kind == "gyro" and found.type == kind and found.site is None):
            bad = none
        elif found.type != kind:
            bad = what
        if bad is not None:
            shown = f' = "{name}"' if name is not None else ""
            return ("mujoco-imu", f": hardware.params.{key}{shown}: {bad} in {model.path} (the "
                    "manifest has base_imu channels)")
    return None


def check_model(m: Manifest, toml_path: str) -> list[tuple[str, str]]:
    """The model-bound rules (see the module's text); ``toml_path`` is the
    robot.toml as given (a relative ``model`` is taken from its folder)."""
    hw = m.hardware
    if hw is None or hw.port != PORT:
        return []
    params = dict(hw.params)
    model_param = params.get("model")
    if not model_param:
        if m.robot_id in BUILTIN:
            return []  # the port's built-in model, where its build found it
        return [("mujoco-model", ": hardware.params.model: missing, and this build has no "
                 f"built-in model for robot {m.robot_id} (docs/ports/mujoco.md)")]
    mobile = _mobile(m)
    if mobile == "wheels":
        names = [params.get("wheel_left"), params.get("wheel_right")]
        for key, v in zip(("wheel_left", "wheel_right"), names):
            if not v:
                return [("mujoco-joint", f": hardware.params.{key}: missing: a differential "
                         "drive names its wheels' joints")]
        mj_names = names
    elif mobile == "autopilot":
        names, mj_names = [], []
    else:
        names = _manifest_joints(m)
        mapping, refusal = _name_map(params.get("joint_names"), names, m.robot_id)
        if refusal is not None:
            return [refusal]
        mj_names = [mapping.get(n, n) for n in names]
    path = model_param if os.path.isabs(model_param) else os.path.join(
        os.path.dirname(toml_path), model_param)
    try:
        model = mjcf.load(path)
    except mjcf.ModelError as e:
        return [("mujoco-model", f': hardware.params.model = "{model_param}": {e}')]
    for name, mj in zip(names, mj_names):
        refusal = _bind(m, model, name, mj)
        if refusal is not None:
            return [refusal]
    refusal = _imu(m, model, params)
    return [refusal] if refusal is not None else []


ROZRUN_ENV = "ROZ_ROZRUN"


def _rozrun() -> str | None:
    """rozrun, whose --check opens a port (see the module's text), or None."""
    given = os.environ.get(ROZRUN_ENV)
    if given:
        return given
    beside = Path(os.path.realpath(sys.argv[0])).parent / "rozrun"
    if beside.is_file() and os.access(beside, os.X_OK):
        return str(beside)
    return shutil.which("rozrun")


def check_open(m: Manifest, toml_path: str) -> list[tuple[str, str]]:
    """What the mujoco port's own open refuses of the robot.toml at
    ``toml_path`` (rozrun --check), as (rule, message); [] when it opens, or
    when no rozrun is found."""
    hw = m.hardware
    if hw is None or hw.port != PORT:
        return []
    exe = _rozrun()
    if exe is None:
        return []
    path = os.path.abspath(toml_path)
    try:
        done = subprocess.run([exe, "--robot", path, "--port", PORT, "--check"],
                              capture_output=True, text=True, errors="backslashreplace")
    except OSError as e:
        return [("mujoco-model", f": the port's own check (rozrun --check) cannot run: {exe}: "
                 f"{e.strerror or e}")]
    if done.returncode == 0:
        return []
    said = [line for line in done.stderr.splitlines() if line.startswith(f"rozrun: port {PORT}: ")]
    text = said[-1][len(f"rozrun: port {PORT}: "):] if said else \
        f"rozrun --check exit {done.returncode}: {done.stderr.strip()[-400:]}"
    for head in (f"{PORT}: {path}", PORT):  # the port's words name the file: it is the problem's
        if text.startswith(head + ": "):
            text = text[len(head):]
            break
    else:
        text = ": " + text
    rule = "mujoco-effort" if "ctrlrange" in text or "effort" in text else "mujoco-model"
    return [(rule, text)]
