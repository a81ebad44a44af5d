# SPDX-License-Identifier: Apache-2.0
"""``rozgen-nn deploy``: a trained policy and the deploy configuration it was
trained for, checked against a robot's manifest, turned into a ready
controller: the C source (roz_policy.h's runner over generated tables, the
network as rozgen.nn writes it) and its ``.wasm``.

    rozgen-nn deploy POLICY [--config DEPLOY.yaml] --robot ROBOT -o OUT.wasm
                     [--spec SPEC] [--command VX,VY,WZ] [--source OUT.c]

POLICY is a TorchScript or torch.save ``.pt``, an ONNX file or a numpy
``.npz`` (these two need ``--spec`` unless the file gives its layers).
DEPLOY.yaml is unitree_rl_gym's deploy configuration, in either of its
shapes (``deploy_mujoco``: kps/kds/default_angles of the policy's joints;
``deploy_real``: the same with ``leg_joint2motor_idx`` and the held joints'
``arm_waist_*``), plus the optional keys of ``EXTRA_KEYS``; without it the
ONNX file's metadata is the configuration. ROBOT is a built-in manifest's
name or a robot.toml. docs/policies.md describes every key.

Every error names the file, the key and the value. Nothing robot-specific is
written by hand: the controller is roz_policy.h driven by tables.
"""
from __future__ import annotations

import hashlib
import math
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from . import __version__, identity
from .fmt import c_double
from .nn import check, header

#: unitree_rl_gym's keys that roz reads, in both shapes
KEYS = ("control_decimation", "simulation_dt", "control_dt", "kps", "kds", "default_angles",
        "leg_joint2motor_idx", "arm_waist_joint2motor_idx", "arm_waist_kps", "arm_waist_kds",
        "arm_waist_target", "ang_vel_scale", "dof_pos_scale", "dof_vel_scale", "action_scale",
        "cmd_scale", "num_actions", "num_obs", "cmd_init", "max_cmd", "imu_type")
#: unitree_rl_gym's keys that say nothing the controller needs (paths,
#: the DDS wiring, the simulation's length)
IGNORED = ("policy_path", "xml_path", "simulation_duration", "msg_type", "lowcmd_topic",
           "lowstate_topic", "weak_motor")
#: roz's own optional keys (docs/policies.md)
EXTRA_KEYS = ("joint_names", "command_channels", "observations", "history", "gait_period",
              "clip_observations", "clip_actions", "gain_ramp", "move_s")

#: unitree_rl_gym's deploy_real around its policy (docs/deploy.md): the move to
#: the default pose takes 2 s (a constant there: its YAML has no key for it; roz's
#: optional ``move_s`` sets it) and the stop is its damping command, kd 8
MOVE_S = 2.0
STOP_DAMPING = 8.0
#: the deploy file's switches and the remote buttons deploy_real reads for them
#: (Start: to the default pose; A: run the policy; Select: damping and exit),
#: with roz's B back to the stand: the manifest's input on each button switches
DEPLOY_BUTTONS = (("start", "remote.btn.start"), ("run", "remote.btn.a"),
                  ("stand", "remote.btn.b"), ("stop", "remote.btn.select"))

#: observation terms: names (unitree_rl_gym's order is the default), their
#: roz_policy.h kinds, and the aliases Isaac Lab and mjlab metadata use
TERMS = {
    "ang_vel": ("ROZ_POLICY_OBS_ANG_VEL", ("base_ang_vel",)),
    "gravity": ("ROZ_POLICY_OBS_GRAVITY", ("projected_gravity", "gravity_orientation")),
    "command": ("ROZ_POLICY_OBS_COMMAND", ("velocity_commands", "generated_commands", "cmd",
                                           "commands")),
    "joint_pos": ("ROZ_POLICY_OBS_JOINT_POS", ("joint_pos_rel", "dof_pos", "qj")),
    "joint_vel": ("ROZ_POLICY_OBS_JOINT_VEL", ("joint_vel_rel", "dof_vel", "dqj")),
    "last_action": ("ROZ_POLICY_OBS_LAST_ACTION", ("actions", "action", "last_actions")),
    "phase": ("ROZ_POLICY_OBS_PHASE", ("gait_phase", "sin_cos_phase")),
}
#: roz/config.h's default ROZ_CFG_FUEL_MAX_PER_SECOND: the default ceiling on a
#: controller's declared fuel is this over the control rate
FUEL_MAX_PER_SECOND = 40000000
UNITREE_ORDER = ("ang_vel", "gravity", "command", "joint_pos", "joint_vel", "last_action", "phase")


class DeployError(ValueError):
    """A problem with the inputs, naming the file, key and value."""


@dataclass
class Term:
    name: str
    scale: list[float]


@dataclass
class Joint:
    name: str
    default: float
    kp: float
    kd: float
    action_scale: float = 0.0


@dataclass
class Plan:
    """Everything the controller is made of, checked."""
    manifest: object
    layers: list
    joints: list[Joint]
    held: list[Joint]
    terms: list[Term]
    decimation: int
    history: int
    gait_period: float
    obs_clip: float
    action_clip: float
    ramp: float
    command_ch: list[int]
    command_const: list[float]
    command_max: list[float]
    notes: list[str] = field(default_factory=list)
    sources: list[tuple[str, str]] = field(default_factory=list)  # (label, sha256)
    move_s: float = MOVE_S


# ---- reading the inputs ----------------------------------------------------------

def _sha256(path: str) -> str:
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def read_policy(path: str, spec: str | None):
    """(layers, metadata, sha256) of a policy file: rozgen.nn_export.read_policy,
    the one reader of every format (its refusals name the file)."""
    from . import nn_export
    p = nn_export.read_policy(path, spec=spec)
    return p.layers, dict(p.metadata or {}), p.source_sha256


