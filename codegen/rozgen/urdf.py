# SPDX-License-Identifier: Apache-2.0
"""The ``rozgen-urdf`` command: a robot.toml from a URDF.

    rozgen-urdf [-o robot.toml] [--force] [--robot-id ID] [--robot-class CLASS]
                [--rate HZ] [--command KIND[,KIND...]] [--states KIND[,KIND...]]
                [--kp-max N --kd-max N] [--imu LINK] [--humanoid] URDF

Writes a robot.toml (to stdout without ``-o``; an existing file only with
``--force``) that rozgen's own rules accept, to review and edit: it is a
starting point, never regenerated. docs/urdf.md describes the mapping:

- every revolute, continuous and prismatic joint, in file order, gets
  channels named ``<joint>/<interface>``; fixed joints are skipped, mimic
  joints are not commanded (a comment names them), floating and planar
  joints are skipped with a comment;
- the interfaces are those of the joint's ``<ros2_control>`` entry
  (command and state interfaces position, velocity, effort; others are
  noted in a comment); where the URDF has no ``<ros2_control>`` tag every
  joint gets the ``--command`` commands (velocity by default; a list may
  add stiffness and damping, whose limits ``--kp-max``/``--kd-max`` give:
  a URDF has none) and the ``--states`` states (position and velocity by
  default), and where it has one, only the joints it lists get
  channels. The hardware plugin and its parameters are not carried over;
- ``--imu LINK`` adds the ten base_imu states (orientation, angular
  velocity, linear acceleration) of an IMU on that link; ``--humanoid`` is
  the built-in humanoids' layout a policy deployment reads (commands
  position, velocity, stiffness, damping, effort; states position,
  velocity, effort; robot_class humanoid) and needs ``--imu``;
- limits come from ``<limit lower upper velocity effort>``, in rad, rad/s,
  N*m (revolute, continuous) or m, m/s, N (prismatic); a limit a channel
  needs that the URDF lacks (or gives as 0, or with lower >= upper) is
  refused, naming the element and its line: a guessed limit is a limit
  nobody chose;
- a continuous joint has no position limits, and robot.toml needs finite
  ones: its position channels get +-CONTINUOUS_LIMIT, commented, and its
  velocity and effort commands are not paired with its position (a paired
  command would be stopped at those limits);
- every other command of a joint with a position state is paired with it
  (``position_state_index``): a position command then holds the measured
  position as its safe default, and a velocity or effort command stops at
  the position limits.

An unexpanded xacro (``xacro:`` elements or ``${...}``) is refused: run
``xacro robot.urdf.xacro > robot.urdf`` first. Problems print as
``<file>:<line>: <message>``; exit status 0, or 2 on any problem.
"""

import argparse
import math
import os
import re
import sys
import tomllib
import xml.parsers.expat
from dataclasses import dataclass, field

from rozgen.validate import validate

EXIT_OK = 0
EXIT_ERROR = 2

#: The position limits written for a continuous joint (rad): robot.toml
#: needs finite limits; a range this wide never binds in practice.
CONTINUOUS_LIMIT = 1.0e9

#: Interfaces roz maps, in the order their channel blocks are written.
INTERFACES = ("position", "velocity", "effort")

#: Commands a joint may get without a <ros2_control> tag, in block order
#: (the built-in humanoids': the gains between velocity and effort).
COMMANDS = ("position", "velocity", "stiffness", "damping", "effort")

#: --humanoid: the built-in humanoids' channels (docs/robot-toml.md).
HUMANOID_COMMANDS = COMMANDS
HUMANOID_STATES = INTERFACES

_UNITS = {
    ("angular", "position"): "rad", ("angular", "velocity"): "rad/s",
    ("angular", "effort"): "N*m",
    ("linear", "position"): "m", ("linear", "velocity"): "m/s", ("linear", "effort"): "N",
    ("angular", "stiffness"): "N*m/rad", ("angular", "damping"): "N*m*s/rad",
    ("linear", "stiffness"): "N/m", ("linear", "damping"): "N*s/m",
}

#: The base IMU's ten states (the built-in humanoids'): name, interface,
#: unit, limit, default. The rate and acceleration ranges are a typical MEMS
#: full scale (2000 deg/s, 16 g), written with a comment to set the IMU's own.
IMU_STATES = tuple(
    [(f"base_imu/orientation.{a}", "orientation", "", 1.0, 1.0 if a == "w" else 0.0)
     for a in "xyzw"]
    + [(f"base_imu/angular_velocity.{a}", "velocity", "rad/s", 35.0, 0.0) for a in "xyz"]
    + [(f"base_imu/linear_acceleration.{a}", "acceleration", "m/s^2", 160.0,
        9.81 if a == "z" else 0.0) for a in "xyz"])


