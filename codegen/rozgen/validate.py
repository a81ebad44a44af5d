# SPDX-License-Identifier: Apache-2.0
"""Rules of robot.toml: document -> model.

``validate(doc, maxima)`` checks a parsed TOML document and returns the
``rozgen.model.Manifest`` or every problem found. It never stops at the
first problem, and it never guesses: unknown keys are refused, because a typo
such as ``max_rate = 0.5`` must not silently drop a safety limit.

Message format (after the file name)::

    : <where>: <key> <value>: <what is wrong>

``<where>`` is ``manifest``, ``manifest.commands[<i>] "<name>"``,
``manifest.states[<i>] "<name>"``, ``hardware`` or ``hardware.params``, and
is left out (with its ``": "``) for top-level keys. The channel name is left
out of ``<where>`` when it is missing or invalid, and for problems with the
name itself (the name is then the value). ``<value>`` is the value as written,
in TOML form (``rozgen.fmt.toml_value``); it is left out for missing and
unknown keys and for channel counts. Example::

    robot.toml: manifest.commands[1] "joint1/velocity": limits [2.0, -2.0]: min must be below max

Order: deterministic, by place in the file's schema -- top level, then
``[manifest]``, then each command in order, then each state, then
``[hardware]``; within one of these, unknown keys (in document order) first,
then the known keys in the order of the schema below (problems found by
cross-checks such as duplicates and pairing sit with the key they concern).

Schema::

    [manifest]                robot_id (string, required), robot_class
                              (string, "generic"), control_rate_hz (integer,
                              100), commands (array of tables, required),
                              states (array of tables, [])
    [[manifest.commands]]     name, interface_type, unit, limits = [min, max],
    [[manifest.states]]       default (all required), max_rate_of_change
                              (number, 0.0), position_state_index (integer, -1),
                              limit_margin (number, position states only;
                              absent: the default, model.Channel.margin)
    [hardware]                port (string, required), joints (array of
                              strings, []), params (table of strings, {});
                              a port's own keys in params are checked by
                              the port's module (``rozgen.socketcan``,
                              ``rozgen.dds_ports``)

Rules, by id (``rozgen --list-rules`` prints them; ``--error-ids`` prefixes
each message with ``[<id>] ``):

==================  ==========================================================
io-error            ``cannot read: <strerror>`` (or ``cannot write``)
utf8                ``cannot read: not valid UTF-8 (byte 0x.. at offset N)``
toml-syntax         ``<file>:<line>:<col>: invalid TOML: <what>`` (see
                    ``rozgen.load``; also ``unsupported TOML: <what>``)
unknown-key         ``<key>: unknown key (known keys: a, b, c)``
missing-key         ``<key>: required key is missing``
type                ``<key> <value>: expected a string`` (an integer, a
                    number, a table, an array of tables, an array of strings,
                    a table of strings; ``, not a boolean`` for true/false)
nul-char            ``<key> <value>: must not contain a NUL character``
robot-id            ``robot_id "UR5": must match [a-z][a-z0-9_]*`` or
                    ``robot_id "...": 33 characters, more than the maximum of 32``
control-rate        ``control_rate_hz 0: must be in 1..100000``
name                ``name "": must not be empty``, ``name "..": must be
                    printable ASCII other than " and \\``, ``name "..": 70
                    bytes, more than the maximum of 63 (ROZ_CFG_MAX_NAME_LEN)``,
                    ``name "/": must have a letter or digit``
interface-type      ``interface_type "Velocity": unknown type (known types: ..)``
limits-shape        ``limits [1.0]: expected [min, max], two numbers``
not-finite          ``limits [-inf, 1.0]: must be finite`` (also default,
                    max_rate_of_change, limit_margin)
limits-order        ``limits [2.0, -2.0]: min must be below max``
default-range       ``default 3.0: must be within limits [-2.0, 2.0]``
max-rate            ``max_rate_of_change -0.5: must not be negative``
duplicate-name      ``name "x": duplicate of manifest.commands[0]`` (among
                    the first maximum channels of the list: a longer list is
                    a too-many-channels problem, and comparing all of it
                    would cost the C reader quadratic time)
constant-collision  ``name "a/b": C constant ROZ_R_CMD_A_B is also that of
                    manifest.commands[0] "a.b"``
pairing-range       ``position_state_index 6: must be -1 (unpaired) or a
                    state index 0..1`` (``or 0, the only state``; ``must be
                    -1 (unpaired): there are no states``)
pairing-type        ``position_state_index 1: manifest.states[1] "x/velocity"
                    is a velocity state, not a position state``
pairing-zero        ``position_state_index 0: a paired velocity (or effort) command must
                    have 0 within its limits [0.5, 2.0], to stop at a position
                    limit``
pairing-on-state    ``position_state_index 0: only commands are paired with
                    a position state; must be -1 or left out``
margin-channel      ``limit_margin 0.01: only a position state has a limit
                    margin (the filter keeps a velocity command paired with
                    it that far inside its limits)``
margin-range        ``limit_margin 0: must be above 0 (leave it out for the
                    default)`` or ``limit_margin 0.05: leaves no room to move
                    within limits [0.0, 0.08]: twice the margin must be below
                    max - min``
no-commands         ``manifest: commands: at least one command is required``
too-many-channels   ``manifest: commands: 300 channels, more than the maximum
                    of 256 (ROZ_CFG_MAX_COMMANDS)`` (states likewise)
joint-name          ``hardware: joints[1] "": must not be empty``
duplicate-joint     ``hardware: joints[2] "a": duplicate of joints[0]``
can-param           (port ``socketcan``: ``rozgen.socketcan``)
                    ``hardware.params: can_id "knee=x": expected an actuator's
                    CAN id, 1..2047 (11 bits; decimal or 0x hex)``, ``...:
                    required key is missing``, ``no value for joint "knee",
                    and none for every joint``
can-id              ``hardware.params: can_id: joint "knee": id 3 is also that
                    of joint "hip"`` (or the same low byte, or master_id)
can-joint           ``hardware: joints[1] "a=b": the socketcan port needs joint
                    names without ',' and '=' ...``, ``... no channel of the
                    manifest is this joint's``
can-channel         ``manifest.states[3] "imu/orientation.x": the socketcan port
                    gives JOINT/position, /velocity and /effort states, ...``
can-range           ``hardware.params: effort_range: joint "knee": the actuator's
                    range [-18.0, 18.0] does not hold manifest.commands[4]
                    "knee/effort" limits [-24.0, 24.0]``
can-bus             ``hardware.params: command_writer_period_us "100": a joint's
                    command and reply take 270 bits, more than 80% of a 100 us
                    round ...``; ``reply_timeout_us "3000": shorter than two
                    command intervals of a joint (2 x 2000 us)``
mujoco-param        (port ``mujoco``: ``rozgen.mujoco``; the message is the port's
                    error) ``parameter servo_kp = "fast": expected a number in
                    0..1e+07`` (also unknown-key: ``unknown parameter "modle"
                    for port mujoco (known: ...)``)
mujoco-model        (port ``mujoco``, the model read: ``rozgen.mujoco.check_model``,
                    after every other rule, by the CLI) ``hardware.params.model =
                    "arm.xml": <path>: cannot be read: No such file or directory``
mujoco-joint        ``joint "elbow": no joint of that name in <model> (...)``,
                    ``joint "elbow": no actuator drives <model>'s joint "elbow"``
mujoco-imu          ``hardware.params.imu_gyro = "gyro": no gyro sensor on a site in
                    <model> (the manifest has base_imu channels)``
mujoco-effort       ``joint "elbow": the manifest's effort limits [-40, 40] N.m exceed
                    what <model>'s actuator "elbow" can give, [-30, 30]``
g1-joint            (ports ``unitree/G1``, ``agibot/X2``, ``engineai/PM01``:
                    ``rozgen.dds_ports``; the message is the port's error)
                    ``unitree/G1: [hardware] joints[1] "left_hip_pich_joint" is
                    not one of the robot's joints (the port's header lists
                    them)``, ``... has no channel in manifest <id> ...``
g1-channel          ``unitree/G1: command 2 "right_knee_joint/position" has no
                    place on the G1 (...)``, ``state 1 "x/velocity" has interface_type
                    effort; the port serves it as velocity``
g1-param            ``parameter mode_pr = "PRR": expected PR (...) or AB (...)``
                    (also unknown-key: ``unknown parameter "dds_domian" for
                    port unitree/G1 (known: ...)``)
ros2-joint          as g1-joint, ``agibot/X2: ...``, ``engineai/PM01: ...``
ros2-channel        as g1-channel
ros2-param          as g1-param, ``parameter link_check = "sequence": ...``
duplicate-robot-id  ``manifest: robot_id "ur5": also the robot_id of <file>``
                    (several files; checked by the CLI)
source-root         ``not under --source-root <dir>`` (checked by the CLI)
==================  ==========================================================

Command-line misuse is reported by argparse (``usage: rozgen ...``, exit 2)
and has no rule id.
"""