def read_config(path: str) -> dict:
    """A deploy YAML as a dict: PyYAML's safe loader (no objects, no code),
    refusing a key given twice (YAML would keep the last silently)."""
    import yaml

    class Loader(yaml.SafeLoader):
        pass

    def mapping(loader, node, deep=False):
        seen = {}
        for k, _ in node.value:
            key = loader.construct_object(k, deep=deep)
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None, None, f"key '{key}' given twice (lines {seen[key]} and "
                    f"{k.start_mark.line + 1})", k.start_mark)
            seen[key] = k.start_mark.line + 1
        return loader.construct_mapping(node, deep=deep)
    Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, mapping)
    try:
        with open(path, encoding="utf-8") as f:
            doc = yaml.load(f, Loader=Loader)  # noqa: S506 (a SafeLoader)
    except OSError as e:
        raise DeployError(f"{path}: cannot read: {e.strerror or e}") from None
    except yaml.YAMLError as e:
        raise DeployError(f"{path}: not valid YAML: {e}") from None
    if not isinstance(doc, dict):
        raise DeployError(f"{path}: a deploy configuration is a mapping of keys, "
                          f"not {type(doc).__name__}")
    return doc


#: the policy rate assumed when ONNX metadata gives none: 50 Hz, the rate
#: legged_gym, unitree_rl_gym, Isaac Lab and mjlab train locomotion at
#: (physics 200 Hz or 500 Hz, decimation 4 or 10)
DEFAULT_CONTROL_DT = 0.02


def config_from_metadata(meta: dict, where: str, notes: list[str] | None = None) -> dict:
    """The deploy configuration that ONNX metadata gives (keys normalised as
    rozgen.nn_export.read_policy normalises them). The policy's rate is the
    metadata's control_dt (seconds between inferences), else 50 Hz, said in
    @p notes: Isaac Lab's and mjlab's metadata carry no rate, and their
    'decimation' counts physics steps, not the robot's ticks."""
    def need(key):
        if key not in meta:
            raise DeployError(f"{where}: metadata has no '{key}' and there is no --config")
        return meta[key]
    names = need("joint_names")
    names = names if isinstance(names, list) else [names]
    n = len(names)
    cfg = {"joint_names": names, "default_angles": _per_joint(need("default_joint_pos"), n),
           "kps": _per_joint(need("stiffness"), n), "kds": _per_joint(need("damping"), n),
           "action_scale": need("action_scale"), "num_actions": n,
           "control_dt": meta.get("control_dt", DEFAULT_CONTROL_DT)}
    if "control_dt" not in meta and notes is not None:
        notes.append(f"{where}: metadata has no control_dt: the policy runs at "
                     f"{1 / DEFAULT_CONTROL_DT:g} Hz (control_dt {DEFAULT_CONTROL_DT}); give a "
                     "--config for another rate")
    if "observation_names" in meta:
        obs = meta["observation_names"]
        obs = obs if isinstance(obs, list) else [obs]
        scales = meta.get("observation_scales", [1.0] * len(obs))
        if isinstance(scales, dict):  # name -> scale, a name it lacks at 1
            scales = [scales.get(o, 1.0) for o in obs]
        scales = scales if isinstance(scales, list) else [scales]
        if len(scales) != len(obs):
            raise DeployError(f"{where}: metadata 'observation_scales' has {len(scales)} values "
                              f"for {len(obs)} observation_names")
        cfg["observations"] = [{"name": o, "scale": s} for o, s in zip(obs, scales)]
    return cfg


def _per_joint(v, n):
    return v if isinstance(v, list) else [v] * n


# ---- the robot ------------------------------------------------------------------

def _up(*rel: str) -> list[Path]:
    """``rel`` under each folder above this package: in a checkout the
    repository, installed the prefix (whatever its libdir's depth)."""
    here = Path(__file__).resolve().parent
    return [p.joinpath(*rel) for p in here.parents if p.joinpath(*rel).is_dir()]


def _builtin_dirs() -> list[Path]:
    return _up("manifests") + _up("share", "roz", "manifests")


def sdk_dirs() -> list[Path]:
    return _up("sdk", "include") + _up("include", "roz", "sdk")


def load_robot(robot: str):
    """(manifest, path) of a built-in name or a robot.toml path."""
    from .load import load
    from .validate import validate
    path = robot
    if not (robot.endswith(".toml") or os.sep in robot):
        for d in _builtin_dirs():
            if (d / f"{robot}.toml").is_file():
                path = str(d / f"{robot}.toml")
                break
        else:
            known = sorted({p.stem for d in _builtin_dirs() if d.is_dir()
                            for p in d.glob("*.toml")})
            raise DeployError(f"--robot {robot}: not a built-in manifest ({', '.join(known)}) "
                              "nor a robot.toml")
    loaded = load(path)
    if loaded.data is None:
        raise DeployError("; ".join(f"{path}{p.message}" for p in loaded.problems))
    manifest, problems = validate(loaded.data)
    if manifest is None:
        raise DeployError("; ".join(f"{path}{p.message}" for p in problems))
    return manifest, path, loaded.sha256


# ---- checking -------------------------------------------------------------------

