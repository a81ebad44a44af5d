# SPDX-License-Identifier: Apache-2.0
"""The [hardware] keys of a robot for the ROS 2 ports ``agibot/X2`` and
``engineai/PM01`` (ports/ros2). They share the binding of joints and
channels (``hal/src/joints.c``), the parameter parsers
(``hal/src/params.c``) and the DDS parameters
(``ports/dds/src/dds_params.c``); what differs is the robot's joints and a
key of its own. These are the rules the ports apply at open, in their
order and with their words, so that rozgen refuses at build time what the
port would refuse at the robot's first start.

Only what the manifest alone decides: parameters given at run time
(``rozrun --param``) come after robot.toml's and are checked by the port.

A port's open stops at its first problem; rozgen goes on where the checks
do not depend on each other, so its first problem is the one the port
gives. Each message is ``": "`` and then the port's own text (the C test
``test_port_vectors`` opens each port with the shared vectors and
compares). ``unitree/G1``'s rules are written once, in C
(``ports/unitree_g1/src/g1_rules.c``), and run by rozgen's checker.

``check(manifest)`` runs on a manifest that passed every other rule and
returns ``(rule, message)`` pairs.
"""

import math
import re
from dataclasses import dataclass

from rozgen import threads
from rozgen.model import Manifest

# ---- the robots (the ports' tables, in their order) ----------------------------

#: agibot/X2: joint groups (x2_port.c)
X2_GROUPS = (
    ("leg", ("left_hip_pitch_joint", "left_hip_roll_joint", "left_hip_yaw_joint",
             "left_knee_joint", "left_ankle_pitch_joint", "left_ankle_roll_joint",
             "right_hip_pitch_joint", "right_hip_roll_joint", "right_hip_yaw_joint",
             "right_knee_joint", "right_ankle_pitch_joint", "right_ankle_roll_joint")),
    ("waist", ("waist_yaw_joint", "waist_pitch_joint", "waist_roll_joint")),
    ("arm", ("left_shoulder_pitch_joint", "left_shoulder_roll_joint",
             "left_shoulder_yaw_joint", "left_elbow_joint", "left_wrist_yaw_joint",
             "left_wrist_pitch_joint", "left_wrist_roll_joint", "right_shoulder_pitch_joint",
             "right_shoulder_roll_joint", "right_shoulder_yaw_joint", "right_elbow_joint",
             "right_wrist_yaw_joint", "right_wrist_pitch_joint", "right_wrist_roll_joint")),
    ("head", ("head_yaw_joint", "head_pitch_joint")),
)

#: engineai/PM01: its one joint group (pm01_port.c)
PM01_GROUPS = (
    ("body", ("J00_HIP_PITCH_L", "J01_HIP_ROLL_L", "J02_HIP_YAW_L", "J03_KNEE_PITCH_L",
              "J04_ANKLE_PITCH_L", "J05_ANKLE_ROLL_L", "J06_HIP_PITCH_R", "J07_HIP_ROLL_R",
              "J08_HIP_YAW_R", "J09_KNEE_PITCH_R", "J10_ANKLE_PITCH_R", "J11_ANKLE_ROLL_R",
              "J12_WAIST_YAW", "J13_SHOULDER_PITCH_L", "J14_SHOULDER_ROLL_L",
              "J15_SHOULDER_YAW_L", "J16_ELBOW_PITCH_L", "J17_ELBOW_YAW_L",
              "J18_SHOULDER_PITCH_R", "J19_SHOULDER_ROLL_R", "J20_SHOULDER_YAW_R",
              "J21_ELBOW_PITCH_R", "J22_ELBOW_YAW_R", "J23_HEAD_YAW")),
)

#: ROZ_DDS_PARAM_KEYS (roz/port/dds.h)
DDS_KEYS = ("network_interface", "dds_domain", "enable_monitor", "exit_stop",
            "command_writer_period_us",
            "command_writer_spin_us", "state_decimation",
            # the writer thread's (roz/hal/thread.h): checked by the port when it opens
            "command_writer_sched", "command_writer_priority", "command_writer_cpus",
            "command_writer_stack_kib", "dds_threads_sched", "dds_threads_priority",
            "dds_threads_stack_kib", "command_timeout_us")
#: common_keys of ros2_bridge.c; a robot's own follow
ROS2_KEYS = DDS_KEYS + ("peer_timeout_ms", "startup_damping", "shutdown_damping", "link_check",
                        # the operator topics': checked by the port when it opens
                        "cmd_vel_topic", "joy_topic", "joy_map")

