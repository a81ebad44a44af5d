# SPDX-License-Identifier: Apache-2.0
"""Read a robot.toml: bytes -> UTF-8 text -> TOML document.

Problems (rule ids of ``rozgen.problems``):

- ``io-error``: ``<file>: cannot read: <strerror>``
- ``utf8``: ``<file>: cannot read: not valid UTF-8 (byte 0xff at offset 17)``
- ``toml-syntax``: ``<file>:<line>:<col>: invalid TOML: <what>``; line and
  column count from 1, the column in bytes of UTF-8 (what a C reader
  counts), ``<what>`` is tomllib's text without its ``(at line ...)`` tail.
  A document that ends too early points just past its last character.
"""

import hashlib
import os
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from rozgen.problems import Problem

_TOMLLIB_WHERE = re.compile(
    r"^(?P<what>.*) \(at (?:line (?P<line>\d+), column (?P<col>\d+)|end of document)\)$",
    re.DOTALL,
)


@dataclass(frozen=True)
class Loaded:
    """One input file, parsed or not."""

    path: str  # as given on the command line
    doc: dict | None  # None when any problem was found
    sha256: str | None  # hex digest of the file bytes, when readable
    problems: list[Problem] = field(default_factory=list)


def load(path: str) -> Loaded:
    """Read and parse ``path``; never raises for a bad file."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        reason = e.strerror or str(e)
        return Loaded(path, None, None, [Problem("io-error", f": cannot read: {reason}")])
    digest = hashlib.sha256(data).hexdigest()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        what = f": cannot read: not valid UTF-8 (byte 0x{data[e.start]:02x} at offset {e.start})"
        return Loaded(path, None, digest, [Problem("utf8", what)])
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        return Loaded(path, None, digest, [_syntax_problem(text, str(e))])
    except RecursionError:  # arrays nested deeper than Python's stack
        return Loaded(path, None, digest, [Problem("toml-syntax", ": invalid TOML: nested too deeply")])
    except ValueError as e:  # tomllib documents only TOMLDecodeError; be safe
        return Loaded(path, None, digest, [Problem("toml-syntax", f": invalid TOML: {e}")])
    return Loaded(path, doc, digest, [])


def _syntax_problem(text: str, message: str) -> Problem:
    match = _TOMLLIB_WHERE.match(message)
    if match is None:
        return Problem("toml-syntax", f": invalid TOML: {message}")
    what = match["what"]
    if match["line"] is not None:
        line = int(match["line"])
        # tomllib counts columns in characters; count bytes instead.
        line_start = _nth_line_start(text, line)
        chars = int(match["col"]) - 1
        col = len(text[line_start:line_start + chars].encode("utf-8")) + 1
    else:
        line = text.count("\n") + 1
        last = text[text.rfind("\n") + 1:]
        col = len(last.encode("utf-8")) + 1
    return Problem("toml-syntax", f":{line}:{col}: invalid TOML: {what}")


def _nth_line_start(text: str, line: int) -> int:
    """Offset of the first character of 1-based line ``line``."""
    start = 0
    for _ in range(line - 1):
        start = text.index("\n", start) + 1
    return start


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