class UrdfError(Exception):
    """A refusal: ``line`` is the line of the element it names (0: none)."""

    def __init__(self, line: int, message: str) -> None:
        super().__init__(message)
        self.line = line


# ---- XML with line numbers ----------------------------------------------------

@dataclass
class Element:
    tag: str
    attrib: dict
    line: int
    children: list = field(default_factory=list)
    text: str = ""

    def find_all(self, tag: str) -> list:
        return [c for c in self.children if c.tag == tag]

    def find(self, tag: str):
        found = self.find_all(tag)
        return found[0] if found else None


def parse_xml(data: bytes) -> Element:
    """The document as Elements carrying their line numbers (expat's).
    Namespaced names keep their prefix (``xacro:macro``), so an unexpanded
    xacro is recognised; no DTD or external entity is loaded."""
    parser = xml.parsers.expat.ParserCreate()
    stack: list[Element] = []
    root: list[Element] = []
    # each open element's text in pieces, joined once at its end: expat hands
    # text over line by line, and adding each to a string is quadratic
    pieces: list[list[str]] = []

    def start(tag, attrib):
        el = Element(tag, dict(attrib), parser.CurrentLineNumber)
        if stack:
            stack[-1].children.append(el)
        else:
            root.append(el)
        stack.append(el)
        pieces.append([])

    def end(_tag):
        stack.pop().text = "".join(pieces.pop())

    def chars(text):
        if pieces:
            pieces[-1].append(text)

    def no_entities(*_args):
        raise UrdfError(parser.CurrentLineNumber, "the file declares an entity; a URDF has none")

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars
    parser.EntityDeclHandler = no_entities
    try:
        parser.Parse(data, True)
    except xml.parsers.expat.ExpatError as e:
        raise UrdfError(e.lineno, f"not well-formed XML: {xml.parsers.expat.ErrorString(e.code)}"
                                  f" (column {e.offset + 1})") from None
    return root[0]


def _walk(el: Element):
    yield el
    for child in el.children:
        yield from _walk(child)


def refuse_xacro(root: Element) -> None:
    """An unexpanded xacro is not a URDF: refuse it, naming the first sign."""
    for el in _walk(root):
        if el.tag.startswith("xacro:"):
            raise UrdfError(el.line, f"<{el.tag}>: an unexpanded xacro; expand it first "
                                     "(xacro robot.urdf.xacro > robot.urdf)")
        for key, value in el.attrib.items():
            if "${" in value or "$(" in value:
                raise UrdfError(el.line, f"<{el.tag}> {key}=\"{value}\": an unexpanded xacro "
                                         "expression; expand it first "
                                         "(xacro robot.urdf.xacro > robot.urdf)")


# ---- the URDF's joints ----------------------------------------------------------

@dataclass
class Joint:
    name: str
    kind: str  # revolute, continuous, prismatic
    line: int
    limit: Element | None
    commands: list = field(default_factory=list)  # interface names, in INTERFACES order
    states: list = field(default_factory=list)
    notes: list = field(default_factory=list)  # comment lines for robot.toml
    bounds: dict = field(default_factory=dict)  # command interface: ros2_control (min, max, line)


def _number(el: Element, key: str) -> float | None:
    """A numeric attribute, or None when absent; refuses one that is not a
    finite number."""
    if key not in el.attrib:
        return None
    text = el.attrib[key].strip()
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise UrdfError(el.line, f"<{el.tag}> {key}=\"{text}\": not a finite number")
    return value


def _ros2_control(root: Element) -> dict | None:
    """{joint name: (element, commands, states, notes)} of every
    <ros2_control> tag's joints, or None when the URDF has no such tag."""
    tags = root.find_all("ros2_control")
    if not tags:
        return None
    out = {}
    for tag in tags:
        for el in tag.find_all("joint"):
            name = el.attrib.get("name")
            if not name:
                raise UrdfError(el.line, "<ros2_control> <joint> has no name")
            if name in out:
                raise UrdfError(el.line, f"<ros2_control> <joint name=\"{name}\">: listed twice "
                                         f"(first at line {out[name][0].line})")
            lists = {"command_interface": [], "state_interface": []}
            notes = []
            bounds = {}
            for kind, found in lists.items():
                for iface in el.find_all(kind):
                    iname = iface.attrib.get("name", "")
                    if iname in INTERFACES:
                        if iname not in found:
                            found.append(iname)
                        if kind == "command_interface":
                            bounds[iname] = _param_bounds(iface)
                    else:
                        notes.append(f"its ros2_control {kind} \"{iname}\" has no roz channel "
                                     "type and is left out")
            out[name] = (el, sorted(lists["command_interface"], key=INTERFACES.index),
                         sorted(lists["state_interface"], key=INTERFACES.index), notes, bounds)
    return out


