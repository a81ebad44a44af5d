# SPDX-License-Identifier: Apache-2.0
"""A reader of the parts of an MJCF model (MuJoCo's XML) that the mujoco
port binds a manifest to: joints (name, type, actuator force range), the
actuators that drive them (joint, gear, force range) and the sensors (name,
type, site), with ``<include file=...>`` followed and ``<default>`` classes
applied as MuJoCo applies them (an element's ``class``, else its body's
``childclass``, else ``main``; a class inherits from the classes around it).
Only Python's xml; what MuJoCo computes when it compiles (meshes, inertias)
is not needed here.

``load(path)`` returns a :class:`Model` or raises :class:`ModelError` whose
text names the file (and the include) that cannot be read.
"""

import os
import stat
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

#: actuator elements; in <default> they all set the one actuator default
ACTUATORS = ("general", "motor", "position", "velocity", "intvelocity", "damper", "cylinder",
             "muscle", "adhesion")
#: includes followed at most this deep (a file that includes itself stops here)
MAX_DEPTH = 16
#: includes followed in all, and the bytes of XML read in all (the model and
#: every include): a few files including each other many times would
#: otherwise make billions of elements (docs/policies.md, the readers' limits)
MAX_INCLUDES = 256
MAX_BYTES = 32 * 1024 * 1024


class ModelError(Exception):
    pass


@dataclass
class Joint:
    name: str
    type: str  # hinge, slide, ball, free
    frc_range: tuple[float, float] | None  # actuatorfrcrange when limited


@dataclass
class Actuator:
    name: str | None
    joint: str
    gear: float
    force_range: tuple[float, float] | None  # forcerange when limited


@dataclass
class Sensor:
    name: str | None
    type: str  # the element: gyro, accelerometer, ...
    site: str | None


@dataclass
class Model:
    path: str
    joints: dict[str, Joint] = field(default_factory=dict)
    actuators: list[Actuator] = field(default_factory=list)  # in model order
    sensors: list[Sensor] = field(default_factory=list)


@dataclass
class _Read:
    """What a model's files have used of MAX_INCLUDES and MAX_BYTES."""
    includes: int = 0
    bytes: int = 0


def _read_bounded(path: str, shown: str, used: _Read) -> bytes:
    """A regular file's bytes, within what MAX_BYTES leaves (/dev/zero, a
    FIFO or a folder refused before a byte is read)."""
    left = MAX_BYTES - used.bytes
    with open(path, "rb") as f:
        if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
            raise ModelError(f"{shown}: not a regular file")
        data = f.read(left + 1)
    if len(data) > left:
        raise ModelError(f"{shown}: the model's XML passes {MAX_BYTES} bytes in all "
                         f"(the model and its includes; this reader's limit)")
    used.bytes += len(data)
    return data


def _parse(path: str, shown: str, used: _Read | None = None) -> ET.Element:
    try:
        return ET.fromstring(_read_bounded(path, shown, used if used is not None else _Read()))
    except OSError as e:
        raise ModelError(f"{shown}: cannot be read: {e.strerror or e}") from None
    except ET.ParseError as e:
        raise ModelError(f"{shown}: not XML: {e}") from None


def _expand(root: ET.Element, base_dir: str, shown: str, depth: int, used: _Read) -> None:
    """Replace every <include file=...> below @p root by the children of
    the included file's root, in place (MuJoCo's include: paths relative to
    the main model's folder), within MAX_DEPTH, MAX_INCLUDES and MAX_BYTES."""
    for parent in list(root.iter()):
        for i, child in reversed(list(enumerate(list(parent)))):
            if child.tag != "include":
                continue
            name = child.get("file")
            where = f'{shown}: <include file="{name}">'
            if not name:
                raise ModelError(f"{shown}: an <include> without a file")
            if depth >= MAX_DEPTH:
                raise ModelError(f"{where}: includes nested more than {MAX_DEPTH} deep")
            used.includes += 1
            if used.includes > MAX_INCLUDES:
                raise ModelError(f"{where}: more than {MAX_INCLUDES} includes in all (this "
                                 "reader's limit)")
            path = name if os.path.isabs(name) else os.path.join(base_dir, name)
            sub = _parse(path, where, used)
            _expand(sub, base_dir, where, depth + 1, used)
            parent.remove(child)
            for k, node in enumerate(list(sub)):
                parent.insert(i + k, node)


