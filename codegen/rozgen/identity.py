# SPDX-License-Identifier: Apache-2.0
"""The identity of a manifest: its robot_id and the hash of its interface.

The *interface* is what a controller is written against: the channel table.
Its hash is FNV-1a 64 over this byte string (integers unsigned,
little-endian)::

    "roz-interface-v1"                 16 ASCII bytes
    u32 number of commands
    u32 number of states
    per command in index order, then per state in index order:
        u32 byte length, then the UTF-8 bytes of the name
        u32 byte length, then the interface type as in robot.toml ("velocity")
        u32 byte length, then the UTF-8 bytes of the unit ("" when unitless)
        u64 bits of min, u64 bits of max (IEEE 754 binary64; -0.0 as +0.0)

Nothing else is hashed: robot_id travels beside the hash, and robot_class,
control_rate_hz, default, max_rate_of_change, position_state_index,
[hardware] and any filter-only property change neither what an index means
nor what a controller may send. lib/src/identity.c computes the same value
from a roz_manifest_t in memory; codegen/README.md ("Manifest identity")
is the reference.

A controller carries the identity in a custom section ``roz.manifest``
holding one or more copies of the same record (wasm-ld concatenates the
sections of every object file)::

    u8  version (1)
    u8  length of robot_id (1..32)
    robot_id bytes ([a-z][a-z0-9_]*)
    u64 hash, little-endian
"""

import struct

from rozgen.model import Channel, Manifest

#: The first bytes hashed; the 1 names this canonical form.
TAG = b"roz-interface-v1"
#: Name of the custom section and version of its record.
SECTION = "roz.manifest"
RECORD_VERSION = 1

_FNV64_OFFSET = 0xCBF29CE484222325
_FNV64_PRIME = 0x100000001B3
_MASK64 = (1 << 64) - 1


def fnv1a64(data: bytes) -> int:
    """FNV-1a, 64 bits, of ``data``."""
    h = _FNV64_OFFSET
    for byte in data:
        h = ((h ^ byte) * _FNV64_PRIME) & _MASK64
    return h


def _text(s: str) -> bytes:
    raw = s.encode("utf-8")
    return struct.pack("<I", len(raw)) + raw


def _limit(x: float) -> bytes:
    return struct.pack("<d", 0.0 if x == 0.0 else x)  # -0.0 and 0.0 are one limit


def _channel(c: Channel) -> bytes:
    return (_text(c.name) + _text(c.interface_type) + _text(c.unit)
            + _limit(c.min) + _limit(c.max))


def interface_bytes(manifest: Manifest) -> bytes:
    """The canonical byte string of ``manifest``'s channel table."""
    parts = [TAG, struct.pack("<II", len(manifest.commands), len(manifest.states))]
    parts += [_channel(c) for c in manifest.commands + manifest.states]
    if manifest.inputs:  # read as states after the states; absent: the hash is unchanged
        parts.append(struct.pack("<I", len(manifest.inputs)))
        parts += [_channel(c) for c in manifest.inputs]
    return b"".join(parts)


def interface_hash(manifest: Manifest) -> int:
    """FNV-1a 64 of :func:`interface_bytes`."""
    return fnv1a64(interface_bytes(manifest))


def record(manifest: Manifest) -> bytes:
    """The ``roz.manifest`` record of a controller built for ``manifest``."""
    rid = manifest.robot_id.encode("ascii")
    return (bytes([RECORD_VERSION, len(rid)]) + rid
            + struct.pack("<Q", interface_hash(manifest)))