class _Cfg:
    """The configuration's values, each read with its key for messages."""

    def __init__(self, doc: dict, where: str):
        self.doc, self.where = doc, where

    def err(self, key, value, what) -> DeployError:
        return DeployError(f"{self.where}: {key}: {value!r}: {what}")

    def get(self, key, default=None):
        return self.doc.get(key, default)

    def number(self, key, default=None, lo=None, hi=None):
        v = self.doc.get(key, default)
        if v is None:
            raise DeployError(f"{self.where}: {key}: missing")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise self.err(key, v, "not a finite number")
        if lo is not None and v < lo or hi is not None and v > hi:
            raise self.err(key, v, f"outside [{lo}, {hi}]")
        return float(v)

    def integer(self, key, default=None, lo=None):
        v = self.doc.get(key, default)
        if v is None:
            raise DeployError(f"{self.where}: {key}: missing")
        if isinstance(v, float) and v.is_integer():
            v = int(v)
        if isinstance(v, bool) or not isinstance(v, int) or lo is not None and v < lo:
            raise self.err(key, v, f"not an integer of at least {lo}")
        return v

    def numbers(self, key, n=None, default=None):
        v = self.doc.get(key, default)
        if v is None:
            raise DeployError(f"{self.where}: {key}: missing")
        if not isinstance(v, list):
            raise self.err(key, v, "not a list of numbers")
        for k, x in enumerate(v):
            if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
                raise self.err(f"{key}[{k}]", x, "not a finite number")
        if n is not None and len(v) != n:
            raise self.err(key, v, f"{len(v)} values, the policy has {n}")
        return [float(x) for x in v]

    def scale(self, key, n, default=1.0):
        """A scale: a number (for every element) or a list of n."""
        v = self.doc.get(key, default)
        if isinstance(v, list):
            return self.numbers(key, n)
        return [self.number(key, default)] * n


def _joint_channels(m, name, where, key, value):
    """Indices of a joint's channels; refuses a joint the manifest lacks."""
    cmd = {c.name: i for i, c in enumerate(m.commands)}
    st = {c.name: i for i, c in enumerate(m.states)}
    want = {"pos": (cmd, f"{name}/position"), "kp": (cmd, f"{name}/stiffness"),
            "kd": (cmd, f"{name}/damping"), "q": (st, f"{name}/position"),
            "dq": (st, f"{name}/velocity")}
    out = {}
    for k, (table, ch) in want.items():
        if ch not in table:
            kind = "command" if table is cmd else "state"
            raise DeployError(f"{where}: {key}: {value!r}: joint '{name}' has no {kind} channel "
                              f"'{ch}' in the manifest {m.robot_id}")
        out[k] = table[ch]
    return out


def _check_within(m, where, key, k, value, channel):
    c = m.commands[channel]
    if not c.min <= value <= c.max:
        raise DeployError(f"{where}: {key}[{k}]: {value:g}: outside {c.name}'s limits "
                          f"[{c.min:g}, {c.max:g}] in the manifest {m.robot_id}")


