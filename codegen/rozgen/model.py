# SPDX-License-Identifier: Apache-2.0
"""The validated manifest: immutable, and valid by construction.

Only ``rozgen.validate`` builds these; renderers and the JSON writer read
them and never check anything. Field meanings follow roz/manifest.h.
"""

from dataclasses import dataclass

from rozgen import names

#: Interface types in roz_interface_t order (ROZ_IF_POSITION = 0, ...).
INTERFACE_TYPES = (
    "position",
    "velocity",
    "effort",
    "stiffness",
    "damping",
    "acceleration",
    "orientation",
)

#: roz_channel_t::position_state of an unpaired channel (ROZ_CHANNEL_UNPAIRED).
UNPAIRED = -1

#: The default limit margin of a position state: the smaller of MARGIN_MAX
#: (in its unit) and MARGIN_SHARE of its range (ROZ_MANIFEST_MARGIN_MAX,
#: ROZ_MANIFEST_MARGIN_SHARE; roz_manifest_limit_margin()).
MARGIN_MAX = 0.05
MARGIN_SHARE = 0.05


@dataclass(frozen=True)
class Maxima:
    """Compile-time maxima of the roz build the output is meant for."""

    commands: int = 256  # ROZ_CFG_MAX_COMMANDS
    states: int = 256  # ROZ_CFG_MAX_STATES
    name_len: int = 63  # ROZ_CFG_MAX_NAME_LEN, bytes without the NUL


@dataclass(frozen=True)
class Channel:
    """One command or state channel (roz_channel_t)."""

    name: str
    interface_type: str  # one of INTERFACE_TYPES
    unit: str
    min: float
    max: float
    default: float
    max_rate: float  # max change per tick; 0.0 = no cap
    position_state: int  # paired state index or UNPAIRED
    limit_margin: float  # position states: as written; 0.0 = the default
    safe_default: str = "follow"  # paired position commands: "follow" or "hold"
    stale_after_ms: int = 0  # operator inputs: ms without an update before the default; 0 elsewhere
    source: str = ""  # operator inputs: the device field ("remote.ly"); "" for none
    scale: float = 0.0  # with a source: value = scale * field (the C checker's 1 by default)

    @property
    def margin(self) -> float:
        """The margin the filter keeps inside a position state's limits:
        ``limit_margin``, or the default when that is 0 (as
        roz_manifest_limit_margin() computes it: the same double)."""
        if self.limit_margin > 0.0:
            return self.limit_margin
        return min(MARGIN_MAX, MARGIN_SHARE * (self.max - self.min))

    @property
    def constant(self) -> str:
        """``<NAME>`` part of the channel's index macro."""
        return names.constant_suffix(self.name)

    @property
    def c_source(self) -> str:
        """roz_operator_field_t enumerator: ``remote.btn.a`` gives
        ``ROZ_OPERATOR_REMOTE_BTN_A`` (the vocabulary is roz/operator.h's,
        checked by the C checker before it gets here)."""
        return "ROZ_OPERATOR_" + self.source.upper().replace(".", "_")

    @property
    def c_type(self) -> str:
        """roz_interface_t enumerator: ``ROZ_IF_VELOCITY``."""
        return "ROZ_IF_" + self.interface_type.upper()


@dataclass(frozen=True)
class Hardware:
    """The optional [hardware] table (roz_hardware_t)."""

    port: str
    joints: tuple[str, ...]  # in the SDK's motor order, as written
    params: tuple[tuple[str, str], ...]  # (key, value), sorted by key


@dataclass(frozen=True)
class Fall:
    """The fall rule, [manifest.fall] (roz_fall_rule_t)."""

    orientation: str  # the quaternion states' prefix, as written
    quaternion: tuple[int, int, int, int]  # their state indices, x, y, z, w
    max_tilt: float  # rad
    for_ms: int


@dataclass(frozen=True)
class Manifest:
    """A whole robot.toml (roz_manifest_t)."""

    robot_id: str
    robot_class: str
    control_rate_hz: int
    commands: tuple[Channel, ...]
    states: tuple[Channel, ...]
    hardware: Hardware | None
    #: operator inputs, read by a controller as states len(states) + k
    inputs: tuple[Channel, ...] = ()
    #: the remote's e-stop chord: button fields ("remote.btn.l2"), all held latch the e-stop
    remote_estop: tuple[str, ...] = ()
    #: the fall rule, or None
    fall: Fall | None = None

    @property
    def prefix(self) -> str:
        """Macro prefix: ``ROZ_UR5``."""
        return names.id_prefix(self.robot_id)

    @property
    def c_remote_estop(self) -> str:
        """``remote_estop`` as a C expression of ROZ_REMOTE_KEY() bits (the
        names are roz/operator.h's, checked by the C checker)."""
        return " | ".join("ROZ_REMOTE_KEY(ROZ_OPERATOR_" + b.upper().replace(".", "_") + ")"
                          for b in self.remote_estop)

    @property
    def longest_name(self) -> int:
        """Bytes in the longest channel name."""
        return max(len(c.name.encode("utf-8"))
                   for c in self.commands + self.states + self.inputs)