MAX_JOINTS = 64  # ROZ_CFG_MAX_JOINTS
NAME_ROOM = 160  # joints.c: a longer "<joint>/<suffix>" is no channel's name
IFNAME_MAX = 15  # ROZ_DDS_IFNAME_MAX
MAX_DOMAIN = 232  # ROZ_DDS_MAX_DOMAIN
MIN_PERIOD_US = 100  # ROZ_DDS_MIN_PERIOD_US
MAX_PERIOD_US = 1000000  # ROZ_DDS_MAX_PERIOD_US
MAX_SPIN_US = 10000  # ROZ_DDS_MAX_SPIN_US
#: the command watchdog's, as roz/hal/cmd_watchdog.h has them
WATCHDOG_DEFAULT_US = 50000
WATCHDOG_DEFAULT_PERIODS = 5
WATCHDOG_MIN_PERIODS = 2
WATCHDOG_MAX_US = 60000000

#: joints.c: the channels a joint may have, in the order they are looked up
JOINT_CHANNELS = (
    ("position", "position", "state"), ("velocity", "velocity", "state"),
    ("effort", "effort", "state"), ("position", "position", "command"),
    ("velocity", "velocity", "command"), ("effort", "effort", "command"),
    ("stiffness", "stiffness", "command"), ("damping", "damping", "command"),
)
#: joints.c: the IMU's states and their types
IMU_STATES = tuple(
    [(f"base_imu/orientation.{a}", "orientation") for a in "xyzw"]
    + [(f"base_imu/angular_velocity.{a}", "velocity") for a in "xyz"]
    + [(f"base_imu/linear_acceleration.{a}", "acceleration") for a in "xyz"])

BOOLS = {"true": True, "1": True, "yes": True, "on": True,
         "false": False, "0": False, "no": False, "off": False}

_IFNAME = re.compile(r"[A-Za-z0-9_.:-]{1,%d}" % IFNAME_MAX)
# what strtod reads whole (C locale); inf and nan are refused as not finite
_DECIMAL = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")
_HEX = re.compile(r"[+-]?0[xX]([0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)([pP][+-]?[0-9]+)?")
_C_SPACE = " \t\n\v\f\r"


@dataclass(frozen=True)
class Port:
    """One DDS port as its open sees a manifest."""

    name: str  # [hardware] port
    family: str  # rule ids: <family>-joint, -channel, -param
    groups: tuple  # ((group, (joint, ...)), ...)
    robot: str  # as the binding's messages call it
    keys: tuple[str, ...]  # known [hardware.params] keys, in the port's order
    has_sequence: bool = False  # ROS 2: the state headers carry a sequence
    own: str = ""  # ROS 2: the robot's own key, checked last

    @property
    def joints(self) -> tuple[str, ...]:
        return tuple(j for _, group in self.groups for j in group)


X2 = Port("agibot/X2", "ros2", X2_GROUPS, "this robot", ROS2_KEYS + ("joint_state_layout",),
          has_sequence=True, own="joint_state_layout")
PM01 = Port("engineai/PM01", "ros2", PM01_GROUPS, "this robot",
            ROS2_KEYS + ("parallel_parser_type",), own="parallel_parser_type")
PORTS = {p.name: p for p in (X2, PM01)}

#: the robots' own keys: accepted values, and what the port says otherwise
OWN_VALUES = {
    "joint_state_layout": (("sdk", "docs"),
                           "expected sdk (the SDK's JointState: name, position, velocity, "
                           "effort, error_code; the default) or docs (the online "
                           "documentation's: ..., coil_temp, motor_temp, motor_vol)"),
    "parallel_parser_type": (("rl", "RL_PARSER", "1", "classic", "CLASSIC_PARSER", "0"),
                             "expected rl (1, RL_PARSER, the default, as the vendor's RL "
                             "example) or classic (0, CLASSIC_PARSER)"),
}


# ---- the parsers of hal/src/params.c ------------------------------------------

def u32(text: str, lo: int, hi: int) -> int | None:
    """roz_params_get_u32: decimal digits only, within lo..hi."""
    if not text or not "0" <= text[0] <= "9" or not text.isascii() or not text.isdigit():
        return None
    value = int(text)
    return value if lo <= value <= hi else None


def strtod_whole(text: str) -> float | None:
    """What strtod makes of the whole of ``text`` (None: not all of it is a number)."""
    body = text.lstrip(_C_SPACE)
    if _DECIMAL.fullmatch(body):
        return float(body)
    if _HEX.fullmatch(body):
        sign = -1.0 if body[0] == "-" else 1.0
        return sign * float.fromhex(body.lstrip("+-"))
    return None


def number(text: str, lo: float, hi: float) -> float | None:
    """roz_params_get_double: a finite number within lo..hi."""
    value = strtod_whole(text)
    if value is None or not math.isfinite(value) or not lo <= value <= hi:
        return None
    return value


def g(x: float) -> str:
    """roz_format's %g."""
    return "%g" % x


# ---- the checks ---------------------------------------------------------------