def plan(layers, cfg_doc: dict, where: str, manifest, command: list[float] | None = None,
         notes: list[str] | None = None) -> Plan:
    """Checks the configuration against the network and the manifest."""
    m = manifest
    c = _Cfg(cfg_doc, where)
    notes = [] if notes is None else notes
    check(layers)
    unknown = sorted(set(cfg_doc) - set(KEYS) - set(IGNORED) - set(EXTRA_KEYS))
    if unknown:
        notes.append(f"{where}: keys roz does not read: {', '.join(unknown)}")
    if c.get("imu_type", "pelvis") != "pelvis":
        raise c.err("imu_type", c.get("imu_type"), "roz reads the pelvis IMU's channels; a torso "
                    "IMU needs the waist's transform, which roz_policy.h does not do")
    n_out = layers[-1].n_out
    n = c.integer("num_actions", n_out, lo=1)
    if n != n_out:
        raise c.err("num_actions", n, f"the network has {n_out} outputs")
    # the policy's joints: names, a motor map, or the manifest's first n
    hw = _motors(m)
    if c.get("joint_names") is not None:
        names = c.get("joint_names")
        if not isinstance(names, list) or len(names) != n or not all(isinstance(s, str)
                                                                     for s in names):
            raise c.err("joint_names", names, f"not a list of {n} joint names")
        key = "joint_names"
    elif c.get("leg_joint2motor_idx") is not None:
        idx = c.get("leg_joint2motor_idx")
        names = _motor_names(c, "leg_joint2motor_idx", idx, hw, n, m)
        key = "leg_joint2motor_idx"
    else:
        if len(hw) < n:
            raise DeployError(f"{where}: no joint_names nor leg_joint2motor_idx, and the manifest "
                              f"{m.robot_id} has {len(hw)} joints for {n} actions")
        names = hw[:n]
        key = "(the manifest's first joints)"
        notes.append(f"{where}: no joint map: the policy's {n} joints are the manifest's first "
                     f"{n} ({names[0]} ... {names[-1]}), in motor order")
    if len(set(names)) != len(names):
        raise c.err(key, names, "a joint named twice")
    kps, kds = c.numbers("kps", n), c.numbers("kds", n)
    defaults = c.numbers("default_angles", n)
    ascale = c.scale("action_scale", n, None)
    joints, channels = [], []
    for j, name in enumerate(names):
        ch = _joint_channels(m, name, where, key, name)
        _check_within(m, where, "kps", j, kps[j], ch["kp"])
        _check_within(m, where, "kds", j, kds[j], ch["kd"])
        _check_within(m, where, "default_angles", j, defaults[j], ch["pos"])
        joints.append(Joint(name, defaults[j], kps[j], kds[j], ascale[j]))
        channels.append(ch)
    # the held joints: the configuration's, then every other joint at the manifest's hold
    held = []
    if c.get("arm_waist_joint2motor_idx") is not None:
        idx = c.get("arm_waist_joint2motor_idx")
        hn = _motor_names(c, "arm_waist_joint2motor_idx", idx, hw, len(idx) if
                          isinstance(idx, list) else -1, m)
        hk = c.numbers("arm_waist_kps", len(hn))
        hd = c.numbers("arm_waist_kds", len(hn))
        ht = c.numbers("arm_waist_target", len(hn))
        for j, name in enumerate(hn):
            if name in names:
                raise c.err("arm_waist_joint2motor_idx", idx, f"joint '{name}' is the policy's too")
            ch = _joint_channels(m, name, where, "arm_waist_joint2motor_idx", idx[j])
            _check_within(m, where, "arm_waist_kps", j, hk[j], ch["kp"])
            _check_within(m, where, "arm_waist_kds", j, hd[j], ch["kd"])
            _check_within(m, where, "arm_waist_target", j, ht[j], ch["pos"])
            held.append(Joint(name, ht[j], hk[j], hd[j]))
    taken = set(names) | {h.name for h in held}
    rest = [j for j in hw if j not in taken]
    for name in rest:
        ch = _joint_channels(m, name, where, "(the manifest's hold)", name)
        kp, kd = m.commands[ch["kp"]].default, m.commands[ch["kd"]].default
        pos = m.commands[ch["pos"]]
        target = min(max(0.0, pos.min), pos.max)
        held.append(Joint(name, target, kp, kd))
    if rest:
        notes.append(f"{m.robot_id}: {len(rest)} joints the configuration does not name are held "
                     f"at 0 rad with the manifest's hold gains (its stiffness and damping "
                     f"defaults): {', '.join(rest)}")
    # decimation against the control rate
    rate = m.control_rate_hz
    if c.get("control_decimation") is not None:
        dec = c.integer("control_decimation", lo=1)
        if c.get("simulation_dt") is not None:
            dt = c.number("simulation_dt", lo=0.0)
            if abs(dt * rate - 1.0) > 1e-9:
                raise c.err("simulation_dt", dt, f"the policy was trained at {1 / dt:g} Hz "
                            f"physics; the robot {m.robot_id} runs at {rate} Hz "
                            f"(1/{rate} = {1 / rate:g} s)")
    elif c.get("control_dt") is not None:
        cdt = c.number("control_dt", lo=0.0)
        dec = round(cdt * rate)
        if dec < 1 or abs(dec - cdt * rate) > 1e-6:
            raise c.err("control_dt", cdt, f"not a whole number of the robot's {rate} Hz ticks")
    else:
        raise DeployError(f"{where}: neither control_decimation nor control_dt: the policy's rate "
                          "is unknown")
    if dec > 100:
        raise c.err("control_decimation", dec, "above 100: roz verifies a controller over ticks "
                    "0-99, which must include an inference tick after the first")
    if rate % dec:
        notes.append(f"{where}: decimation {dec} does not divide {rate} Hz: the policy runs at "
                     f"{rate / dec:g} Hz")
    # observations
    if c.get("observations") is not None:
        terms = _terms(c, n)
    else:
        terms = [Term("ang_vel", c.scale("ang_vel_scale", 3)), Term("gravity", [1.0] * 3),
                 Term("command", c.scale("cmd_scale", 3)),
                 Term("joint_pos", c.scale("dof_pos_scale", n)),
                 Term("joint_vel", c.scale("dof_vel_scale", n)),
                 Term("last_action", [1.0] * n), Term("phase", [1.0, 1.0])]
    frame = sum(len(t.scale) for t in terms)
    history = c.integer("history", 1, lo=1)
    if c.get("num_obs") is not None and c.integer("num_obs", lo=1) not in (frame, frame * history):
        raise c.err("num_obs", c.get("num_obs"), f"the observation terms make {frame} "
                    f"({' + '.join(f'{t.name} {len(t.scale)}' for t in terms)})")
    if layers[0].n_in != frame * history:
        raise DeployError(f"{where}: the observations make {frame} x history {history} = "
                          f"{frame * history} inputs; the network takes {layers[0].n_in}")
    # the velocity command: channels among the states, else a constant
    const = command if command is not None else (
        c.numbers("cmd_init", 3) if c.get("cmd_init") is not None else [0.0, 0.0, 0.0])
    cmax = c.numbers("max_cmd", 3) if c.get("max_cmd") is not None else [0.0] * 3
    chans = c.get("command_channels")
    # the operator's inputs are read as states after the states (state.get_all covers both)
    states = {s.name: i for i, s in enumerate(m.states + m.inputs)}
    command_ch = [-1, -1, -1]
    if chans is not None:
        if not isinstance(chans, list) or len(chans) != 3 or not all(isinstance(s, str)
                                                                     for s in chans):
            raise c.err("command_channels", chans, "not a list of 3 state channel names "
                        "(vx, vy, yaw rate)")
        found = [states.get(s, -1) for s in chans]
        if all(i >= 0 for i in found):
            command_ch = found
            notes.append(f"velocity command: read from the state channels {', '.join(chans)}")
        elif any(i >= 0 for i in found):
            raise c.err("command_channels", chans, "some of them are state channels of "
                        f"{m.robot_id}, some are not: {', '.join(s for s in chans if s not in states)}")
        else:
            notes.append(f"velocity command: the manifest {m.robot_id} has no state channels "
                         f"{', '.join(chans)}: the constant {_vec(const)} is compiled in")
    if command_ch[0] < 0 and any(t.name == "command" for t in terms):
        if chans is None:
            notes.append(f"velocity command: the constant {_vec(const)} (no command_channels in "
                         "the configuration)")
    gait = c.number("gait_period", 0.8, lo=1e-3)
    p = Plan(m, layers, joints, held, terms, dec, history, gait,
                c.number("clip_observations", 100.0, lo=0.0),
                c.number("clip_actions", 100.0, lo=0.0), c.number("gain_ramp", 1.0, lo=0.0),
                command_ch, const, cmax, notes)
    p.move_s = c.number("move_s", MOVE_S)  # its range is rozrun's to judge (docs/deploy.md)
    ceiling = FUEL_MAX_PER_SECOND // rate
    if fuel(p) > ceiling:
        notes.append(f"the controller declares {fuel(p)} fuel units a tick, above the default "
                     f"ceiling of {ceiling} on a {rate} Hz robot (ROZ_CFG_FUEL_MAX_PER_SECOND / "
                     "rate): the runtime refuses it at load unless its fuel_per_tick_max (rozrun "
                     "--fuel-max) allows it")
    return p


