# SPDX-License-Identifier: Apache-2.0
"""The [hardware] keys of a robot for the socketcan port (CAN actuators in
"MIT mode"): the rules of ``ports/socketcan/src/can_config.c``, the same
problems with the same words in the same order, so that rozgen refuses at
build time what the port would refuse at open. The keys, their values and
defaults are documented in ``ports/socketcan/include/roz/port/can_config.h``.

``check(manifest)`` runs on a manifest that passed every other rule and
returns ``(rule, message)`` pairs, messages starting with ``": "``.
"""

import math
import re

from rozgen import threads
from rozgen.fmt import c_double, quote
from rozgen.model import Manifest

PORT = "socketcan"

GLOBAL_KEYS = (
    "network_interface",
    "bitrate",
    "command_writer_period_us",
    "max_bus_load_percent",
    "reply_timeout_us",
    "command_timeout_us",
    "master_id",
    "consistency_margin",
    "enable_monitor",
    "state_decimation",
)
JOINT_KEYS = (
    "can_id",
    "reply",
    "position_range",
    "velocity_range",
    "stiffness_range",
    "damping_range",
    "effort_range",
    "direction",
    "zero_offset",
)
#: the port's two threads (roz/hal/thread.h; threads.py)
THREAD_KEYS = tuple(f"{thread}_{what}" for thread in ("receive_thread", "command_writer")
                    for what in ("sched", "priority", "cpus", "stack_kib"))
KEYS = GLOBAL_KEYS + THREAD_KEYS + JOINT_KEYS
OPTIONAL_JOINT_KEYS = ("direction", "zero_offset")
RANGE_KEYS = JOINT_KEYS[2:7]
#: the interface type each range holds
RANGE_TYPES = dict(zip(RANGE_KEYS, ("position", "velocity", "stiffness", "damping", "effort")))
LAYOUTS = {"basic": 6, "temperature_error": 8}
STATE_TYPES = ("position", "velocity", "effort")
COMMAND_TYPES = ("position", "velocity", "stiffness", "damping", "effort")

MAX_JOINTS = 64  # ROZ_CFG_MAX_JOINTS
MAX_NUMBER_TEXT = 63
DEFAULT_TIMEOUT_US = 20000
#: the command watchdog's, as roz/hal/cmd_watchdog.h has them
WATCHDOG_DEFAULT_US = 50000
WATCHDOG_DEFAULT_PERIODS = 5
WATCHDOG_MIN_PERIODS = 2
WATCHDOG_MAX_US = 60000000
BOOLS = {"true": True, "1": True, "yes": True, "on": True,
         "false": False, "0": False, "no": False, "off": False}

_NUMBER = re.compile(r"[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?")
_UINT = re.compile(r"0[xX][0-9a-fA-F]+|[0-9]+")
_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")

POSITION_EXPECTED = "expected MIN:MAX, two finite numbers, MIN below MAX"
RANGE_EXPECTED = ("expected MIN:MAX, two finite numbers, MIN below MAX, 0 between them (a hold "
                  "sends 0)")
EXPECTED = {
    "position_range": POSITION_EXPECTED,
    "can_id": "expected an actuator's CAN id, 1..2047 (11 bits; decimal or 0x hex)",
    "reply": "unknown reply layout (known: basic, temperature_error)",
    "direction": "expected 1 or -1",
    "zero_offset": "expected a finite number (rad)",
}


def frame_bits(n: int) -> int:
    """Worst-case bits of a standard CAN data frame of n bytes."""
    return 47 + 8 * n + (33 + 8 * n) // 4


def _trim(s: str) -> str:
    return s.strip(" \t")


def _uint(text: str) -> int | None:
    if not _UINT.fullmatch(text):
        return None
    return int(text, 16) if text[:2] in ("0x", "0X") else int(text)


def _uint_in(text: str, lo: int, hi: int) -> int | None:
    value = _uint(text)
    return value if value is not None and lo <= value <= hi else None


def _number(text: str) -> float | None:
    if len(text) > MAX_NUMBER_TEXT or not _NUMBER.fullmatch(text):
        return None
    value = float(text)
    return value if math.isfinite(value) else None


def _range(text: str) -> tuple[float, float] | None:
    lo_text, colon, hi_text = text.partition(":")
    if not colon:
        return None
    lo, hi = _number(_trim(lo_text)), _number(_trim(hi_text))
    if lo is None or hi is None or not lo < hi or not math.isfinite((hi - lo) * 65536.0):
        return None
    return lo, hi


def _range_with_zero(text: str) -> tuple[float, float] | None:
    """A range a hold can send 0 in: velocity, gains, torque."""
    r = _range(text)
    return r if r is not None and r[0] <= 0.0 <= r[1] else None