def _floats(text: str | None) -> list[float] | None:
    if text is None:
        return None
    try:
        return [float(x) for x in text.split()]
    except ValueError:
        return None


class _Defaults:
    """The <default> classes: class -> (parent class, {element: attributes})."""

    def __init__(self, root: ET.Element) -> None:
        self.classes: dict[str, tuple[str | None, dict[str, dict[str, str]]]] = {}
        for top in root.findall("default"):
            self._add(top, None)

    def _add(self, node: ET.Element, parent: str | None) -> None:
        name = node.get("class", "main" if parent is None else None)
        if name is None:
            return
        own: dict[str, dict[str, str]] = {}
        for child in node:
            if child.tag == "default":
                continue
            key = "actuator" if child.tag in ACTUATORS else child.tag
            own.setdefault(key, {}).update(child.attrib)
        self.classes[name] = (parent, own)
        for child in node.findall("default"):
            self._add(child, name)

    def get(self, cls: str, key: str, attr: str) -> str | None:
        seen = 0
        while cls is not None and cls in self.classes and seen < 64:
            parent, own = self.classes[cls]
            if attr in own.get(key, {}):
                return own[key][attr]
            cls = parent
            seen += 1
        return None


def _limited(flag: str | None, rng: list[float] | None) -> tuple[float, float] | None:
    """MuJoCo's *limited = "auto" (the default): limited when a range is given."""
    if flag == "false" or rng is None or len(rng) != 2:
        return None
    return (rng[0], rng[1])


def load(path: str) -> Model:
    """The model at @p path (as the robot.toml names it, resolved)."""
    used = _Read()
    root = _parse(path, path, used)
    if root.tag != "mujoco":
        raise ModelError(f"{path}: not an MJCF model (its root is <{root.tag}>, not <mujoco>)")
    _expand(root, os.path.dirname(path), path, 0, used)
    defaults = _Defaults(root)
    model = Model(path)

    def attr(node: ET.Element, cls: str, key: str, name: str) -> str | None:
        v = node.get(name)
        return v if v is not None else defaults.get(node.get("class", cls), key, name)

    def walk(body: ET.Element, childclass: str) -> None:
        for node in body:
            if node.tag in ("body", "worldbody"):
                walk(node, node.get("childclass", childclass))
            elif node.tag == "freejoint":
                if node.get("name"):
                    model.joints[node.get("name")] = Joint(node.get("name"), "free", None)
            elif node.tag == "joint":
                name = node.get("name")
                if name is None:
                    continue
                jtype = attr(node, childclass, "joint", "type") or "hinge"
                rng = _limited(attr(node, childclass, "joint", "actuatorfrclimited"),
                               _floats(attr(node, childclass, "joint", "actuatorfrcrange")))
                model.joints.setdefault(name, Joint(name, jtype, rng))

    for wb in root.findall("worldbody"):
        walk(wb, "main")
    for section in root.findall("actuator"):
        for node in section:
            if node.tag not in ACTUATORS:
                continue
            joint = node.get("joint") or node.get("jointinparent")
            gear = _floats(attr(node, "main", "actuator", "gear")) or [1.0]
            rng = _limited(attr(node, "main", "actuator", "forcelimited"),
                           _floats(attr(node, "main", "actuator", "forcerange")))
            model.actuators.append(Actuator(node.get("name"), joint or "", gear[0], rng))
    for section in root.findall("sensor"):
        for node in section:
            model.sensors.append(Sensor(node.get("name"), node.tag, node.get("site")))
    return model
