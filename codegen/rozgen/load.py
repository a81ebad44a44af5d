# SPDX-License-Identifier: Apache-2.0
"""Read a robot.toml's bytes (the rules read the rest: ``rozgen.validate``).

Problems (rule ids of ``rozgen.problems``):

- ``io-error``: ``<file>: cannot read: <strerror>``
"""

import hashlib
import os
from dataclasses import dataclass, field
from pathlib import Path

from rozgen.problems import Problem


@dataclass(frozen=True)
class Loaded:
    """One input file, read or not."""

    path: str  # as given on the command line
    data: bytes | None  # None when it cannot be read
    sha256: str | None  # hex digest of the file bytes, when readable
    problems: list[Problem] = field(default_factory=list)


def load(path: str) -> Loaded:
    """Read ``path``; never raises for a bad file."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        reason = e.strerror or str(e)
        return Loaded(path, None, None, [Problem("io-error", f": cannot read: {reason}")])
    return Loaded(path, data, hashlib.sha256(data).hexdigest())


def source_label(path: str, source_root: str | None) -> str | None:
    """How the banner names ``path``: never absolute, always with ``/``.

    Relative to ``source_root`` when given (None if ``path`` is not under
    it); else relative to the current directory when under it; else the
    base name.
    """
    # os.path.realpath never raises (unlike Path.resolve on symlink loops).
    resolved = Path(os.path.realpath(path))
    if source_root is not None:
        try:
            return resolved.relative_to(os.path.realpath(source_root)).as_posix()
        except ValueError:
            return None
    try:
        return resolved.relative_to(os.path.realpath(os.getcwd())).as_posix()
    except (ValueError, OSError):  # OSError: the current directory is gone
        return resolved.name