def _param_bounds(iface: Element) -> tuple:
    """(min, max, line) of a ros2_control command interface's min and max
    parameters (None where absent)."""
    found = {"min": None, "max": None}
    for param in iface.find_all("param"):
        key = param.attrib.get("name")
        if key in found:
            text = param.text.strip()
            try:
                value = float(text)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise UrdfError(param.line, f"<param name=\"{key}\">{text}</param>: not a "
                                            "finite number")
            found[key] = value
    return found["min"], found["max"], iface.line


def read_joints(root: Element, default_command, default_states=("position", "velocity")
                ) -> tuple[list, list]:
    """The joints that get channels, and comment lines about the others;
    without a <ros2_control> tag each gets @p default_command (one
    interface, or a sequence in COMMANDS order) and @p default_states."""
    if root.tag != "robot":
        raise UrdfError(root.line, f"<{root.tag}>: a URDF's root element is <robot>")
    control = _ros2_control(root)
    joints, notes, seen = [], [], {}
    for el in root.find_all("joint"):
        name = el.attrib.get("name")
        kind = el.attrib.get("type")
        if not name:
            raise UrdfError(el.line, "<joint> has no name")
        if name in seen:
            raise UrdfError(el.line, f"<joint name=\"{name}\">: a second joint of that name "
                                     f"(the first is at line {seen[name]})")
        seen[name] = el.line
        if kind == "fixed":
            continue
        if kind in ("floating", "planar"):
            notes.append(f"{kind} joint {name} (line {el.line}): not an actuated joint, left out")
            continue
        if kind not in ("revolute", "continuous", "prismatic"):
            raise UrdfError(el.line, f"<joint name=\"{name}\"> type=\"{kind}\": expected revolute, "
                                     "continuous, prismatic, fixed, floating or planar")
        mimic = el.find("mimic")
        if mimic is not None:
            follows = mimic.attrib.get("joint", "?")
            factor = mimic.attrib.get("multiplier", "1")
            offset = mimic.attrib.get("offset", "0")
            notes.append(f"mimic joint {name} (line {el.line}) follows {follows} "
                         f"(x {factor} + {offset}): not commanded, no channels")
            continue
        joint = Joint(name, kind, el.line, el.find("limit"))
        if control is None:
            joint.commands = [default_command] if isinstance(default_command, str) \
                else list(default_command)
            joint.states = list(default_states)
        elif name in control:
            _, joint.commands, joint.states, joint.notes, joint.bounds = control[name]
            if not joint.commands and not joint.states:
                notes.append(f"joint {name} (line {el.line}): ros2_control lists no position, "
                             "velocity or effort interface; no channels")
                continue
        else:
            notes.append(f"joint {name} (line {el.line}): not in ros2_control; no channels")
            continue
        joints.append(joint)
    if control is not None:
        for name, (el, *_rest) in control.items():
            if name not in seen:
                raise UrdfError(el.line, f"<ros2_control> <joint name=\"{name}\">: the URDF has "
                                         "no joint of that name")
    return joints, notes


# ---- channels -------------------------------------------------------------------

@dataclass
class Channel:
    name: str
    interface: str
    unit: str
    low: float
    high: float
    default: float
    joint: Joint
    comment: str = ""
    pair: int = -1


