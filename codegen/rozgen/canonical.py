# SPDX-License-Identifier: Apache-2.0
"""Canonical JSON of a manifest (``rozgen --json``).

Every reader of robot.toml (this one, the C reader in lib/, future ones)
prints this exact text for the same file, so their results can be compared
byte for byte. A C program can write it with printf() alone. The format::

    {
      "robot_id": "ur5",
      "robot_class": "manipulator",
      "control_rate_hz": 100,
      "commands": [
        {"name": "a/velocity", "interface_type": "velocity", "unit": "rad/s", "limits": [-3.14, 3.14], "default": 0, "max_rate_of_change": 0.5, "position_state_index": 0, "limit_margin": null, "safe_default": "follow"},
        {"name": "b/velocity", ...}
      ],
      "states": [
        {"name": "a/position", "interface_type": "position", "unit": "rad", "limits": [-3.14, 3.14], "default": 0, "max_rate_of_change": 0, "position_state_index": -1, "limit_margin": 0.05, "safe_default": "follow"}
      ],
      "hardware": {"port": "unitree/G1", "joints": ["a", "b"], "params": {"dds_domain": "0"}}
    }

- UTF-8 (in fact ASCII), ``\\n`` line ends, a final newline, two-space indent.
- Keys always present and in the order shown. Channels one per line, in
  manifest order, keys in the order shown, ``", "`` and ``": "`` separators.
  An empty list is ``[]`` on the key's line. Defaults are written out:
  ``"robot_class": "generic"``, ``"max_rate_of_change": 0``,
  ``"position_state_index": -1``. ``"limit_margin"`` is the margin the
  filter keeps inside a position state's limits, the default worked out
  (``Channel.margin``, roz_manifest_limit_margin()), and ``null`` on
  commands and on states of other types. ``"safe_default"`` is
  ``"follow"`` unless the channel says ``"hold"``.
- ``"hardware"`` is ``null`` without a ``[hardware]`` table, else one line
  with ``"joints"`` (``[]`` when absent) in the given order and ``"params"``
  (``{}`` when absent) sorted by key (byte order of UTF-8 = code point order).
- Integers in decimal. Numbers of limits, default, max_rate_of_change and
  limit_margin (doubles, always finite) as the shortest ``%.{p}g``, p = 1..17, that reads
  back as the same double: ``0`` (also for ints written in TOML), ``-0``,
  ``0.5``, ``1e-05``, ``1e+16``, ``6.283185307179586``.
- Strings in double quotes, ASCII only: ``"`` -> ``\\"``, ``\\`` ->
  ``\\\\``, U+0008 U+000C U+000A U+000D U+0009 -> ``\\b \\f \\n \\r \\t``;
  every other character outside U+0020..U+007E (so also U+007F) -> ``\\u``
  and four lower-case hex digits of its UTF-16 code units (a character
  above U+FFFF gives a surrogate pair). ``/`` is not escaped. This is
  Python's ``json.dumps(s, ensure_ascii=True)``.
"""

from rozgen.fmt import json_string, shortest_g
from rozgen.model import Channel, Hardware, Manifest


def to_json(manifest: Manifest) -> str:
    """The canonical JSON text of ``manifest``, newline-terminated."""
    lines = [
        "{",
        f'  "robot_id": {json_string(manifest.robot_id)},',
        f'  "robot_class": {json_string(manifest.robot_class)},',
        f'  "control_rate_hz": {manifest.control_rate_hz},',
    ]
    lines += _channel_list("commands", manifest.commands, False)
    lines += _channel_list("states", manifest.states, True)
    lines.append(f'  "hardware": {_hardware(manifest.hardware)}')
    lines.append("}")
    return "\n".join(lines) + "\n"


def _channel_list(key: str, channels: tuple[Channel, ...], states: bool) -> list[str]:
    if not channels:
        return [f'  "{key}": [],']
    rows = [f"    {_channel(c, states)}," for c in channels]
    rows[-1] = rows[-1][:-1]
    return [f'  "{key}": ['] + rows + ["  ],"]


def _channel(c: Channel, state: bool) -> str:
    has_margin = state and c.interface_type == "position"
    fields = [
        ("name", json_string(c.name)),
        ("interface_type", json_string(c.interface_type)),
        ("unit", json_string(c.unit)),
        ("limits", f"[{shortest_g(c.min)}, {shortest_g(c.max)}]"),
        ("default", shortest_g(c.default)),
        ("max_rate_of_change", shortest_g(c.max_rate)),
        ("position_state_index", str(c.position_state)),
        ("limit_margin", shortest_g(c.margin) if has_margin else "null"),
        ("safe_default", json_string(c.safe_default)),
    ]
    return "{" + ", ".join(f'"{k}": {v}' for k, v in fields) + "}"


def _hardware(hw: Hardware | None) -> str:
    if hw is None:
        return "null"
    joints = ", ".join(json_string(j) for j in hw.joints)
    params = ", ".join(f"{json_string(k)}: {json_string(v)}" for k, v in hw.params)
    return (f'{{"port": {json_string(hw.port)}, "joints": [{joints}], '
            f'"params": {{{params}}}}}')