def _vec(v):
    return "(" + ", ".join(f"{x:g}" for x in v) + ")"


def _motors(m) -> list[str]:
    """The robot's joints in motor order: its [hardware] joints, else (a
    simulation robot such as unitree_g1_12dof) the joints of its position
    commands in channel order."""
    if m.hardware and m.hardware.joints:
        return list(m.hardware.joints)
    return [c.name[:-len("/position")] for c in m.commands
            if c.name.endswith("/position") and "/" not in c.name[:-len("/position")]]


def _motor_names(c: _Cfg, key, idx, hw, n, m):
    if not isinstance(idx, list) or (n >= 0 and len(idx) != n):
        raise c.err(key, idx, f"not a list of {n} motor indices")
    if not hw:
        raise c.err(key, idx, f"the manifest {m.robot_id} has no joints to map motor indices "
                    "to: name them with joint_names")
    out = []
    for k, i in enumerate(idx):
        if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < len(hw):
            raise c.err(f"{key}[{k}]", i, f"not a motor index of {m.robot_id} (0..{len(hw) - 1})")
        out.append(hw[i])
    if len(set(out)) != len(out):
        raise c.err(key, idx, "a motor named twice")
    return out


def _terms(c: _Cfg, n) -> list[Term]:
    alias = {a: k for k, (_, al) in TERMS.items() for a in (k,) + al}
    width = {"ang_vel": 3, "gravity": 3, "command": 3, "joint_pos": n, "joint_vel": n,
             "last_action": n, "phase": 2}
    out = []
    for k, t in enumerate(c.get("observations")):
        name, scale = (t, 1.0) if isinstance(t, str) else (
            (t.get("name"), t.get("scale", 1.0)) if isinstance(t, dict) else (None, None))
        key = f"observations[{k}]"
        if name not in alias:
            raise c.err(key, t, f"not an observation term roz_policy.h knows "
                        f"({', '.join(TERMS)}, or {', '.join(a for _, al in TERMS.values() for a in al)})")
        name = alias[name]
        w = width[name]
        sc = scale if isinstance(scale, list) else [scale] * w
        if len(sc) != w or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                   and math.isfinite(x) for x in sc):
            raise c.err(f"{key}.scale", scale, f"not a number or {w} numbers")
        out.append(Term(name, [float(x) for x in sc]))
    return out


# ---- the controller's C -----------------------------------------------------------

def _ints(v) -> str:
    return "{ " + ", ".join(str(i) for i in v) + " }"


def _dbls(v) -> str:
    return "{ " + ", ".join(c_double(x) for x in v) + " }"


def fuel(p: Plan) -> int:
    """Units an inference tick needs (roz_nn.h's costs), with a margin for
    the runner's own wasm: what the module declares (ROZ_FUEL_PER_TICK)."""
    units = 0
    for l in p.layers:
        if l.kind == "dense":
            units += l.n_in * l.n_out + 2 * l.n_out
            units += {"linear": 0, "relu": 2}.get(l.act, 24) * l.n_out
        else:
            g = 4 if l.kind == "lstm" else 3
            units += g * l.n_out * (l.n_in + l.n_out) + 4 * g * l.n_out + 24 * (g + 1) * l.n_out
    m = p.manifest
    runner = 2000 + 25 * (len(m.commands) + len(m.states)) + 40 * sum(len(t.scale)
                                                                       for t in p.terms) * p.history
    return int(math.ceil((units + runner) * 1.25 / 1000.0) * 1000)


