# SPDX-License-Identifier: Apache-2.0
"""Warnings: what a valid manifest may say by mistake.

``lint(manifest)`` looks at a manifest ``rozgen.validate`` accepted and
returns what is likely a slip. rozgen prints each on stderr and goes on
(exit status unchanged); ``rozgen --strict`` makes each an error (exit 2,
nothing written). Warnings are not rules: the manifest stays valid for
every reader (the C loader, ``roz/manifest_toml.h``, accepts it as it is).

Warnings, by id (``--error-ids`` prefixes each with ``[<id>] ``)::

    pairing-names  a command paired with a position state of another
                   joint (joint = the name before its last "/", as the
                   ports bind channels): "joint1/velocity" with
                   "joint2/position"; names without a "/" are not compared

Format (after the file name)::

    : warning: manifest.commands[0] "joint1/velocity": position_state_index 1:
    paired with manifest.states[1] "joint2/position", a state of joint
    "joint2", not of "joint1"

(one line; ``error (--strict)`` in place of ``warning`` under --strict).
"""

from dataclasses import dataclass

from rozgen.model import UNPAIRED, Manifest

#: Every warning id, with what it flags.
WARNINGS: dict[str, str] = {
    "pairing-names": "a command is paired with the position state of another joint",
}


@dataclass(frozen=True)
class Warning:  # noqa: A001 - a rozgen warning, not the builtin category
    """One thing that looks wrong in a valid file."""

    rule: str
    message: str  # text after "warning" / "error (--strict)", starting with ":"

    def render(self, file: str, with_id: bool = False, strict: bool = False) -> str:
        """The line printed on stderr."""
        prefix = f"[{self.rule}] " if with_id else ""
        kind = "error (--strict)" if strict else "warning"
        return f"{prefix}{file}: {kind}{self.message}"


def _joint(name: str) -> str | None:
    return name.rsplit("/", 1)[0] if "/" in name else None


def lint(manifest: Manifest) -> list[Warning]:
    """The warnings of a valid manifest, in channel order."""
    out = []
    for i, command in enumerate(manifest.commands):
        if command.position_state == UNPAIRED:
            continue
        state = manifest.states[command.position_state]
        mine, theirs = _joint(command.name), _joint(state.name)
        if mine is not None and theirs is not None and mine != theirs:
            out.append(Warning(
                "pairing-names",
                f': manifest.commands[{i}] "{command.name}": position_state_index '
                f'{command.position_state}: paired with manifest.states[{command.position_state}] '
                f'"{state.name}", a state of joint "{theirs}", not of "{mine}"'))
    return out