def _limits(joint: Joint, interface: str) -> tuple[float, float, str]:
    """(min, max, comment) of one of the joint's interfaces."""
    where = f"<joint name=\"{joint.name}\">"
    limit = joint.limit
    if interface == "position" and joint.kind == "continuous":
        return (-CONTINUOUS_LIMIT, CONTINUOUS_LIMIT,
                "continuous joint: the URDF has no position limits and robot.toml needs "
                "finite ones;\n# this range never binds: set the one its driver reports "
                "(e.g. [-3.141593, 3.141593]\n# if it wraps)")
    if limit is None:
        raise UrdfError(joint.line, f"{where}: no <limit>; its {interface} channel needs one")
    line = limit.line
    if interface == "position":
        lower, upper = _number(limit, "lower"), _number(limit, "upper")
        if lower is None or upper is None:
            missing = "lower" if lower is None else "upper"
            raise UrdfError(line, f"{where} <limit>: no {missing}; a {joint.kind} joint's "
                                  "position needs both (URDF's default 0 would lock it)")
        if not lower < upper:
            raise UrdfError(line, f"{where} <limit> lower=\"{limit.attrib['lower']}\" "
                                  f"upper=\"{limit.attrib['upper']}\": lower must be below upper")
        return lower, upper, ""
    value = _number(limit, interface)
    if value is None or value <= 0.0:
        got = "no" if value is None else f"{interface}=\"{limit.attrib[interface]}\", not a"
        raise UrdfError(line, f"{where} <limit>: {got} {interface} limit above 0; its "
                              f"{interface} channel needs one")
    return -value, value, ""


def _gain_limits(joint: Joint, interface: str, gains: dict) -> tuple[float, float, str]:
    """(0, max, comment) of a stiffness or damping command: the URDF has no
    gains, so the maximum is the command line's (--kp-max, --kd-max)."""
    option = "--kp-max" if interface == "stiffness" else "--kd-max"
    high = gains.get(interface)
    if high is None:
        raise UrdfError(0, f"joint {joint.name}: a {interface} command needs {option}: a URDF "
                           "has no gain limits (the largest gain the robot's drivers take)")
    return 0.0, high, (f"limits: {option} (a URDF has no gains); default 0: a stop leaves the "
                       "joint unheld:\n# set the hold gain its stop needs (docs/robot-toml.md)")


def imu_states(root: Element, link: str) -> list:
    """The ten base_imu states of an IMU on @p link (a link of the URDF)."""
    links = [el for el in root.find_all("link") if el.attrib.get("name") == link]
    if not links:
        raise UrdfError(root.line, f"--imu {link}: the URDF has no <link name=\"{link}\"> (the "
                                   "link the IMU is mounted on, e.g. the pelvis's IMU link)")
    out = []
    for k, (name, interface, unit, limit, default) in enumerate(IMU_STATES):
        comment = ""
        if k == 0:
            comment = (f"the IMU on link {link} (line {links[0].line}); orientation a unit "
                       "quaternion, x, y, z, w")
        elif interface != "orientation" and name.endswith(".x"):
            comment = ("range: a typical MEMS full scale (2000 deg/s, 16 g); set your IMU's "
                       "(the URDF gives none)")
        out.append(Channel(name, interface, unit, -limit, limit, default, None, comment))
    return out


def channels(joints: list, gains: dict | None = None) -> tuple[list, list]:
    """(commands, states), blocks by interface (positions, velocities,
    efforts), each block in joint order; commands paired with their joint's
    position state, except velocity and effort commands of continuous
    joints."""
    def make(joint, interface, command=False):
        if interface in ("stiffness", "damping"):
            low, high, comment = _gain_limits(joint, interface, gains or {})
        else:
            low, high, comment = _limits(joint, interface)
        pmin, pmax, line = joint.bounds.get(interface, (None, None, 0)) if command else (None,) * 3
        if pmin is not None or pmax is not None:
            # ros2_control's own bounds on the command: the tighter wins
            low = low if pmin is None else max(low, pmin)
            high = high if pmax is None else min(high, pmax)
            if not low < high:
                raise UrdfError(line, f"<ros2_control> <joint name=\"{joint.name}\"> "
                                      f"<command_interface name=\"{interface}\">: its min/max "
                                      "leave nothing of the URDF's <limit>")
            comment = (comment + "; " if comment else "") + \
                "limits: the URDF's <limit> within ros2_control's min/max"
        default = min(max(0.0, low), high)
        unit = _UNITS[("linear" if joint.kind == "prismatic" else "angular", interface)]
        return Channel(f"{joint.name}/{interface}", interface, unit, low, high, default, joint,
                       comment)

    states = [make(j, i) for i in INTERFACES for j in joints if i in j.states]
    commands = [make(j, i, True) for i in COMMANDS for j in joints if i in j.commands]
    for prev, c in zip([None] + commands, commands):
        if c.interface in ("stiffness", "damping") and prev is not None \
                and prev.interface == c.interface:
            c.comment = ""  # said once, at the block's first channel
    position_of = {s.joint.name: k for k, s in enumerate(states) if s.interface == "position"}
    for c in commands:
        # A paired position command holds the measured position as its safe
        # default; a paired velocity or effort command is stopped at the
        # position limits, which a continuous joint does not have.
        if c.joint.name not in position_of or c.interface in ("stiffness", "damping"):
            continue
        if c.joint.kind != "continuous" or c.interface == "position":
            c.pair = position_of[c.joint.name]
        else:
            c.comment = (f"not paired with {c.joint.name}/position: a continuous joint has no "
                         "position limit to stop at")
    return commands, states