def source(p: Plan, name: str = "policy") -> str:
    """The controller's C source."""
    m = p.manifest
    up = m.robot_id.upper()
    ch = [_joint_channels(m, j.name, "", "", "") for j in p.joints]
    hc = [_joint_channels(m, j.name, "", "", "") for j in p.held]
    quat = [_state(m, f"/orientation.{a}") for a in "xyzw"]
    gyro = [_state(m, f"/angular_velocity.{a}") for a in "xyz"]
    frame = sum(len(t.scale) for t in p.terms)
    net = header(p.layers, name, p.sources[0][0] if p.sources else "a policy")
    rec = identity.record(m)
    sha = bytes.fromhex(p.sources[0][1]) if p.sources else bytes(32)
    o = ["/* SPDX-License-Identifier: Apache-2.0 */",
         f"/* Generated by rozgen-nn deploy {__version__} from"]
    o += [f" *   {label} (sha256 {digest})" for label, digest in p.sources]
    o += [" * DO NOT EDIT: edit the sources and regenerate. */",
          f"/* The policy on {m.robot_id} ({m.control_rate_hz} Hz): roz_policy.h's runner over "
          "the tables below.",
          f" * Inference every {p.decimation} ticks ({m.control_rate_hz / p.decimation:g} Hz); "
          f"{len(p.joints)} joints driven, {len(p.held)} held.",
          f" * Observations ({frame} a frame, history {p.history}): "
          + ", ".join(f"{t.name} {len(t.scale)}" for t in p.terms) + ".",
          " * Velocity command: " + ("state channels " + ", ".join(
              (m.states + m.inputs)[i].name for i in p.command_ch) if p.command_ch[0] >= 0 else
              f"the constant {_vec(p.command_const)}") + ". */",
          '#include "roz_controller.h"', '#include "roz_policy.h"', "",
          f"ROZ_FUEL_PER_TICK({fuel(p)});", "",
          "/* The robot it was built for (roz/identity.h, custom section "
          f"\"{identity.SECTION}\") and the",
          " * sha256 of the policy file (custom section \"roz.policy\": version 1, 32 bytes). */",
          "#if defined(__wasm__)",
          f'__asm__(".section .custom_section.{identity.SECTION},\\"\\",@\\n"']
    o += _int8s(rec)
    o += ['        ".text");', '__asm__(".section .custom_section.roz.policy,\\"\\",@\\n"']
    o += _int8s(bytes([1]) + sha)
    o += ['        ".text");', "#endif", "", "/* ---- the network ---- */", net,
          "/* ---- the tables ---- */",
          f"#define {up}_N_STATES {len(m.states) + len(m.inputs)}", f"#define {up}_N_COMMANDS {len(m.commands)}",
          f"#define POLICY_FRAME {frame}", f"#define POLICY_HISTORY {p.history}",
          f"#define POLICY_JOINTS {len(p.joints)}",
          f"_Static_assert(POLICY_FRAME * POLICY_HISTORY == {name.upper()}_N_IN, "
          "\"observations and the network's inputs\");",
          f"_Static_assert(POLICY_JOINTS == {name.upper()}_N_OUT, \"joints and the network's "
          "outputs\");", ""]
    o.append("/* driven, in the policy's order: " + ", ".join(j.name for j in p.joints) + " */")
    for key, arr in (("q", [c["q"] for c in ch]), ("dq", [c["dq"] for c in ch]),
                     ("pos", [c["pos"] for c in ch]), ("kp_ch", [c["kp"] for c in ch]),
                     ("kd_ch", [c["kd"] for c in ch])):
        o.append(f"static const int j_{key}[POLICY_JOINTS] = {_ints(arr)};")
    for key, arr in (("default", [j.default for j in p.joints]), ("kp", [j.kp for j in p.joints]),
                     ("kd", [j.kd for j in p.joints]),
                     ("scale", [j.action_scale for j in p.joints])):
        o.append(f"static const double j_{key}[POLICY_JOINTS] = {_dbls(arr)};")
    nh = max(len(p.held), 1)
    o.append("/* held: " + (", ".join(j.name for j in p.held) or "none") + " */")
    for key, arr in (("pos", [c["pos"] for c in hc]), ("kp_ch", [c["kp"] for c in hc]),
                     ("kd_ch", [c["kd"] for c in hc])):
        o.append(f"static const int h_{key}[{nh}] = {_ints(arr or [0])};")
    for key, arr in (("target", [j.default for j in p.held]), ("kp", [j.kp for j in p.held]),
                     ("kd", [j.kd for j in p.held])):
        o.append(f"static const double h_{key}[{nh}] = {_dbls(arr or [0.0])};")
    o.append("/* every command channel's manifest default */")
    o.append(f"static const double command_init[{up}_N_COMMANDS] = "
             f"{_dbls([c.default for c in m.commands])};")
    for k, t in enumerate(p.terms):
        o.append(f"static const double term{k}_scale[{len(t.scale)}] = {_dbls(t.scale)}; "
                 f"/* {t.name} */")
    o.append(f"static const roz_policy_term_t terms[{len(p.terms)}] = {{")
    for k, t in enumerate(p.terms):
        o.append(f"    {{ {TERMS[t.name][0]}, term{k}_scale }},")
    o.append("};")
    o += ["", "static const roz_policy_config_t config = {",
          f"    {up}_N_STATES, {up}_N_COMMANDS, {m.control_rate_hz}, {p.decimation},",
          "    POLICY_JOINTS, j_q, j_dq, j_pos, j_kp_ch, j_kd_ch, j_default, j_kp, j_kd, j_scale,",
          f"    {len(p.held)}, h_pos, h_kp_ch, h_kd_ch, h_target, h_kp, h_kd,",
          "    command_init,", f"    {_ints(quat)}, {_ints(gyro)},",
          f"    {_ints(p.command_ch)}, {_dbls(p.command_const)}, {_dbls(p.command_max)},",
          f"    terms, {len(p.terms)}, POLICY_FRAME, POLICY_HISTORY,",
          f"    {c_double(p.gait_period)}, {c_double(p.obs_clip)}, {c_double(p.action_clip)}, {c_double(p.ramp)},",
          f"    {name.upper()}_N_IN, {name.upper()}_N_OUT, {name}_reset, {name}_forward,", "};", "",
          f"static double s[{up}_N_STATES], cmd[{up}_N_COMMANDS];",
          "static float frame[POLICY_FRAME], obs[POLICY_FRAME * POLICY_HISTORY], "
          "action[POLICY_JOINTS];",
          "static roz_policy_ws_t ws = { s, cmd, frame, obs, action };", "",
          "ROZ_PROCESS(tick)", "{", "    if (roz_policy_tick(&config, &ws, tick) != 0)",
          "        roz_request_estop(); /* the host refused a call: a broken build or another robot */", "}"]
    return "\n".join(o) + "\n"


def _int8s(data: bytes) -> list[str]:
    """Assembler lines of ``data``, 16 bytes a line."""
    return [f'        ".byte {", ".join(str(b) for b in data[i:i + 16])}\\n"'
            for i in range(0, len(data), 16)]


