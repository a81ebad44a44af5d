# SPDX-License-Identifier: Apache-2.0
"""rozgen and the DDS ports give the same verdict on seeded robot.toml variants.

    port_agreement.py --tool PORT_OPEN_CHECK --work DIR [--variants N] [--seed S]

Each variant is a small robot for unitree/G1, agibot/X2 or engineai/PM01,
made from a fixed seed: a few of the robot's joints (now and then a name it
does not have, or one of another robot's), some of each joint's channels
(now and then of the wrong type), some IMU states, now and then a channel
of no joint, and [hardware.params] drawn from every key the DDS ports know
and a few they do not, with values valid, at the edges of their ranges and
beyond them, at several tick rates. rozgen (``rozgen.validate``, this
checkout's: unitree/G1's rules in C, run by its checker, the ROS 2 ports'
in ``rozgen.dds_ports``) and the port's open
(port_open_check, roz's C loader and the port with no run-time parameter)
must agree: both accept it, or the port's error is rozgen's first line.
An interface name that passes the rules but names no interface of this
host is refused by the port at open, as it should be: those variants count
as accepted (their names are none a host has, so a port never opens a
network other than loopback).

dds_domain is always given, either 21 (the domain this test reserves) or
a value the ports refuse, so that a port that opens talks on no other
test's domain. Exit status 0 when every variant agrees and each verdict
(accepted, refused by each rule) was reached, 1 otherwise.
"""

import argparse
import collections
import os
import random
import re
import subprocess
import sys
from pathlib import Path

from rozgen import checker, dds_ports
from rozgen.load import load
from rozgen.validate import validate


def _g1() -> dds_ports.Port:
    """unitree/G1 as the variants need it: its joints and keys, read from
    its rules (ports/unitree_g1/src/g1_rules.c), which rozgen's checker runs."""
    text = (Path(__file__).resolve().parents[3] / "ports" / "unitree_g1" / "src" /
            "g1_rules.c").read_text(encoding="utf-8")

    def strings(name: str) -> tuple[str, ...]:
        found = re.search(name + r"\[[^\]]*\] = \{(.*?)\};", text, re.S)
        assert found, name
        return tuple(re.findall(r'"([^"]*)"', found.group(1)))

    return dds_ports.Port("unitree/G1", "g1", (("body", strings("slot_names")),), "the G1",
                          dds_ports.DDS_KEYS + strings("known_keys"))


ROBOTS = {"unitree/G1": _g1(), "agibot/X2": dds_ports.X2, "engineai/PM01": dds_ports.PM01}
OTHER_TYPES = ("position", "velocity", "effort", "stiffness", "damping", "acceleration",
               "orientation")
ALL_KEYS = sorted({k for p in ROBOTS.values() for k in p.keys})
#: per key: values the ports take, values at an edge, values they refuse
VALUES = {
    # names of no interface but lo: a port never opens one that may reach a
    # network (the others pass the rules and are absent at open)
    "network_interface": ["lo", "roz_none0", "roz-none.1:2", "roz" + "r" * 12,
                          "roz" + "r" * 13, "roz none", "", "roz/none", "é"],
    "dds_domain": ["233", "-1", "x", " 21", "21 ", "0x15", "99999999999"],
    "enable_monitor": ["true", "false", "1", "0", "yes", "no", "on", "off", "True", "", "2"],
    "state_decimation": ["1", "1000", "0", "1001", "10", "+5"],
    "command_writer_period_us": ["0", "99", "100", "2000", "1000000", "1000001", "1", "-0",
                                 "20000"],
    "command_writer_spin_us": ["0", "00", "1", "500", "10000", "10001", "-1", "1e3"],
    "command_timeout_us": ["0", "1999", "3999", "4000", "4001", "20000", "50000", "60000000",
                           "60000001", "2e4", ""],
    "mode_pr": ["PR", "pr", "0", "AB", "ab", "1", "PRR", "Pr", ""],
    "peer": ["robot", "unitree_mujoco", "unitree_mujoco", "mujoco", "Robot", ""],
    "peer_timeout_ms": ["9", "10", "500", "60000", "60001", "1e3"],
    "startup_damping": ["0", "0.5", "1", "5", "10", "10.0001", "-0", "-0.1", "1e1", "0x1p3",
                        " 2", "2 ", "nan", "inf", "abc", ""],
    "shutdown_damping": ["0", "0.5", "2.5", "10", "11", "-1", ".5", "5.", "1e-400", "1e400"],
    "link_check": ["stamp", "sequence", "Stamp", "", "seq"],
    "joint_state_layout": ["sdk", "docs", "doc", "SDK"],
    "parallel_parser_type": ["rl", "RL_PARSER", "1", "classic", "CLASSIC_PARSER", "0", "RL",
                             "2"],
    "dds_domian": ["0"], "mode": ["PR"], "enable monitor": ["true"], "Z": [""],
}
PORT_RULES = ("g1-joint", "g1-channel", "g1-param", "ros2-joint", "ros2-channel", "ros2-param",
              "unknown-key")
#: what a port finds at open only: the interface does not exist on this host
ABSENT = ": no such network interface"
RATES = (1, 50, 100, 333, 500, 1000, 2000, 100000)
JOINT_CHANNELS = dds_ports.JOINT_CHANNELS
UNITS = {"position": "rad", "velocity": "rad/s", "effort": "N.m", "stiffness": "N.m/rad",
         "damping": "N.m.s/rad", "acceleration": "m/s^2", "orientation": "1"}