# ---- robot.toml -----------------------------------------------------------------

def _float(value: float) -> str:
    if abs(value) >= 1.0e6:
        return f"{value:.1e}"
    text = repr(float(value))
    return text if ("." in text or "e" in text or "inf" in text or "nan" in text) else text + ".0"


def _toml_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def robot_id_of(name: str) -> str:
    """A robot_id ([a-z][a-z0-9_]*, at most 32) from the URDF's robot name."""
    rid = re.sub(r"[^a-z0-9_]+", "_", name.lower()).strip("_")
    if not rid or not rid[0].isalpha():
        rid = "robot_" + rid if rid else "robot"
    return rid[:32].rstrip("_")


def to_toml(source: str, robot_id: str, robot_class: str, rate: int, commands: list,
            states: list, notes: list, joints: list, ros2_control: bool) -> str:
    out = [
        f"# Imported from {source} by rozgen-urdf: a starting point to review and edit",
        "# (it is not regenerated). Check every limit against the robot's data sheet,",
        "# the defaults (the values roz falls back to), and add max_rate_of_change",
        "# and limit_margin where the robot needs them (docs/robot-toml.md).",
    ]
    if ros2_control:
        out.append("# The URDF's ros2_control hardware plugin and its parameters are not carried")
        out.append("# over: roz drives a robot through a port ([hardware], docs/ports/).")
    for note in notes:
        out.append(f"# {note}")
    for joint in joints:
        for note in joint.notes:
            out.append(f"# joint {joint.name}: {note}")
    out += ["", "[manifest]", f"robot_id = {_toml_string(robot_id)}"]
    if robot_class:
        out.append(f"robot_class = {_toml_string(robot_class)}")
    out.append(f"control_rate_hz = {rate}")
    for kind, chans in (("commands", commands), ("states", states)):
        for k, c in enumerate(chans):
            out += ["", f"[[manifest.{kind}]]   # {k}"]
            if c.comment:
                out.append(f"# {c.comment}")
            out += [f"name = {_toml_string(c.name)}",
                    f"interface_type = \"{c.interface}\"",
                    f"unit = \"{c.unit}\"",
                    f"limits = [{_float(c.low)}, {_float(c.high)}]",
                    f"default = {_float(c.default)}"]
            if c.pair >= 0:
                out.append(f"position_state_index = {c.pair}   # {states[c.pair].name}")
    return "\n".join(out) + "\n"


def convert(data: bytes, source: str, robot_id: str | None = None, robot_class: str = "",
            rate: int = 100, command="velocity", states_of=("position", "velocity"),
            gains: dict | None = None, imu: str | None = None) -> str:
    """robot.toml text from URDF bytes; raises UrdfError. @p command: an
    interface or a sequence of them; @p gains: {"stiffness": max,
    "damping": max}; @p imu: the IMU's link."""
    root = parse_xml(data)
    refuse_xacro(root)
    joints, notes = read_joints(root, command, states_of)
    commands, states = channels(joints, gains)
    if imu is not None:
        states += imu_states(root, imu)
    if not commands:
        raise UrdfError(root.line, "<robot>: no joint with a command interface; robot.toml "
                                   "needs at least one command")
    rid = robot_id or robot_id_of(root.attrib.get("name", ""))
    text = to_toml(source, rid, robot_class, rate, commands, states, notes, joints,
                   root.find("ros2_control") is not None)
    # What rozgen would say of the result (a joint name too long for a
    # channel, two names giving one C constant, too many channels, ...).
    _, problems = validate(text)
    if problems:
        raise UrdfError(0, "the robot.toml it makes is refused by rozgen:\n"
                        + "\n".join(p.render("  robot.toml") for p in problems))
    return text