def _state(m, suffix):
    hits = [i for i, s in enumerate(m.states) if s.name.endswith(suffix)]
    if not hits:
        raise DeployError(f"the manifest {m.robot_id} has no state channel '*{suffix}': "
                          "a locomotion policy needs the base IMU's orientation and angular "
                          "velocity")
    base = [i for i in hits if m.states[i].name.startswith("base_imu/")]
    return (base or hits)[0]


# ---- building ---------------------------------------------------------------------

def find_clang() -> str:
    for c in (os.environ.get("ROZ_CLANG"), "clang", "clang-14"):
        if c and shutil.which(c):
            return shutil.which(c)
    raise DeployError("clang (with wasm-ld) is needed to build the .wasm: not found "
                      "(set ROZ_CLANG)")


def find_sdk(given: str | None) -> str:
    dirs = [Path(given)] if given else sdk_dirs()
    for d in dirs:
        if (d / "roz_policy.h").is_file():
            return str(d)
    raise DeployError(f"the controller SDK (roz_policy.h) is not in {', '.join(map(str, dirs))}: "
                      "give --sdk DIR")


def _toml_list(values, fmt) -> str:
    return "[" + ", ".join(fmt(v) for v in values) + "]"


def deploy_file(p: Plan) -> str:
    """The deploy sequence of the policy (docs/deploy.md), the file rozrun
    --deploy reads: the stand is the configuration's default pose and gains
    (the policy's joints, then the held ones), the move its move_s or
    deploy_real's 2 s, the stop deploy_real's damping, the switches the
    manifest's inputs on the buttons deploy_real reads. rozrun checks it
    (rozrun --check --deploy FILE): the rules are its own, in C."""
    m = p.manifest
    joints = p.joints + p.held
    damping = [m.commands[_joint_channels(m, j.name, "", "", "")["kd"]] for j in joints]
    stop = STOP_DAMPING
    low = min((c.max for c in damping), default=stop)
    if low < stop:
        stop = low
        p.notes.append(f"{m.robot_id}: the damping stop is {stop:g}, the largest damping every "
                       f"joint allows (deploy_real's is {STOP_DAMPING:g})")
    by_source = {i.source: i.name for i in m.inputs if i.source}
    o = ["# SPDX-License-Identifier: Apache-2.0", f"# Generated by rozgen-nn deploy {__version__} from"]
    o += [f"#   {label} (sha256 {digest})" for label, digest in p.sources]
    o += ["# DO NOT EDIT: edit the sources and regenerate.",
          f"# The deploy sequence of the policy on {m.robot_id} (docs/deploy.md), as unitree_rl_gym's",
          "# deploy_real runs it: zero torque until start, the default pose over move_s, held until",
          "# run, the policy, damping at stop. rozrun --deploy FILE runs it; rozrun --check",
          "# --deploy FILE checks it against the robot.", "",
          "[deploy]", f'robot = "{m.robot_id}"',
          f"move_s = {c_double(p.move_s)}  # s: the configuration's move_s, else deploy_real's "
          "2 s (its YAML has no key for it)",
          f"stop_damping = {c_double(stop)}  # N*m*s/rad on every joint: deploy_real's damping "
          "command (kp 0, kd 8)", ""]
    found = [(key, by_source[src], src) for key, src in DEPLOY_BUTTONS if src in by_source]
    missing = [f"{key} ({src})" for key, src in DEPLOY_BUTTONS if src not in by_source]
    o.append("# the switches: the manifest's inputs on the remote's buttons deploy_real reads "
             "(B: roz's back to the stand)")
    if missing:
        o.append(f"# no input of {m.robot_id} on: {', '.join(missing)}; rozrun --stage-at or "
                 "roz_runtime_stage_request() switch those")
        p.notes.append(f"{m.robot_id}: no operator input on the remote's "
                       f"{', '.join(missing)}: the deploy file leaves those switches to rozrun "
                       "--stage-at and the API")
    if found:
        o.append("[deploy.inputs]")
        o += [f'{key} = "{name}"  # {src}' for key, name, src in found]
    o += ["", "# the stand: the configuration's default_angles, kps and kds, then the held joints'",
          "# targets and gains (arm_waist_*, else the manifest's hold at 0 rad)",
          "[deploy.stand]",
          "joints = " + _toml_list([j.name for j in joints], lambda s: f'"{s}"'),
          "pose = " + _toml_list([j.default for j in joints], c_double),
          "kp = " + _toml_list([j.kp for j in joints], c_double),
          "kd = " + _toml_list([j.kd for j in joints], c_double), ""]
    return "\n".join(o)


def sdk_includes(sdk: str) -> list[str]:
    """The -I flags of the SDK in @p sdk: installed, roz_math.h is beside its
    headers; in a checkout it is the core's, lib/math/ (roz::sdk's include
    folders, sdk/CMakeLists.txt)."""
    math = Path(sdk).resolve().parent.parent / "lib" / "math"
    extra = [] if (Path(sdk) / "roz_math.h").is_file() or not math.is_dir() else [f"-I{math}"]
    return [f"-I{sdk}"] + extra


def compile_wasm(c_path: str, out: str, sdk: str, clang: str | None = None) -> None:
    """clang with roz_add_wasm_controller()'s flags (cmake/RozWasm.cmake)."""
    cmd = [clang or find_clang(), "--target=wasm32", "-O2", "-nostdlib", "-fno-builtin",
           "-std=c11", "-Wall", "-Wextra", "-Werror", *sdk_includes(sdk), "-Wl,--no-entry",
           "-Wl,--strip-all", "-Wl,-z,stack-size=16384", "-o", out, c_path]
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        raise DeployError(f"{c_path}: clang wasm32 failed:\n{r.stdout}")