def _channel(kind: str, name: str, itype: str, lo: float, hi: float) -> str:
    return (f'\n[[manifest.{kind}]]\nname = "{name}"\ninterface_type = "{itype}"\n'
            f'unit = "{UNITS[itype]}"\nlimits = [{lo!r}, {hi!r}]\n'
            f"default = {min(max(0.0, lo), hi)!r}\n")


def _variant(rng: random.Random) -> str:
    port_name = rng.choice(sorted(ROBOTS))
    port = ROBOTS[port_name]
    joints = rng.sample(port.joints, rng.randint(1, 3))
    if rng.random() < 0.1:
        joints.append(rng.choice(["left_knee", "J03_KNEE_PITCH_L", "head_yaw_joint",
                                  "waist_roll_joint", "left_wrist_roll_joint"]))
    if rng.random() < 0.03:
        joints = []
    joints = list(dict.fromkeys(joints))  # the loader refuses duplicates itself
    commands, states = [], []
    damping = (rng.choice([0.0, 0.0, 0.5, 1.0]), rng.choice([5.0, 10.0, 10.0]))
    for j in joints:
        kinds = [c for c in JOINT_CHANNELS if rng.random() < 0.5]
        if rng.random() < 0.05:
            kinds = []
        for suffix, itype, kind in kinds:
            if rng.random() < 0.03:
                itype = rng.choice([t for t in OTHER_TYPES if t != itype])
            lo, hi = (damping if itype == "damping" else
                      (0.0, 100.0) if itype == "stiffness" else (-2.0, 2.0))
            (states if kind == "state" else commands).append((f"{j}/{suffix}", itype, lo, hi))
    for name, itype in dds_ports.IMU_STATES:
        if rng.random() < 0.3:
            if rng.random() < 0.05:
                itype = rng.choice([t for t in OTHER_TYPES if t != itype])
            states.append((name, itype, -1.0, 1.0))
    if rng.random() < 0.05:
        commands.append(("gripper/position", "position", 0.0, 1.0))
    if rng.random() < 0.05:
        states.append(("imu/orientation.x", "orientation", -1.0, 1.0))
    if not commands:
        commands.append((f"{port.joints[0]}/position", "position", -1.0, 1.0))
    params = {"dds_domain": "21" if rng.random() < 0.9 else rng.choice(VALUES["dds_domain"])}
    # mostly the port's own keys (an unknown one stops the port before the values)
    keys = (list(port.keys) if rng.random() < 0.7
            else ALL_KEYS + ["dds_domian", "mode", "enable monitor", "Z"])
    for key in rng.sample(keys, rng.randint(0, 4)):
        # (the writer thread's keys have no VALUES: rozgen knows them, the
        # port alone checks their values, test/hal/test_thread.c)
        if key != "dds_domain" and key in VALUES:
            params[key] = rng.choice(VALUES[key])
    text = (f'[manifest]\nrobot_id = "variant"\ncontrol_rate_hz = {rng.choice(RATES)}\n'
            + "".join(_channel("commands", *c) for c in commands)
            + "".join(_channel("states", *s) for s in states)
            + f'\n[hardware]\nport = "{port_name}"\njoints = ['
            + ", ".join(f'"{j}"' for j in joints) + "]\n\n[hardware.params]\n"
            + "".join(f'"{k}" = "{v}"\n' for k, v in params.items()))
    return text


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--tool", required=True, help="port_open_check")
    p.add_argument("--work", required=True, help="a directory for the variants")
    p.add_argument("--variants", type=int, default=2000)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()

    os.makedirs(args.work, exist_ok=True)
    rng = random.Random(args.seed)
    files = []
    for i in range(args.variants):
        path = os.path.join(args.work, f"variant{i:04d}.toml")
        with open(path, "w", encoding="utf-8") as f:
            f.write(_variant(rng))
        files.append(path)

    ports = {}
    for start in range(0, len(files), 100):
        done = subprocess.run([args.tool] + files[start:start + 100], capture_output=True,
                              text=True, timeout=600, check=True)
        for line in done.stdout.splitlines():
            file, _, said = line.partition(": ")
            ports[file] = said

    verdicts = collections.Counter()
    failed = 0
    rules = checker.find()  # once, not once per variant
    for path in files:
        loaded = load(path)
        problems = loaded.problems
        if loaded.data is not None:
            _, problems = validate(loaded.data, checker=rules)
        said = ports.get(path, "(nothing)")
        if said.startswith("[loader]"):
            verdicts["the loader's"] += 1
            ok = bool(problems) and problems[0].rule not in PORT_RULES
        elif not problems and said.endswith(ABSENT):
            verdicts["accepted, interface absent at open"] += 1
            ok = said.startswith('parameter network_interface = "roz')
        elif not problems:
            verdicts["accepted"] += 1
            ok = said == "ok"
        else:
            verdicts[problems[0].rule] += 1
            ok = problems[0].render(path) == f"{path}: {said}"
        if not ok:
            failed += 1
            first = problems[0].render(path, with_id=True) if problems else "(valid)"
            print(f"FAIL {path}\n  port:   {said}\n  rozgen: {first}")
    print(", ".join(f"{n} {v}" for v, n in sorted(verdicts.items())))
    print(f"{len(files)} variants, {failed} disagreeing")
    wanted = {"accepted", "unknown-key"} | {f"{f}-{k}" for f in ("g1", "ros2")
                                            for k in ("joint", "channel", "param")}
    missing = wanted - set(verdicts)
    if missing:
        print(f"no variant reached: {sorted(missing)}")
    return 1 if failed or missing else 0


if __name__ == "__main__":
    sys.exit(main())
