# SPDX-License-Identifier: Apache-2.0
"""What roz refuses in TOML although Python's tomllib reads it.

Two things, refused by rozgen and by roz's C reader (host/toml/src/toml.c) alike,
at the same place and in the same words:

- an integer outside 64 bits: TOML requires an error for an integer that
  cannot be kept losslessly, and roz keeps 64-bit integers; tomllib keeps
  Python integers of any size (``1`` and 309 zeros would then overflow as a
  float). Reported at the integer's first character as ``invalid TOML``.
- arrays and inline tables nested more than ``MAX_DEPTH`` deep: tomllib
  recurses once or more per level and fails with RecursionError a few
  hundred levels down, at a place that depends on the Python stack; the
  C reader refuses the same depth. Reported at the bracket that goes too
  deep as ``unsupported TOML``.

``first_refusal(text, end)`` finds the first of them in document order
before ``end``. It reads TOML lexically (strings, comments, keys, values,
brackets) without building anything, and it is only ever asked about a part
of the text that tomllib has read without error -- all of it, or the part
before tomllib's error -- so it need not check what it skips.
"""

import re

#: ROZ_TOML_MAX_DEPTH of roz/toml.h.
MAX_DEPTH = 100
#: The messages of roz's C reader for the same refusals.
INT_RANGE = "integer does not fit in 64 bits (-9223372036854775808..9223372036854775807)"
DEPTH = f"arrays and inline tables nested more than {MAX_DEPTH} deep are not supported"

_INT64_MIN = -(2**63)
_INT64_MAX = 2**63 - 1

_WS = re.compile(r"[ \t\r\n]*")
_COMMENT = re.compile(r"#[^\n]*")
_BARE = re.compile(r"[A-Za-z0-9_-]+")
# Dates and times come before numbers (1979-05-27 starts like 1979); what is
# matched need not be a valid date: tomllib has read it.
_DATETIME = re.compile(
    r"\d{4}-\d{2}-\d{2}(?:[Tt ]\d{2}:\d{2}:\d{2}(?:\.\d+)?(?:[Zz]|[+-]\d{2}:\d{2})?)?"
    r"|\d{2}:\d{2}:\d{2}(?:\.\d+)?"
)
# An integer in TOML's forms, as long as both readers read it (digits with
# single underscores between them); it is a float when a fraction ('.' and
# a digit) or an exponent ('e', a sign, a digit) follows. Whatever follows
# else is the next thing to read (or an error after the integer).
# Possessive (*+): a shorter integer is never the answer.
_INTEGER = re.compile(
    r"0x(?P<hex>[0-9A-Fa-f](?:_?[0-9A-Fa-f])*+)"
    r"|0o(?P<oct>[0-7](?:_?[0-7])*+)"
    r"|0b(?P<bin>[01](?:_?[01])*+)"
    r"|(?P<dec>[+-]?(?:0|[1-9](?:_?[0-9])*+))(?!\.[0-9]|[eE][+-]?[0-9])"
)
_WORD = re.compile(r"[A-Za-z0-9_.+:-]+")  # floats, inf, nan, true, false
_BASIC = re.compile(r'"(?:[^"\\\n]+|\\.)*"?')  # ends at a newline, where tomllib stops


def first_refusal(text: str, end: int | None = None) -> tuple[int, str] | None:
    """(offset, message) of the first refusal before ``end``, or None.

    ``offset`` counts characters of ``text``; ``message`` is the text after
    ``invalid TOML: `` or ``unsupported TOML: `` (see ``prefix_of``).
    """
    end = len(text) if end is None else end
    stack: list[str] = []  # open '[' (arrays) and '{' (inline tables)
    state = "key"  # "key": a key or header comes next; "value"; "after" a value
    i = 0
    while i < end:
        i = _WS.match(text, i).end()
        if i >= end:
            break
        c = text[i]
        if c == "#":
            i = _COMMENT.match(text, i).end()
            continue
        if state == "after":
            if not stack:  # a newline ended the statement
                state = "key"
            elif c == ",":
                state = "value" if stack[-1] == "[" else "key"
                i += 1
            else:  # ']' or '}'
                _pop(stack)
                i += 1
            continue
        if state == "key":
            if c == "[" and not stack:
                i = _skip_header(text, i)
            elif c in "\"'":
                i = _skip_string(text, i)
            elif c == "=":
                state = "value"
                i += 1
            elif c == "}":  # an empty inline table
                _pop(stack)
                state = "after"
                i += 1
            elif c == ".":
                i += 1
            else:
                m = _BARE.match(text, i)
                i = m.end() if m is not None else i + 1
            continue
        # state == "value"
        if c in "[{":
            if len(stack) >= MAX_DEPTH:
                return i, DEPTH
            stack.append(c)
            state = "value" if c == "[" else "key"
            i += 1
        elif c == "]":  # an empty array, or after a trailing comma
            _pop(stack)
            state = "after"
            i += 1
        elif c in "\"'":
            i = _skip_string(text, i)
            state = "after"
        else:
            m = _DATETIME.match(text, i)
            if m is None:
                m = _INTEGER.match(text, i)
                if m is not None and not _INT64_MIN <= _integer(m) <= _INT64_MAX:
                    return i, INT_RANGE
            if m is None:
                m = _WORD.match(text, i)
            i = m.end() if m is not None and m.end() > i else i + 1
            state = "after"
    return None


def prefix_of(message: str) -> str:
    """``invalid TOML`` or ``unsupported TOML``, as roz's C reader says."""
    return "unsupported TOML" if message == DEPTH else "invalid TOML"


def _pop(stack: list[str]) -> None:
    if stack:  # always, in text that tomllib has read
        stack.pop()


def _integer(m: re.Match) -> int:
    for group, base in (("hex", 16), ("oct", 8), ("bin", 2), ("dec", 10)):
        if m[group] is not None:
            return int(m[group].replace("_", ""), base)
    raise AssertionError("unreachable")


def _skip_string(text: str, i: int) -> int:
    """The offset just past the string (of any of TOML's four kinds) at ``i``."""
    q = text[i]
    if text.startswith(q * 3, i):
        j = i + 3
        k = text.find(q * 3, j)
        while q == '"' and k >= 0:  # an escape may hide a quote
            esc = text.find("\\", j, k)
            if esc < 0:
                break
            j = esc + 2
            if k < j:
                k = text.find(q * 3, j)
        if k < 0:
            return len(text)
        k += 3
        for _ in range(2):  # up to two more quotes belong to the content
            if text.startswith(q, k):
                k += 1
        return k
    if q == '"':
        return _BASIC.match(text, i).end()
    k = text.find("'", i + 1)  # tomllib looks for the closing quote first
    return len(text) if k < 0 else k + 1


def _skip_header(text: str, i: int) -> int:
    """The offset just past the [table] or [[array of tables]] header at ``i``."""
    j = i + 1
    while j < len(text):
        c = text[j]
        if c in "\"'":
            j = _skip_string(text, j)
        elif c == "]":
            return j + 2 if text.startswith("]]", j) else j + 1
        elif c == "\n":
            return j
        else:
            j += 1
    return len(text)