class _Checker:
    def __init__(self, manifest: Manifest, port: Port) -> None:
        self.m = manifest
        self.port = port
        self.hw = manifest.hardware
        self.params = dict(self.hw.params)  # sorted by key, as the C loader keeps them
        self.problems: list[tuple[str, str]] = []
        self.damping: list[tuple[float, float]] = []  # bound damping commands' limits

    def say(self, rule: str, text: str) -> None:
        self.problems.append((rule, ": " + text))

    def run(self) -> list[tuple[str, str]]:
        if self.bind_joints() and self.bind_channels():
            self.check_params()
        return self.problems

    # ---- binding: ports' place(), roz_joints_bind() -----------------------

    def bind_joints(self) -> bool:
        p, joints = self.port, self.hw.joints
        rule = f"{p.family}-joint"
        n_slots = len(p.joints)
        if not 1 <= len(joints) <= MAX_JOINTS:
            self.say(rule, f"{p.name}: manifest {self.m.robot_id}: [hardware] joints must list "
                     f"the robot's joints (1..{n_slots}), it lists {len(joints)}")
            return False
        elif len(joints) > n_slots:
            self.say(rule, f"{p.name}: manifest {self.m.robot_id}: [hardware] joints lists "
                     f"{len(joints)} joints; the robot has {n_slots}")
            return False
        ok = True
        first: dict[str, int] = {}
        for k, joint in enumerate(joints):
            if joint not in p.joints:
                by_group = " by group" if len(p.groups) > 1 else ""
                self.say(rule, f'{p.name}: [hardware] joints[{k}] "{joint}" is not one of the '
                         f"robot's joints (the port's header lists them{by_group})")
                ok = False
            elif joint in first:  # the C loader refuses it first (duplicate-joint)
                self.say(rule, f'{p.name}: [hardware] joints[{k}] "{joint}" is listed twice')
                ok = False
            else:
                first[joint] = k
        return ok

    def bind_channels(self) -> bool:
        p, m = self.port, self.m
        states = {c.name: (i, c) for i, c in reversed(list(enumerate(m.states)))}
        commands = {c.name: (i, c) for i, c in reversed(list(enumerate(m.commands)))}
        seen: set[tuple[str, int]] = set()  # bound, or already said wrong
        ok = True
        for j, joint in enumerate(self.hw.joints):
            found = False
            for suffix, itype, kind in JOINT_CHANNELS:
                name = f"{joint}/{suffix}"
                if len(name.encode("utf-8")) >= NAME_ROOM:
                    continue
                hit = (states if kind == "state" else commands).get(name)
                if hit is None:
                    continue
                i, ch = hit
                found = True
                seen.add((kind, i))
                if ch.interface_type != itype:
                    self.say(f"{p.family}-channel", f'{p.name}: {kind} {i} "{name}" has interface_type '
                             f"{ch.interface_type}; the port serves it as {itype}")
                    ok = False
                elif kind == "command" and itype == "damping":
                    self.damping.append((ch.min, ch.max))
            if not found:
                self.say(f"{p.family}-joint", f'{p.name}: [hardware] joints[{j}] "{joint}" has '
                         f"no channel in manifest {m.robot_id} (expected {joint}/position, "
                         "/velocity, /effort, /stiffness, /damping)")
                ok = False
        for name, itype in IMU_STATES:
            hit = states.get(name)
            if hit is None:
                continue
            i, ch = hit
            seen.add(("state", i))
            if ch.interface_type != itype:
                self.say(f"{p.family}-channel", f'{p.name}: state {i} "{name}" has interface_type '
                         f"{ch.interface_type}; expected {itype}")
                ok = False
        for i, ch in enumerate(m.states):
            if ("state", i) not in seen:
                self.say(f"{p.family}-channel", f'{p.name}: state {i} "{ch.name}" has no source '
                         f"on {p.robot} (joint states are <joint>/position, /velocity, /effort "
                         "of a [hardware] joint; the IMU is base_imu/orientation.x..w, "
                         "angular_velocity.x..z, linear_acceleration.x..z)")
                ok = False
        for i, ch in enumerate(m.commands):
            if ("command", i) not in seen:
                self.say(f"{p.family}-channel", f'{p.name}: command {i} "{ch.name}" has no place '
                         f"on {p.robot} (commands are <joint>/position, /velocity, /effort, "
                         "/stiffness, /damping of a [hardware] joint)")
                ok = False
        return ok

    # ---- parameters: the ports' parse_params() ------------------------------

    def bad(self, key: str, what: str) -> None:
        self.say(f"{self.port.family}-param", f'parameter {key} = "{self.params[key]}": {what}')

    def check_u32(self, key: str, lo: int, hi: int) -> bool:
        if key in self.params and u32(self.params[key], lo, hi) is None:
            self.bad(key, f"expected an integer in {lo}..{hi}")
            return False
        return True

    def check_params(self) -> None:
        p, params = self.port, self.params
        for key in params:
            if key not in p.keys:
                self.say("unknown-key", f'unknown parameter "{key}" for port {p.name} (known: '
                         f"{' '.join(p.keys)})")
        # roz_dds_params_parse()
        iface = params.get("network_interface")
        if iface is not None and not _IFNAME.fullmatch(iface):
            self.bad("network_interface", "expected an interface name (1..15 characters from "
                     "A-Z a-z 0-9 _ . : -), such as lo or eth0")
        self.check_u32("dds_domain", 0, MAX_DOMAIN)
        if "enable_monitor" in params and params["enable_monitor"] not in BOOLS:
            self.bad("enable_monitor", "expected true or false")
        if "exit_stop" in params and params["exit_stop"] not in ("hold", "damping"):
            self.bad("exit_stop", "expected hold (the stop's hold at the hold gains, the "
                     "default) or damping (kp 0, kd shutdown_damping)")
        self.check_u32("state_decimation", 1, 1000)
        period = 2000
        if "command_writer_period_us" in params:
            period = u32(params["command_writer_period_us"], 0, MAX_PERIOD_US)
            if period is None or 0 < period < MIN_PERIOD_US:
                self.bad("command_writer_period_us", "expected 0 (publish as soon as the tick "
                         f"writes) or a period in {MIN_PERIOD_US}..{MAX_PERIOD_US} us")
                period = None
        spin = 0  # a spinning writer is an event-driven one
        if "command_writer_spin_us" in params:
            spin = u32(params["command_writer_spin_us"], 0, MAX_SPIN_US)
            if spin is None:
                self.bad("command_writer_spin_us", f"expected an integer in 0..{MAX_SPIN_US}")
        if spin and period:
            self.bad("command_writer_spin_us", "only with an event-driven writer "
                     f"(command_writer_period_us = 0); this one publishes every {period} us")
        # roz_thread_params(): the writer's, then Cyclone's
        found = threads.problem(params, "command_writer") or threads.cyclone_problem(params)
        if found is not None:
            self.say(f"{p.family}-param", found)
        if period is not None:
            self.check_command_timeout(period)
        # the port's own
        self.check_u32("peer_timeout_ms", 10, 60000)
        self.check_link_check()
        self.check_damping()
        self.check_own(p.own)

    def check_command_timeout(self, period: int) -> None:
        """roz_cmd_watchdog_param()."""
        rate = self.m.control_rate_hz
        tick_us = (1000000 + rate - 1) // rate
        slowest = max(tick_us, period)
        least = max(WATCHDOG_MIN_PERIODS * slowest, 1)
        default = min(max(WATCHDOG_DEFAULT_PERIODS * slowest, WATCHDOG_DEFAULT_US),
                      WATCHDOG_MAX_US)
        key = "command_timeout_us"
        if least > WATCHDOG_MAX_US:
            self.say(f"{self.port.family}-param",
                     f"parameter {key}: the tick ({rate} Hz) or the command writer ({period} us) "
                     f"is too slow for any timeout up to {WATCHDOG_MAX_US} us")
            return
        if key in self.params and u32(self.params[key], least, WATCHDOG_MAX_US) is None:
            self.bad(key, f"expected a time in {least}..{WATCHDOG_MAX_US} us (at least "
                     f"{WATCHDOG_MIN_PERIODS} periods of the tick at {rate} Hz and of the "
                     f"command writer; default {default})")

    def check_own(self, key: str) -> None:
        values, what = OWN_VALUES[key]
        if key in self.params and self.params[key] not in values:
            self.bad(key, what)

    def check_link_check(self) -> None:
        allowed = ("stamp", "sequence") if self.port.has_sequence else ("stamp",)
        if "link_check" in self.params and self.params["link_check"] not in allowed:
            self.bad("link_check", "expected " + (
                "sequence (the header's sequence number) or stamp (its stamp, strictly "
                "increasing)" if self.port.has_sequence
                else "stamp (these messages' std_msgs/Header has no sequence)")
                + " (what the state messages' headers offer the link checks)")

    def check_damping(self) -> None:
        """startup_damping and shutdown_damping: a gain every damping channel allows
        (roz_joints_damping_range(): 0..0 without one)."""
        lo = max((r[0] for r in self.damping), default=0.0)
        hi = min((r[1] for r in self.damping), default=0.0)
        for key in ("startup_damping", "shutdown_damping"):
            if key in self.params and number(self.params[key], lo, hi) is None:
                self.bad(key, f"expected a number in {g(lo)}..{g(hi)}")


def check(manifest: Manifest) -> list[tuple[str, str]]:
    """The problems of a DDS port robot's [hardware] keys (none: valid)."""
    if manifest.hardware is None or manifest.hardware.port not in PORTS:
        return []
    return _Checker(manifest, PORTS[manifest.hardware.port]).run()