def deploy(policy: str, config: str | None, robot: str, out: str, *, spec: str | None = None,
           command: list[float] | None = None, c_out: str | None = None, sdk: str | None = None,
           wasm: bool = True, deploy_out: str | None = None) -> Plan:
    """The whole command; returns the plan (its notes say what was assumed)."""
    layers, meta, digest = read_policy(policy, spec)
    manifest, mpath, msha = load_robot(robot)
    notes: list[str] = []
    if config is not None:
        doc, where, csha = read_config(config), config, _sha256(config)
    else:
        notes.append(f"{policy}: no --config: the configuration is the file's metadata")
        doc, where, csha = config_from_metadata(meta, policy, notes), policy, None
    p = plan(layers, doc, where, manifest, command, notes)
    p.sources = [(os.path.basename(policy), digest)]
    if config is not None:
        p.sources.append((os.path.basename(config), csha))
    p.sources.append((os.path.basename(mpath), msha))
    text = source(p)
    c_out = c_out or (out[:-5] + ".c" if out.endswith(".wasm") else out + ".c")
    Path(c_out).write_text(text, encoding="utf-8")
    stem = out[:-5] if out.endswith(".wasm") else out
    Path(deploy_out or stem + ".deploy.toml").write_text(deploy_file(p), encoding="utf-8")
    if wasm:
        sdk_dir = find_sdk(sdk)
        with tempfile.TemporaryDirectory() as tmp:
            tmp_out = os.path.join(tmp, "out.wasm")
            compile_wasm(c_out, tmp_out, sdk_dir)
            shutil.copyfile(tmp_out, out)
    return p


def parse_command(text: str) -> list[float]:
    try:
        v = [float(x) for x in text.split(",")]
    except ValueError:
        v = []
    if len(v) != 3 or not all(math.isfinite(x) for x in v):
        raise DeployError(f"--command {text!r}: not three numbers vx,vy,wz (m/s, m/s, rad/s)")
    return v


# ---- the numpy reference of the runner ------------------------------------------------

def reference(p: Plan, states) -> "list":
    """What roz_policy.h sends, computed in numpy over a state frame per
    tick from tick 0 (float64 arithmetic, the observations rounded to
    float32 as the runner does; the network by rozgen.nn.forward): a list of
    command vectors. For tests: the C agrees within the network's float32
    rounding."""
    import numpy as np
    from .nn import forward
    m = p.manifest
    ch = [_joint_channels(m, j.name, "", "", "") for j in p.joints]
    hc = [_joint_channels(m, j.name, "", "", "") for j in p.held]
    quat = [_state(m, f"/orientation.{a}") for a in "xyzw"]
    gyro = [_state(m, f"/angular_velocity.{a}") for a in "xyz"]
    rate = m.control_rate_hz
    clip = lambda v, c: np.float32(min(max(v, -c), c) if c > 0 else v)  # noqa: E731
    cmd = np.array([c.default for c in m.commands], dtype=np.float64)
    action = np.zeros(len(p.joints), dtype=np.float32)
    inputs, hist, out = [], None, []
    for tick, s in enumerate(states):
        ramp = min(1.0, tick / (rate * p.ramp)) if p.ramp > 0 else 1.0
        if tick == 0:
            for j, c in enumerate(ch):
                cmd[c["pos"]] = p.joints[j].default
            for j, c in enumerate(hc):
                cmd[c["pos"]] = p.held[j].default
        if tick % p.decimation == 0:
            x, y, z, w = (s[i] for i in quat)
            frame = []
            for t in p.terms:
                if t.name == "ang_vel":
                    v = [s[i] for i in gyro]
                elif t.name == "gravity":
                    v = [2.0 * (w * y - x * z), -2.0 * (y * z + w * x), -1.0 + 2.0 * (x * x + y * y)]
                elif t.name == "command":
                    v = []
                    for k in range(3):
                        u = s[p.command_ch[k]] if p.command_ch[k] >= 0 else p.command_const[k]
                        u = u if math.isfinite(u) else 0.0
                        mx = p.command_max[k]
                        v.append(min(max(u, -mx), mx) if mx > 0 else u)
                elif t.name == "joint_pos":
                    v = [s[c["q"]] - p.joints[j].default for j, c in enumerate(ch)]
                elif t.name == "joint_vel":
                    v = [s[c["dq"]] for c in ch]
                elif t.name == "last_action":
                    v = [float(a) for a in action]
                else:
                    cycles = (tick // p.decimation + 1) * p.decimation / (rate * p.gait_period)
                    ph = cycles - math.floor(cycles)
                    v = [math.sin(2 * math.pi * ph), math.cos(2 * math.pi * ph)]
                frame += [clip(a * b, p.obs_clip) for a, b in zip(v, t.scale)]
            frame = np.array(frame, dtype=np.float32)
            hist = np.tile(frame, p.history) if hist is None else np.concatenate(
                [hist[len(frame):], frame])
            inputs.append(hist.copy())
            a = forward(p.layers, np.array(inputs))[-1]
            action = np.array([clip(v, p.action_clip) for v in a], dtype=np.float32)
            for j, c in enumerate(ch):
                cmd[c["pos"]] = p.joints[j].default + p.joints[j].action_scale * float(action[j])
        for j, c in enumerate(ch):
            cmd[c["kp"]], cmd[c["kd"]] = ramp * p.joints[j].kp, p.joints[j].kd
        for j, c in enumerate(hc):
            cmd[c["kp"]], cmd[c["kd"]] = ramp * p.held[j].kp, p.held[j].kd
        out.append(cmd.copy())
    return out