def _direction(text: str) -> int | None:
    return {"1": 1, "+1": 1, "-1": -1}.get(text)


def _reply(text: str) -> str | None:
    return text if text in LAYOUTS else None


_PARSERS = {"can_id": lambda t: _uint_in(t, 1, 0x7FF), "reply": _reply,
            "direction": _direction, "zero_offset": _number}
_PARSERS.update({k: _range_with_zero for k in RANGE_KEYS})
_PARSERS["position_range"] = _range


class _Checker:
    def __init__(self, manifest: Manifest) -> None:
        self.m = manifest
        self.hw = manifest.hardware
        self.params = dict(self.hw.params)
        self.problems: list[tuple[str, str]] = []
        self.joints = list(self.hw.joints)
        self.values: dict[str, dict[str, object]] = {}  # joint key -> joint -> value
        self.config: dict[str, object] = {
            "network_interface": "can0", "bitrate": 1000000, "command_writer_period_us": 2000,
            "max_bus_load_percent": 80, "reply_timeout_us": DEFAULT_TIMEOUT_US,
            "command_timeout_us": WATCHDOG_DEFAULT_US, "master_id": 0,
            "consistency_margin": 0.2, "enable_monitor": True, "state_decimation": 1}

    def say(self, rule: str, text: str) -> None:
        self.problems.append((rule, text))

    def say_entry(self, rule: str, key: str, entry: str, what: str) -> None:
        self.say(rule, f": hardware.params: {key} {quote(entry)}: {what}")

    def say_joint(self, index: int, name: str, what: str) -> None:
        self.say("can-joint", f": hardware: joints[{index}] {quote(name)}: {what}")

    # ---- the table --------------------------------------------------------

    def run(self) -> list[tuple[str, str]]:
        joints_ok = self.check_joints()
        for key in self.params:  # sorted by key, as in the model
            if key not in KEYS:
                shown = key if _BARE_KEY.fullmatch(key) else quote(key)
                self.say("unknown-key", f": hardware.params: {shown}: unknown key of the "
                         f"socketcan port (known keys: {', '.join(KEYS)})")
        parsed = {}
        for key in KEYS:
            value = self.params.get(key)
            if key in THREAD_KEYS:
                continue
            if key in GLOBAL_KEYS:
                parsed[key] = self.global_key(key, value)
            elif joints_ok:
                parsed[key] = self.per_joint(key, value, key not in OPTIONAL_JOINT_KEYS)
            else:
                parsed[key] = False
        found = threads.problem(self.params, "receive_thread") or \
            threads.problem(self.params, "command_writer")
        if found is not None:
            self.say("can-param", f": hardware.params: {found}")
        if joints_ok and parsed["can_id"] and parsed["master_id"]:
            self.check_ids()
        bound = joints_ok and self.check_channels()
        if bound and all(parsed[k] for k in RANGE_KEYS + ("direction", "zero_offset")):
            self.check_ranges()
        if joints_ok and all(parsed[k] for k in ("bitrate", "command_writer_period_us",
                                                 "max_bus_load_percent", "reply_timeout_us",
                                                 "reply")):
            if self.check_bus() and parsed["command_timeout_us"]:
                self.check_command_timeout()
        return self.problems

    def check_joints(self) -> bool:
        if not self.joints:
            self.say("can-joint", ": hardware: joints: the socketcan port drives the joints "
                     "listed here, one actuator each, and none is")
            return False
        if len(self.joints) > MAX_JOINTS:
            self.say("can-joint", f": hardware: joints: {len(self.joints)} joints, more than "
                     f"the maximum of {MAX_JOINTS} (ROZ_CFG_MAX_JOINTS)")
            return False
        ok = True
        for i, name in enumerate(self.joints):
            if "," in name or "=" in name or name != _trim(name):
                self.say_joint(i, name, "the socketcan port needs joint names without ',' and "
                               "'=' and without spaces around them")
                ok = False
        return ok

    def global_key(self, key: str, value: str | None) -> bool:
        if value is None:
            return True
        checks = {
            "network_interface": (
                lambda v: v if 0 < len(v.encode("utf-8")) <= 15
                and all(0x20 < ord(c) < 0x7F and c != "/" for c in v) else None,
                "expected an interface name, 1..15 printable bytes without spaces or '/'"),
            "bitrate": (lambda v: _uint_in(v, 10000, 1000000),
                        "expected an integer in 10000..1000000 (bit/s)"),
            "command_writer_period_us": (
                lambda v: 0 if v == "0" else _uint_in(v, 100, 1000000),
                "expected 0 (a round per write) or an integer in 100..1000000 (us)"),
            "max_bus_load_percent": (lambda v: _uint_in(v, 10, 100),
                                     "expected an integer in 10..100 (percent)"),
            "reply_timeout_us": (lambda v: _uint_in(v, 1000, 10000000),
                                 "expected an integer in 1000..10000000 (us)"),
            "command_timeout_us": (lambda v: _uint_in(v, 1000, WATCHDOG_MAX_US),
                                   "expected an integer in 1000..60000000 (us)"),
            "master_id": (lambda v: _uint_in(v, 0, 0x7FF),
                          "expected a CAN id, 0..2047 (decimal or 0x hex)"),
            "consistency_margin": (
                lambda v: x if (x := _number(v)) is not None and x >= 0.0 else None,
                "expected a finite number, 0 or more (rad; 0 = off)"),
            "enable_monitor": (lambda v: BOOLS.get(v),
                               "expected true or false (1/0, yes/no, on/off)"),
            "state_decimation": (lambda v: 1 if v == "1" else None,
                                 "must be 1: the socketcan port converts every reply"),
        }
        parse, what = checks[key]
        parsed = parse(value)
        if parsed is None:
            self.say_entry("can-param", key, value, what)
            return False
        self.config[key] = parsed
        return True

    def per_joint(self, key: str, value: str | None, required: bool) -> bool:
        parse = _PARSERS[key]
        expected = EXPECTED.get(key, RANGE_EXPECTED)
        absent = 1 if key == "direction" else 0.0  # an optional key's value when not given
        self.values[key] = {}
        if value is None:
            if not required:
                self.values[key] = {j: absent for j in self.joints}
                return True
            self.say("can-param", f": hardware.params: {key}: required key is missing")
            return False
        ok = True
        have: dict[str, bool] = {}  # joint -> valid
        default, have_default = None, 0  # 1 valid, 2 invalid
        for raw in value.split(","):
            entry = _trim(raw)
            if not entry:
                self.say_entry("can-param", key, value, "an entry is empty")
                ok = False
                continue
            joint_text, eq, text = entry.partition("=")
            if not eq:
                if have_default:
                    self.say_entry("can-param", key, entry, "a second entry for every joint")
                    ok = False
                elif (parsed := parse(entry)) is None:
                    self.say_entry("can-param", key, entry, expected)
                    have_default, ok = 2, False
                else:
                    have_default, default = 1, parsed
                continue
            joint = _trim(joint_text)
            if joint not in self.joints:
                self.say_entry("can-param", key, entry,
                               f"{quote(joint)} is not a joint of hardware.joints")
                ok = False
            elif joint in have:
                self.say_entry("can-param", key, entry, f'joint "{joint}" is given twice')
                ok = False
            elif (parsed := parse(_trim(text))) is None:
                self.say_entry("can-param", key, entry, expected)
                have[joint], ok = False, False
            else:
                have[joint] = True
                self.values[key][joint] = parsed
        for joint in self.joints:
            if joint in have:
                continue
            if have_default == 1:
                self.values[key][joint] = default
            elif not required:
                self.values[key][joint] = absent
            elif have_default == 0:
                self.say_entry("can-param", key, value,
                               f'no value for joint "{joint}", and none for every joint')
                ok = False
        return ok

    # ---- cross-checks -----------------------------------------------------

    def check_ids(self) -> None:
        ids = self.values["can_id"]
        master = self.config["master_id"]
        for j, joint in enumerate(self.joints):
            head = f': hardware.params: can_id: joint "{joint}": id {ids[joint]}'
            if ids[joint] == master:
                self.say("can-id", head + " is master_id, where replies come from")
                continue
            for other in self.joints[:j]:
                if ids[other] == ids[joint]:
                    self.say("can-id", head + f' is also that of joint "{other}"')
                    break
                if ids[other] & 0xFF == ids[joint] & 0xFF:
                    self.say("can-id", head + f" (0x{ids[joint]:03X}) answers with id byte "
                             f'0x{ids[joint] & 0xFF:02X}, as joint "{other}" (id {ids[other]}) '
                             "does")
                    break

    def bound(self, name: str, itype: str, is_state: bool) -> bool:
        joint, slash, suffix = name.rpartition("/")
        if not slash or joint not in self.joints or suffix != itype:
            return False
        return itype in (STATE_TYPES if is_state else COMMAND_TYPES)

    def check_channels(self) -> bool:
        ok = True
        used = set()
        for kind, channels in (("commands", self.m.commands), ("states", self.m.states)):
            for i, ch in enumerate(channels):
                if self.bound(ch.name, ch.interface_type, kind == "states"):
                    used.add(ch.name.rpartition("/")[0])
                    continue
                what = ("the socketcan port takes JOINT/position, /velocity, /stiffness, "
                        "/damping and /effort commands, of a joint of hardware.joints, each of "
                        "its type") if kind == "commands" else (
                        "the socketcan port gives JOINT/position, /velocity and /effort states, "
                        "of a joint of hardware.joints, each of its type")
                self.say("can-channel", f": manifest.{kind}[{i}] {quote(ch.name)}: {what}")
                ok = False
        for j, joint in enumerate(self.joints):
            if joint not in used:
                self.say_joint(j, joint, "no channel of the manifest is this joint's")
                ok = False
        return ok

    def check_ranges(self) -> None:
        for kind, channels in (("commands", self.m.commands), ("states", self.m.states)):
            for i, ch in enumerate(channels):
                joint = ch.name.rpartition("/")[0]
                key = next(k for k, t in RANGE_TYPES.items() if t == ch.interface_type)
                lo_r, hi_r = self.values[key][joint]
                sign = self.values["direction"][joint]
                offset = self.values["zero_offset"][joint]
                a, b = ch.min, ch.max
                if ch.interface_type == "position":
                    a, b = float(sign) * (ch.min - offset), float(sign) * (ch.max - offset)
                elif ch.interface_type in ("velocity", "effort"):
                    a, b = float(sign) * ch.min, float(sign) * ch.max
                lo, hi = (a, b) if a < b else (b, a)
                if lo >= lo_r and hi <= hi_r:
                    continue
                text = (f': hardware.params: {key}: joint "{joint}": the actuator\'s range '
                        f"[{c_double(lo_r)}, {c_double(hi_r)}] does not hold manifest.{kind}[{i}] "
                        f"{quote(ch.name)} limits [{c_double(ch.min)}, {c_double(ch.max)}]")
                if lo != ch.min or hi != ch.max:
                    text += f" (the actuator sees [{c_double(lo)}, {c_double(hi)}])"
                self.say("can-range", text)

    def check_bus(self) -> bool:
        c = self.config
        period = c["command_writer_period_us"]
        round_us = period if period != 0 else 1000000 // self.m.control_rate_hz
        round_us = max(round_us, 1)
        budget = c["bitrate"] * round_us * c["max_bus_load_percent"] // 100000000
        replies = self.values["reply"]
        bits = [frame_bits(8) + frame_bits(LAYOUTS[replies[j]]) for j in self.joints]
        groups, worst = 0, 0
        for k in range(1, len(self.joints) + 1):
            worst = max(sum(bits[g::k]) for g in range(k))
            if worst <= budget:
                groups = k
                break
        if groups == 0:
            shown = f" {quote(self.params[k])}" if (k := "command_writer_period_us") in \
                self.params else ""
            self.say("can-bus", f": hardware.params: command_writer_period_us{shown}: a joint's "
                     f"command and reply take {worst} bits, more than "
                     f"{c['max_bus_load_percent']}% of a {round_us} us round at {c['bitrate']} "
                     f"bit/s ({budget} bits)")
            return False
        interval = round_us * groups
        c["joint_interval_us"] = interval
        if "reply_timeout_us" in self.params and c["reply_timeout_us"] < 2 * interval:
            self.say("can-bus", f": hardware.params: reply_timeout_us "
                     f"{quote(self.params['reply_timeout_us'])}: shorter than two command "
                     f"intervals of a joint (2 x {interval} us)")
            return False
        return True

    def check_command_timeout(self) -> None:
        """The command watchdog: at least two command intervals of a joint and two ticks."""
        c = self.config
        rate = self.m.control_rate_hz
        slowest = max((1000000 + rate - 1) // rate, c["joint_interval_us"])
        least = WATCHDOG_MIN_PERIODS * slowest
        default = max(WATCHDOG_DEFAULT_US, WATCHDOG_DEFAULT_PERIODS * slowest)
        if default > WATCHDOG_MAX_US:
            default = max(least, WATCHDOG_MAX_US)
        if "command_timeout_us" not in self.params:
            c["command_timeout_us"] = default
        elif c["command_timeout_us"] < least:
            self.say("can-bus", f": hardware.params: command_timeout_us "
                     f"{quote(self.params['command_timeout_us'])}: shorter than two command "
                     f"intervals of a joint or two ticks (2 x {slowest} us)")


def check(manifest: Manifest) -> list[tuple[str, str]]:
    """The problems of a socketcan robot's [hardware] keys (none: valid)."""
    if manifest.hardware is None or manifest.hardware.port != PORT:
        return []
    return _Checker(manifest).run()