def _interface_options(a, ap) -> dict:
    """convert()'s channel arguments from the command line (--humanoid's
    layout, or --command, --states, --kp-max, --kd-max, --imu); argparse's
    error (exit 2) on a kind it does not know."""
    def kinds(text, allowed, option):
        out = [k.strip() for k in text.split(",") if k.strip()]
        for k in out:
            if k not in allowed:
                ap.error(f"{option} {text}: \"{k}\" is not one of {', '.join(allowed)}")
        if not out or len(set(out)) != len(out):
            ap.error(f"{option} {text}: expected distinct kinds, comma-separated")
        return sorted(out, key=allowed.index)
    if a.humanoid:
        if a.imu is None:
            ap.error("--humanoid needs --imu LINK (the link its IMU is mounted on): a policy "
                     "reads the base's orientation and rate")
        a.robot_class = a.robot_class or "humanoid"
        command, states = list(HUMANOID_COMMANDS), list(HUMANOID_STATES)
    else:
        command = kinds(a.command, COMMANDS, "--command")
        states = kinds(a.states, INTERFACES, "--states")
    gains = {k: v for k, v in (("stiffness", a.kp_max), ("damping", a.kd_max)) if v is not None}
    for k, v in gains.items():
        if not (math.isfinite(v) and v > 0.0):
            ap.error(f"--{'kp' if k == 'stiffness' else 'kd'}-max {v}: expected a number above 0")
    return {"command": command, "states_of": states, "gains": gains, "imu": a.imu}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rozgen-urdf", description=__doc__.split("\n\n")[0])
    ap.add_argument("urdf", metavar="URDF", help="an expanded URDF (not a .xacro)")
    ap.add_argument("-o", "--output", metavar="FILE", help="robot.toml to write (default: stdout)")
    ap.add_argument("--force", action="store_true", help="overwrite FILE if it exists")
    ap.add_argument("--robot-id", help="robot_id (default: from <robot name>)")
    ap.add_argument("--robot-class", default="", help="robot_class (default: left out, generic)")
    ap.add_argument("--rate", type=int, default=100, help="control_rate_hz (default 100)")
    ap.add_argument("--command", default="velocity", metavar="KIND[,KIND...]",
                    help="each joint's commands without a <ros2_control> tag, of "
                         f"{', '.join(COMMANDS)} (default velocity)")
    ap.add_argument("--states", default="position,velocity", metavar="KIND[,KIND...]",
                    help="each joint's states without a <ros2_control> tag, of "
                         f"{', '.join(INTERFACES)} (default position,velocity)")
    ap.add_argument("--kp-max", type=float, metavar="N",
                    help="the stiffness commands' upper limit (N*m/rad; N/m prismatic)")
    ap.add_argument("--kd-max", type=float, metavar="N",
                    help="the damping commands' upper limit (N*m*s/rad; N*s/m prismatic)")
    ap.add_argument("--imu", metavar="LINK", help="add base_imu states: an IMU on LINK")
    ap.add_argument("--humanoid", action="store_true",
                    help="the built-in humanoids' channels a policy deployment reads: --command "
                         f"{','.join(HUMANOID_COMMANDS)} --states {','.join(HUMANOID_STATES)} "
                         "--robot-class humanoid; needs --imu, --kp-max, --kd-max")
    a = ap.parse_args(argv)
    options = _interface_options(a, ap)
    try:
        with open(a.urdf, "rb") as f:
            data = f.read()
    except OSError as e:
        print(f"{a.urdf}: cannot read: {e.strerror or e}", file=sys.stderr)
        return EXIT_ERROR
    try:
        text = convert(data, os.path.basename(a.urdf), a.robot_id, a.robot_class, a.rate,
                       **options)
    except UrdfError as e:
        where = f"{a.urdf}:{e.line}" if e.line else a.urdf
        print(f"{where}: {e}", file=sys.stderr)
        return EXIT_ERROR
    if a.output is None:
        sys.stdout.write(text)
        return EXIT_OK
    try:
        with open(a.output, "w" if a.force else "x", encoding="utf-8") as f:
            f.write(text)
    except FileExistsError:
        print(f"{a.output}: exists; it may hold your edits (--force overwrites it)",
              file=sys.stderr)
        return EXIT_ERROR
    except OSError as e:
        print(f"{a.output}: cannot write: {e.strerror or e}", file=sys.stderr)
        return EXIT_ERROR
    manifest = tomllib.loads(text)["manifest"]
    print(f"{a.output}: {len(manifest['commands'])} commands, "
          f"{len(manifest.get('states', []))} states from {a.urdf}", file=sys.stderr)
    return EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
