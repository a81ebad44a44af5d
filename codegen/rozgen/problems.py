# SPDX-License-Identifier: Apache-2.0
"""Problems found in input files, each with a stable rule id.

A problem prints as ``<file><message>``; ``message`` starts with ``": "``
(or ``":<line>:<col>: "`` for TOML syntax errors). With ``--error-ids`` the
line is prefixed by ``[<rule>] ``. The rules are roz's C loader's
(``rozgen.checker``), which reports the same ids; their descriptions are
in ``RULES``, and each has a fixture in manifests/invalid/.
"""

from dataclasses import dataclass, field

#: Every rule id, in documentation order, with what it refuses.
RULES: dict[str, str] = {
    "io-error": "the file cannot be read (or an output cannot be written)",
    "utf8": "the file is not valid UTF-8",
    "toml-syntax": "the file is not valid TOML",
    "unknown-key": "a key or table that rozgen does not know (typos never pass)",
    "missing-key": "a required key or table is absent",
    "type": "a value has the wrong TOML type (booleans are not numbers, "
    "floats are not integers)",
    "nul-char": "a string holds a NUL character (C would cut it short)",
    "robot-id": "robot_id does not match [a-z][a-z0-9_]* or is longer than 32",
    "control-rate": "control_rate_hz is not in 1..100000",
    "name": "a channel name is empty, too long, has no letter or digit, or "
    "has characters other than printable ASCII without \" and \\",
    "interface-type": "interface_type is not a known type",
    "limits-shape": "limits is not an array of exactly two numbers",
    "not-finite": "limits, default, max_rate_of_change or limit_margin is inf or nan",
    "limits-order": "limits min is not below max",
    "default-range": "default is outside the limits",
    "max-rate": "max_rate_of_change is negative",
    "stale-after": "an operator input's stale_after_ms outside 1..3600000",
    "input-source": "an operator input's source is not a field of the remote or a twist",
    "input-scale": "an operator input's scale of 0, or a scale without a source",
    "duplicate-source": "two operator inputs with one source (one field feeds one input)",
    "remote-estop": "a remote_estop that is empty, names no button of the remote, or a button twice",
    "input-rate": "an operator input's max_rate_of_change of 0 (a stale input must return to its default gradually)",
    "duplicate-name": "two channels of one list have the same name",
    "constant-collision": "two names of one list give the same C constant",
    "pairing-range": "position_state_index is neither -1 nor a state index",
    "pairing-type": "position_state_index points at a state that is not of "
    "type position",
    "pairing-zero": "a velocity command paired with a position state has limits "
    "that exclude 0, so the filter could not stop it at a position limit",
    "pairing-on-state": "a state channel has a position_state_index other than -1",
    "margin-channel": "limit_margin on a channel other than a position state",
    "margin-range": "limit_margin is not above 0, or leaves no room to move (twice the "
    "margin is not below max - min)",
    "safe-default": 'safe_default is neither "follow" nor "hold", or "hold" on a channel '
    "other than a position command paired with a position state",
    "fall-orientation": "[manifest.fall] orientation names no states <orientation>.x, .y, .z "
    "and .w, or one of them is not an orientation state",
    "fall-tilt": "[manifest.fall] max_tilt_rad is not above 0 and below pi",
    "fall-time": "[manifest.fall] for_ms is not in 0..10000",
    "fall-stiffness": "a stiffness command whose limits exclude 0 in a manifest with a fall "
    "rule (the fallen stop sends zero stiffness)",
    "no-commands": "the manifest has no command channel",
    "too-many-channels": "more commands or states than ROZ_CFG_MAX_COMMANDS "
    "or ROZ_CFG_MAX_STATES (--max-commands, --max-states)",
    "joint-name": "a hardware joint name is empty",
    "duplicate-joint": "a hardware joint is listed twice",
    "can-param": "socketcan port: a [hardware.params] key of a CAN robot is missing or "
    "malformed (an entry, a number, a range, a layout)",
    "can-id": "socketcan port: two joints share a CAN id or its low byte (a reply's id), "
    "or one is master_id",
    "can-joint": "socketcan port: a hardware joint name it cannot use, none at all, or a "
    "joint without a channel",
    "can-channel": "socketcan port: a channel that is not JOINT/<type> of a hardware joint "
    "with a type it carries",
    "can-range": "socketcan port: an actuator's range does not hold the limits of one of "
    "its joint's channels",
    "can-bus": "socketcan port: one joint's frames overrun the bus in a round, or "
    "reply_timeout_us is shorter than two command intervals",
    "g1-joint": "unitree/G1 port: [hardware] joints lists none, more than the G1 has, a name "
    "that is not one of its SDK joint names, or a joint without a channel",
    "g1-channel": "unitree/G1 port: a channel that is not a listed joint's or the IMU's, or "
    "one of another type than the port serves under its name",
    "g1-param": "unitree/G1 port: a [hardware.params] value its parser refuses (a number out "
    "of range, an unknown mode_pr, a damping gain a damping channel does not allow)",
    "ros2-joint": "ROS 2 ports (agibot/X2, engineai/PM01): [hardware] joints lists none, more "
    "than the robot has, a name that is not one of its joints, or a joint without a channel",
    "ros2-channel": "ROS 2 ports: a channel that is not a listed joint's or the IMU's, or one "
    "of another type than the port serves under its name",
    "ros2-param": "ROS 2 ports: a [hardware.params] value their parser refuses (a number out "
    "of range, an unknown link_check or layout, a damping gain a damping channel does not "
    "allow)",
    "mujoco-param": "mujoco port: a [hardware.params] value its parser refuses before it "
    "loads the model (a number out of range, an unknown unbound)",
    "mujoco-model": "mujoco port: the model the file names cannot be read (missing, not "
    "XML, an include that cannot be read), or none is named for a robot without a built-in one",
    "mujoco-joint": "mujoco port: a manifest joint with no joint of that name in the model "
    "(or joint_names), not a hinge or slide, or driven by no actuator",
    "mujoco-imu": "mujoco port: base_imu channels, and the model has no such gyro (on a "
    "site) or accelerometer",
    "mujoco-effort": "mujoco port: a joint's effort limit that its actuator's force range "
    "cannot give, or no effort limit at all (and, under --check where a rozrun is found, "
    "the port's own: an effort channel wider than its motor's ctrlrange times gear and gain)",
    "storage": "a limit of the build of roz_manifest_json that checks the file: more than "
    "ROZ_CFG_MAX_JOINTS hardware joints or ROZ_CFG_MAX_PARAMS parameters, names beyond "
    "ROZ_CFG_NAME_ARENA_BYTES, a document beyond its reader's room",
    "duplicate-robot-id": "two files given together have the same robot_id",
    "source-root": "a file is not under --source-root",
}

#: Rules that no single robot.toml can break (they need several files, the
#: file system or --source-root), hence without a fixture in manifests/invalid.
#: (``storage``: the limits of the checker's build, not of robot.toml.)
RULES_WITHOUT_FIXTURE = frozenset({"io-error", "duplicate-robot-id", "source-root", "storage"})


@dataclass(frozen=True)
class Problem:
    """One thing wrong with one file."""

    rule: str
    message: str  # text after the file name, starting with ":"
    order: tuple = field(default=(), compare=False)  # sort key within a file

    def __post_init__(self) -> None:
        if self.rule not in RULES:
            raise ValueError(f"undocumented rule id {self.rule!r}")

    def render(self, file: str, with_id: bool = False) -> str:
        """The line printed on stderr."""
        prefix = f"[{self.rule}] " if with_id else ""
        return f"{prefix}{file}{self.message}"
