# SPDX-License-Identifier: Apache-2.0
"""The [hardware] keys of a robot on the mujoco port (physics): the rules of
``ports/mujoco/src/mujoco.c`` that need no model, with the same words, so
that rozgen refuses at build time what the port would refuse at open. The
keys, their values and defaults are documented in ``docs/ports/mujoco.md``;
what needs the model (names, effort limits, the timestep's fit) the port
checks when it loads it.

``check(manifest)`` runs on a manifest that passed every other rule and
returns ``(rule, message)`` pairs, messages starting with ``": "``.
"""

import math

from rozgen.model import Manifest

PORT = "mujoco"

#: in the order of mujoco.c's known_keys (its error lists them so)
KEYS = (
    "model", "keyframe", "timestep", "joint_names", "imu_gyro", "imu_accelerometer",
    "servo_kp", "servo_kd", "unbound", "latency_ticks", "noise_seed", "noise_position",
    "noise_velocity", "noise_effort", "noise_gyro", "noise_accelerometer",
    "drop", "freeze", "delay", "push", "gantry", "restart",
    "wheel_left", "wheel_right", "wheel_radius", "wheel_separation", "max_thrust",
)

#: numbers the port reads with roz_params_get_double(), in the order it
#: reads them, and their ranges
NUMBERS = (
    ("wheel_radius", 1e-4, 10.0),
    ("wheel_separation", 1e-3, 100.0),
    ("max_thrust", 0.0, 1e6),
    ("servo_kp", 0.0, 1e7),
    ("servo_kd", 0.0, 1e6),
    ("noise_position", 0.0, 1.0),
    ("noise_velocity", 0.0, 10.0),
    ("noise_effort", 0.0, 100.0),
    ("noise_gyro", 0.0, 10.0),
    ("noise_accelerometer", 0.0, 100.0),
    ("timestep", 1e-6, 1.0),
)
#: integers (roz_params_get_u32())
INTEGERS = (("latency_ticks", 0, 15), ("noise_seed", 0, 4294967295))


def _g(x: float) -> str:
    """C's %g."""
    return f"{x:g}"


def _number(v: str) -> float | None:
    """strtod() over the whole string, finite; None otherwise."""
    try:
        x = float(v)
    except ValueError:
        return None
    if v != v.rstrip() or v.strip().lower().lstrip("+-") in ("nan", "inf", "infinity") or not math.isfinite(x):
        return None
    return x


def check(m: Manifest) -> list[tuple[str, str]]:
    hw = m.hardware
    if hw is None or hw.port != PORT:
        return []
    params = dict(hw.params)
    for key, _ in hw.params:
        if key not in KEYS:
            return [("unknown-key",
                     f': unknown parameter "{key}" for port {PORT} (known: {" ".join(KEYS)})')]
    problems = []
    for key, lo, hi in NUMBERS:
        v = params.get(key)
        if v is not None:
            x = _number(v)
            if x is None or x < lo or x > hi:
                problems.append(("mujoco-param", f': parameter {key} = "{v}": expected a number '
                                 f"in {_g(lo)}..{_g(hi)}"))
    for key, lo, hi in INTEGERS:
        v = params.get(key)
        if v is not None and not (v.isdigit() and v.isascii() and lo <= int(v) <= hi):
            problems.append(("mujoco-param", f': parameter {key} = "{v}": expected an integer '
                             f"in {lo}..{hi}"))
    unbound = params.get("unbound")
    if unbound is not None and unbound not in ("lock", "limp"):
        problems.append(("mujoco-param", f': parameter unbound = "{unbound}": expected lock or limp'))
    return problems