import math
import re
from dataclasses import dataclass

from rozgen import dds_ports, mujoco, names, socketcan
from rozgen.fmt import c_double, quote, toml_value
from rozgen.model import INTERFACE_TYPES, UNPAIRED, Channel, Hardware, Manifest, Maxima
from rozgen.problems import Problem

TOP_KEYS = ("manifest", "hardware")
MANIFEST_KEYS = ("robot_id", "robot_class", "control_rate_hz", "commands", "states")
CHANNEL_KEYS = (
    "name",
    "interface_type",
    "unit",
    "limits",
    "default",
    "max_rate_of_change",
    "position_state_index",
    "limit_margin",
    "safe_default",
)
#: What a paired position command holds during a stop (roz_safe_default_t).
SAFE_DEFAULTS = ("follow", "hold")
HARDWARE_KEYS = ("port", "joints", "params")

ROBOT_ID_RE = re.compile(r"[a-z][a-z0-9_]*")
ROBOT_ID_MAX = 32
RATE_MAX = 100000
DEFAULT_CLASS = "generic"
DEFAULT_RATE = 100

# Sections, in reporting order (a port's keys are checked last, on a
# manifest without other problems).
_TOP, _MANIFEST, _COMMANDS, _STATES, _HARDWARE, _PORT = range(6)
_UNKNOWN_RANK = -1  # unknown keys come first within a section

