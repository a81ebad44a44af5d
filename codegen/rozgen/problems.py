# SPDX-License-Identifier: Apache-2.0
"""Problems found in input files, each with a stable rule id.

A problem prints as ``<file><message>``; ``message`` starts with ``": "``
(or ``":<line>:<col>: "`` for TOML syntax errors). With ``--error-ids`` the
line is prefixed by ``[<rule>] ``. The rules are roz's C loader's
(``rozgen.checker``), which reports the same ids; their descriptions are
in ``RULES`` (robot.toml's own here, each port's beside its rules in C:
``roz_manifest_json --list-rules``), and each has a fixture in
manifests/invalid/.
"""

import subprocess
from dataclasses import dataclass, field
from functools import cache

#: robot.toml's own rule ids, in documentation order, with what each
#: refuses; the ports' come from their rules (``ports()``), after
#: ``no-commands`` ... ``duplicate-joint``, before ``storage``.
_OWN: dict[str, str] = {
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
    "storage": "a limit of the build of roz_manifest_json that checks the file: more than "
    "ROZ_CFG_MAX_JOINTS hardware joints or ROZ_CFG_MAX_PARAMS parameters, names beyond "
    "ROZ_CFG_NAME_ARENA_BYTES, a document beyond its reader's room",
    "duplicate-robot-id": "two files given together have the same robot_id",
    "source-root": "a file is not under --source-root",
}

#: the rows after the ports'
_LAST = ("storage", "duplicate-robot-id", "source-root")


#: the roz_manifest_json that checked a file last (rozgen.checker.check())
used_checker: str | None = None


@cache
def ports() -> dict[str, str]:
    """The ports' rule ids and what each refuses, as their rules in C say
    (``roz_manifest_json --list-rules``: every registered port's)."""
    from rozgen import checker  # it needs Problem: not at import

    tool = used_checker or checker.find()
    try:
        done = subprocess.run([tool, "--list-rules"], capture_output=True, text=True)
    except OSError as e:
        raise checker.CheckerError(f"{tool}: cannot run: {e.strerror or e}") from None
    if done.returncode != 0:
        raise checker.CheckerError(f"{tool} --list-rules failed: {done.stderr.strip()}")
    return dict(line.split("\t", 1) for line in done.stdout.splitlines() if "\t" in line)


@cache
def rules() -> dict[str, str]:
    """Every rule id, in documentation order, with what it refuses."""
    own = [(k, v) for k, v in _OWN.items() if k not in _LAST]
    return dict(own + list(ports().items()) + [(k, _OWN[k]) for k in _LAST])


def __getattr__(name: str):
    if name == "RULES":  # every rule id: robot.toml's and the ports' (rules())
        return rules()
    raise AttributeError(name)


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
        if self.rule not in _OWN and self.rule not in rules():
            raise ValueError(f"undocumented rule id {self.rule!r}")

    def render(self, file: str, with_id: bool = False) -> str:
        """The line printed on stderr."""
        prefix = f"[{self.rule}] " if with_id else ""
        return f"{prefix}{file}{self.message}"
