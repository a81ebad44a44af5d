# SPDX-License-Identifier: Apache-2.0
"""Read a robot.toml: bytes -> UTF-8 text -> TOML document.

Problems (rule ids of ``rozgen.problems``):

- ``io-error``: ``<file>: cannot read: <strerror>``
- ``utf8``: ``<file>: cannot read: not valid UTF-8 (byte 0xff at offset 17)``
- ``toml-syntax``: ``<file>:<line>:<col>: invalid TOML: <what>``; line and
  column count from 1, the column in bytes of UTF-8 (what a C reader
  counts), ``<what>`` is tomllib's text without its ``(at line ...)`` tail.
  A document that ends too early points just past its last character.
  Also what roz refuses although tomllib reads it (``rozgen.toml_limits``):
  ``invalid TOML: integer does not fit in 64 bits (...)`` and
  ``unsupported TOML: arrays and inline tables nested more than 100 deep
  are not supported``, in the words of roz's C reader, at the same place;
  the first problem in the file wins, whichever reader would see it.
"""

import hashlib
import os
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from rozgen.problems import Problem
from rozgen.toml_limits import MAX_DEPTH, first_refusal, prefix_of

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
        where, what = _tomllib_error(text, str(e))
        problem = _refusal(text, len(text) if where is None else where)
        if problem is None:
            problem = (Problem("toml-syntax", f": invalid TOML: {what}") if where is None
                       else _at(text, where, f"invalid TOML: {what}"))
        return Loaded(path, None, digest, [problem])
    except RecursionError:  # nested deeper than Python's stack, so beyond MAX_DEPTH
        problem = _refusal(text, len(text))
        if problem is None:  # never, unless tomllib recursed elsewhere
            problem = Problem("toml-syntax", ": unsupported TOML: nested too deeply")
        return Loaded(path, None, digest, [problem])
    except ValueError as e:  # tomllib documents only TOMLDecodeError; be safe
        return Loaded(path, None, digest, [Problem("toml-syntax", f": invalid TOML: {e}")])
    if _may_be_refused(doc):
        problem = _refusal(text, len(text))
        if problem is not None:
            return Loaded(path, None, digest, [problem])
    return Loaded(path, doc, digest, [])


def _refusal(text: str, end: int) -> Problem | None:
    """What roz refuses before offset ``end``, as a problem; see the docstring."""
    found = first_refusal(text, end)
    if found is None:
        return None
    where, what = found
    return _at(text, where, f"{prefix_of(what)}: {what}")


def _may_be_refused(doc: dict) -> bool:
    """Whether ``first_refusal`` can find anything in a parsed document: an
    integer beyond 64 bits, or tables and arrays more than MAX_DEPTH deep
    (some of them may be [tables], which nest freely; the scan tells)."""
    todo: list[tuple[object, int]] = [(doc, 0)]
    while todo:
        value, depth = todo.pop()
        if isinstance(value, dict | list):
            if depth > MAX_DEPTH:
                return True
            items = value.values() if isinstance(value, dict) else value
            todo.extend((item, depth + 1) for item in items)
        elif isinstance(value, int) and not isinstance(value, bool):
            if not -(2**63) <= value < 2**63:
                return True
    return False


def _tomllib_error(text: str, message: str) -> tuple[int | None, str]:
    """(offset in characters or None, what) of a tomllib error message."""
    match = _TOMLLIB_WHERE.match(message)
    if match is None:
        return None, message
    if match["line"] is None:  # at the end of the document
        return len(text), match["what"]
    line_start = _nth_line_start(text, int(match["line"]))
    return line_start + int(match["col"]) - 1, match["what"]


def _at(text: str, offset: int, what: str) -> Problem:
    """A toml-syntax problem at character ``offset``: line and column from
    1, the column in bytes of UTF-8 (tomllib counts characters)."""
    line_start = text.rfind("\n", 0, offset) + 1
    line = text.count("\n", 0, line_start) + 1
    col = len(text[line_start:offset].encode("utf-8")) + 1
    return Problem("toml-syntax", f":{line}:{col}: {what}")


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