_MISSING = object()
_NO_VALUE = object()


@dataclass(frozen=True)
class _Place:
    """Where problems go: section and index for ordering, text for messages."""

    section: int
    index: int
    where: str  # "" at top level
    keys: tuple[str, ...]  # known keys, in reporting order


@dataclass
class _Draft:
    """A channel while being checked: None fields failed their checks."""

    index: int
    where: str
    name: str | None = None
    interface_type: str | None = None
    unit: str | None = None
    limits: tuple[float, float] | None = None
    default: float | None = None
    max_rate: float | None = None
    position_state: int | None = None
    limit_margin: float | None = None
    safe_default: str | None = None

    def complete(self) -> bool:
        return None not in (
            self.name,
            self.interface_type,
            self.unit,
            self.limits,
            self.default,
            self.max_rate,
            self.position_state,
            self.limit_margin,
            self.safe_default,
        )


def _is_int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def validate(doc: dict, maxima: Maxima = Maxima()) -> tuple[Manifest | None, list[Problem]]:
    """Check ``doc`` (from tomllib); return the model, or None and problems."""
    checker = _Checker(maxima)
    manifest = checker.run(doc)
    problems = sorted(checker.problems, key=lambda p: p.order)
    return (None if problems else manifest), problems


class _Checker:
    def __init__(self, maxima: Maxima) -> None:
        self.maxima = maxima
        self.problems: list[Problem] = []
        self.robot_id: str | None = None

    # ---- reporting --------------------------------------------------------

    def report(self, rule: str, place: _Place, key: str, what: str,
               value: object = _NO_VALUE, rank_key: str | None = None) -> None:
        """Record ``<where>: <key> <value>: <what>`` under ``place``."""
        rank_of = rank_key if rank_key is not None else key
        rank = place.keys.index(rank_of) if rank_of in place.keys else _UNKNOWN_RANK
        subject = key if value is _NO_VALUE else f"{key} {toml_value(value)}"
        parts = [place.where, subject, what] if place.where else [subject, what]
        order = (place.section, place.index, rank, len(self.problems))
        self.problems.append(Problem(rule, ": " + ": ".join(parts), order))

    def unknown_keys(self, place: _Place, table: dict) -> None:
        for key in table:
            if key not in place.keys:
                known = ", ".join(place.keys)
                self.report("unknown-key", place, _key_text(key),
                            f"unknown key (known keys: {known})", rank_key="")

    def string(self, place: _Place, table: dict, key: str, default: object = _MISSING) -> str | None:
        """A string value (None when missing or invalid)."""
        value = table.get(key, default)
        if value is _MISSING:
            self.report("missing-key", place, key, "required key is missing")
            return None
        if not isinstance(value, str):
            self.report("type", place, key, "expected a string", value)
            return None
        if not self.no_nul(place, key, value):
            return None
        return value

    def no_nul(self, place: _Place, key: str, value: str, rank_key: str | None = None) -> bool:
        if "\0" in value:
            self.report("nul-char", place, key, "must not contain a NUL character", value,
                        rank_key=rank_key)
            return False
        return True

    def number(self, place: _Place, table: dict, key: str, default: object = _MISSING) -> float | None:
        """A finite number, ints converted to float (None when invalid)."""
        value = table.get(key, default)
        if value is _MISSING:
            self.report("missing-key", place, key, "required key is missing")
            return None
        if not _is_number(value):
            self.report("type", place, key, _expected("a number", value), value)
            return None
        if not math.isfinite(value):
            self.report("not-finite", place, key, "must be finite", value)
            return None
        return float(value)

    def integer(self, place: _Place, table: dict, key: str, default: int) -> int | None:
        value = table.get(key, default)
        if not _is_int(value):
            self.report("type", place, key, _expected("an integer", value), value)
            return None
        return value

    def tables(self, place: _Place, table: dict, key: str, default: object = _MISSING) -> list | None:
        """An array of tables; elements that are not tables become None."""
        value = table.get(key, default)
        if value is _MISSING:
            self.report("missing-key", place, key, "required key is missing")
            return None
        if not isinstance(value, list):
            self.report("type", place, key, "expected an array of tables", value)
            return None
        items = []
        for i, item in enumerate(value):
            if isinstance(item, dict):
                items.append(item)
            else:
                self.report("type", place, f"{key}[{i}]", "expected a table", item, rank_key=key)
                items.append(None)
        return items

    # ---- document ---------------------------------------------------------

    def run(self, doc: dict) -> Manifest | None:
        top = _Place(_TOP, 0, "", TOP_KEYS)
        self.unknown_keys(top, doc)
        manifest_table = doc.get("manifest", _MISSING)
        manifest = None
        if manifest_table is _MISSING:
            self.report("missing-key", top, "manifest", "required key is missing")
        elif not isinstance(manifest_table, dict):
            self.report("type", top, "manifest", "expected a table", manifest_table)
        else:
            manifest = self.manifest(manifest_table)
        hardware = None
        hardware_table = doc.get("hardware", _MISSING)
        if hardware_table is not _MISSING:
            if isinstance(hardware_table, dict):
                hardware = self.hardware(hardware_table)
            else:
                self.report("type", top, "hardware", "expected a table", hardware_table)
        if manifest is None or self.problems:
            return None
        result = Manifest(**manifest, hardware=hardware)
        # a port's own keys, checked as the port checks them at open
        for rule, message in socketcan.check(result) + dds_ports.check(result) + mujoco.check(result):
            self.problems.append(Problem(rule, message, (_PORT, 0, 0, len(self.problems))))
        return None if self.problems else result

    def manifest(self, table: dict) -> dict | None:
        place = _Place(_MANIFEST, 0, "manifest", MANIFEST_KEYS)
        self.unknown_keys(place, table)

        robot_id = self.string(place, table, "robot_id")
        if robot_id is not None:
            if not ROBOT_ID_RE.fullmatch(robot_id):
                self.report("robot-id", place, "robot_id",
                            "must match [a-z][a-z0-9_]* (it names C symbols and files)", robot_id)
                robot_id = None
            elif len(robot_id) > ROBOT_ID_MAX:
                self.report("robot-id", place, "robot_id",
                            f"{len(robot_id)} characters, more than the maximum of {ROBOT_ID_MAX}",
                            robot_id)
                robot_id = None
        self.robot_id = robot_id

        robot_class = self.string(place, table, "robot_class", DEFAULT_CLASS)

        rate = self.integer(place, table, "control_rate_hz", DEFAULT_RATE)
        if rate is not None and not 1 <= rate <= RATE_MAX:
            self.report("control-rate", place, "control_rate_hz", f"must be in 1..{RATE_MAX}", rate)
            rate = None

        command_tables = self.tables(place, table, "commands")
        state_tables = self.tables(place, table, "states", [])
        if command_tables is not None:
            if not command_tables:
                self.report("no-commands", place, "commands", "at least one command is required")
            self.count(place, "commands", len(command_tables), self.maxima.commands,
                       "ROZ_CFG_MAX_COMMANDS")
        if state_tables is not None:
            self.count(place, "states", len(state_tables), self.maxima.states,
                       "ROZ_CFG_MAX_STATES")

        states = self.channels(_STATES, "states", state_tables or [])
        commands = self.channels(_COMMANDS, "commands", command_tables or [])
        if state_tables is not None:
            self.pairing(commands, states)

        if None in (robot_id, robot_class, rate, command_tables, state_tables):
            return None
        if not all(d is not None and d.complete() for d in commands + states):
            return None
        return {
            "robot_id": robot_id,
            "robot_class": robot_class,
            "control_rate_hz": rate,
            "commands": tuple(_channel(d) for d in commands),
            "states": tuple(_channel(d) for d in states),
        }

    def count(self, place: _Place, key: str, n: int, maximum: int, option: str) -> None:
        if n > maximum:
            self.report("too-many-channels", place, key,
                        f"{n} channels, more than the maximum of {maximum} ({option})")

    # ---- channels ---------------------------------------------------------

    def channels(self, section: int, kind: str, tables: list) -> list:
        drafts = [None if t is None else self.channel(section, kind, i, t)
                  for i, t in enumerate(tables)]
        maximum = self.maxima.commands if section == _COMMANDS else self.maxima.states
        self.unique_names(section, kind, drafts[:maximum])
        return drafts

    def channel(self, section: int, kind: str, index: int, table: dict) -> _Draft:
        bare = f"manifest.{kind}[{index}]"
        name_place = _Place(section, index, bare, CHANNEL_KEYS)
        name = self.channel_name(name_place, table)
        where = bare if name is None else f"{bare} {quote(name)}"
        place = _Place(section, index, where, CHANNEL_KEYS)
        draft = _Draft(index, where, name=name)
        self.unknown_keys(place, table)

        itype = self.string(place, table, "interface_type")
        if itype is not None and itype not in INTERFACE_TYPES:
            self.report("interface-type", place, "interface_type",
                        f"unknown type (known types: {', '.join(INTERFACE_TYPES)})", itype)
            itype = None
        draft.interface_type = itype

        draft.unit = self.string(place, table, "unit")
        draft.limits = self.limits(place, table)

        default = self.number(place, table, "default")
        if default is not None and draft.limits is not None:
            low, high = draft.limits
            if not low <= default <= high:
                self.report("default-range", place, "default",
                            f"must be within limits [{c_double(low)}, {c_double(high)}]",
                            table["default"])
                default = None
        draft.default = default

        max_rate = self.number(place, table, "max_rate_of_change", 0.0)
        if max_rate is not None and max_rate < 0:
            self.report("max-rate", place, "max_rate_of_change", "must not be negative",
                        table["max_rate_of_change"])
            max_rate = None
        draft.max_rate = max_rate

        pair = self.integer(place, table, "position_state_index", UNPAIRED)
        if pair is not None and kind == "states" and pair != UNPAIRED:
            self.report("pairing-on-state", place, "position_state_index",
                        "only commands are paired with a position state; must be -1 or left out",
                        pair)
            pair = None
        draft.position_state = pair
        draft.limit_margin = self.margin(place, kind, table, itype, draft.limits)
        draft.safe_default = self.safe_default(place, kind, table, itype, pair)
        return draft

    def safe_default(self, place: _Place, kind: str, table: dict, itype: str | None,
                     pair: int | None) -> str | None:
        """safe_default: "follow" (the default) or "hold", which only a
        position command paired with a position state can do."""
        value = self.string(place, table, "safe_default", "follow")
        if value is None:
            return None
        if value not in SAFE_DEFAULTS:
            self.report("safe-default", place, "safe_default", 'must be "follow" or "hold"',
                        value)
            return None
        if value == "hold" and (kind == "states" or (itype is not None and itype != "position")
                                or pair == UNPAIRED):
            self.report("safe-default", place, "safe_default",
                        "only a position command paired with a position state can hold (the "
                        "setpoint a stop latched)", value)
            return None
        return value

    def margin(self, place: _Place, kind: str, table: dict, itype: str | None,
               limits: tuple[float, float] | None) -> float | None:
        """limit_margin: 0.0 (the default) when absent; a position state's
        own margin must be above 0 and leave the joint room to move."""
        if "limit_margin" not in table:
            return 0.0
        margin = self.number(place, table, "limit_margin")
        if margin is None:
            return None
        value = table["limit_margin"]
        if kind == "commands" or (itype is not None and itype != "position"):
            self.report("margin-channel", place, "limit_margin",
                        "only a position state has a limit margin (the filter keeps a velocity "
                        "command paired with it that far inside its limits)", value)
            return None
        if not margin > 0.0:
            self.report("margin-range", place, "limit_margin",
                        "must be above 0 (leave it out for the default)", value)
            return None
        if limits is not None and not 2.0 * margin < limits[1] - limits[0]:
            low, high = limits
            self.report("margin-range", place, "limit_margin",
                        f"leaves no room to move within limits [{c_double(low)}, "
                        f"{c_double(high)}]: twice the margin must be below max - min", value)
            return None
        return margin

    def channel_name(self, place: _Place, table: dict) -> str | None:
        name = self.string(place, table, "name")
        if name is None:
            return None
        what = None
        if name == "":
            what = "must not be empty"
        elif not all(0x20 <= ord(c) < 0x7F and c not in '"\\' for c in name):
            what = 'must be printable ASCII other than " and \\'
        elif len(name) > self.maxima.name_len:
            what = (f"{len(name)} bytes, more than the maximum of {self.maxima.name_len} "
                    "(ROZ_CFG_MAX_NAME_LEN)")
        elif names.constant_suffix(name) == "":
            what = "must have a letter or digit (it names a C constant)"
        if what is not None:
            self.report("name", place, "name", what, name)
            return None
        return name

    def limits(self, place: _Place, table: dict) -> tuple[float, float] | None:
        value = table.get("limits", _MISSING)
        if value is _MISSING:
            self.report("missing-key", place, "limits", "required key is missing")
            return None
        if not (isinstance(value, list) and len(value) == 2 and all(map(_is_number, value))):
            self.report("limits-shape", place, "limits", "expected [min, max], two numbers", value)
            return None
        low, high = float(value[0]), float(value[1])
        if not (math.isfinite(low) and math.isfinite(high)):
            self.report("not-finite", place, "limits", "must be finite", value)
            return None
        if not low < high:
            self.report("limits-order", place, "limits", "min must be below max", value)
            return None
        return low, high

    def unique_names(self, section: int, kind: str, drafts: list) -> None:
        """Names, and the C constants made from them, must be unique."""
        first_of_name: dict[str, _Draft] = {}
        first_of_constant: dict[str, _Draft] = {}
        make = names.command_constant if kind == "commands" else names.state_constant
        robot_id = self.robot_id if self.robot_id is not None else "<id>"
        for draft in drafts:
            if draft is None or draft.name is None:
                continue
            place = _Place(section, draft.index, f"manifest.{kind}[{draft.index}]", CHANNEL_KEYS)
            first = first_of_name.setdefault(draft.name, draft)
            if first is not draft:
                self.report("duplicate-name", place, "name",
                            f"duplicate of manifest.{kind}[{first.index}]", draft.name)
                draft.name = None
                continue
            constant = make(robot_id, draft.name)
            first = first_of_constant.setdefault(constant, draft)
            if first is not draft:
                self.report("constant-collision", place, "name",
                            f"C constant {constant} is also that of {first.where}", draft.name)
                draft.name = None

    def pairing(self, commands: list, states: list) -> None:
        """Each paired command points at an existing position state."""
        for draft in commands:
            if draft is None or draft.position_state in (None, UNPAIRED):
                continue
            index = draft.position_state
            place = _Place(_COMMANDS, draft.index, draft.where, CHANNEL_KEYS)
            if not 0 <= index < len(states):
                if not states:
                    what = "must be -1 (unpaired): there are no states"
                elif len(states) == 1:
                    what = "must be -1 (unpaired) or 0, the only state"
                else:
                    what = f"must be -1 (unpaired) or a state index 0..{len(states) - 1}"
                self.report("pairing-range", place, "position_state_index", what, index)
                draft.position_state = None
                continue
            target = states[index]
            if target is not None and target.interface_type == "position":
                # The filter stops a paired velocity or effort command at a
                # position limit by commanding 0: 0 must be a value it may send.
                if draft.interface_type in ("velocity", "effort") and draft.limits is not None:
                    low, high = draft.limits
                    if not low <= 0.0 <= high:
                        self.report("pairing-zero", place, "position_state_index",
                                    f"a paired {draft.interface_type} command must have 0 "
                                    "within its limits "
                                    f"[{c_double(low)}, {c_double(high)}], to stop at a "
                                    "position limit", index)
                continue
            if target is None or target.interface_type is None:
                continue  # a broken target is reported where it is
            self.report("pairing-type", place, "position_state_index",
                        f"{target.where} is a {target.interface_type} state, "
                        "not a position state", index)
            draft.position_state = None

    # ---- hardware ---------------------------------------------------------

    def hardware(self, table: dict) -> Hardware | None:
        place = _Place(_HARDWARE, 0, "hardware", HARDWARE_KEYS)
        self.unknown_keys(place, table)
        port = self.string(place, table, "port")
        joints = self.joints(place, table.get("joints", []))
        params = self.params(table.get("params", {}))
        if None in (port, joints, params):
            return None
        return Hardware(port=port, joints=joints, params=params)

    def joints(self, place: _Place, value: object) -> tuple[str, ...] | None:
        if not isinstance(value, list):
            self.report("type", place, "joints", "expected an array of strings", value)
            return None
        ok = True
        first_of: dict[str, int] = {}
        for i, joint in enumerate(value):
            key = f"joints[{i}]"
            if not isinstance(joint, str):
                self.report("type", place, key, "expected a string", joint, rank_key="joints")
                ok = False
            elif joint == "":
                self.report("joint-name", place, key, "must not be empty", joint, rank_key="joints")
                ok = False
            elif not self.no_nul(place, key, joint, rank_key="joints"):
                ok = False
            elif first_of.setdefault(joint, i) != i:
                self.report("duplicate-joint", place, key, f"duplicate of joints[{first_of[joint]}]",
                            joint, rank_key="joints")
                ok = False
        return tuple(value) if ok else None

    def params(self, value: object) -> tuple[tuple[str, str], ...] | None:
        hw = _Place(_HARDWARE, 0, "hardware", HARDWARE_KEYS)
        if not isinstance(value, dict):
            self.report("type", hw, "params", "expected a table of strings", value)
            return None
        place = _Place(_HARDWARE, 1, "hardware.params", ())
        ok = True
        for key, item in value.items():
            shown = _key_text(key)
            if not isinstance(item, str):
                self.report("type", place, shown, "expected a string", item)
                ok = False
            elif "\0" in key:
                self.report("nul-char", place, shown, "must not contain a NUL character")
                ok = False
            elif not self.no_nul(place, shown, item):
                ok = False
        return tuple(sorted(value.items())) if ok else None


def _expected(what: str, value: object) -> str:
    if isinstance(value, bool):
        return f"expected {what}, not a boolean"
    return f"expected {what}"


def _key_text(key: str) -> str:
    """A TOML key as written: bare when it can be, else quoted."""
    if key and all(c.isascii() and (c.isalnum() or c in "_-") for c in key):
        return key
    return quote(key)


def _channel(draft: _Draft) -> Channel:
    low, high = draft.limits
    return Channel(
        name=draft.name,
        interface_type=draft.interface_type,
        unit=draft.unit,
        min=low,
        max=high,
        default=draft.default,
        max_rate=draft.max_rate,
        position_state=draft.position_state,
        limit_margin=draft.limit_margin,
        safe_default=draft.safe_default,
    )
