# SPDX-License-Identifier: Apache-2.0
"""Text forms of values: C literals, JSON strings, and values in messages.

Every function here is pure and has a C counterpart that a C tool can write
with printf() alone, so that readers of robot.toml in either language print
the same bytes:

- ``shortest_g(x)``: take the first of ``"%.1g"``, ``"%.2g"``, ...
  ``"%.17g"`` that reads back as exactly ``x`` (printf rounds correctly in
  glibc, musl and Python alike); if that text has an exponent ``e`` with
  ``0 <= e < 16``, print it again with ``"%.{e+1}g"``, which writes the same
  (integral) value without exponent. So ``0.0`` -> ``0``, ``-0.0`` -> ``-0``,
  ``100.0`` -> ``100`` (not ``1e+02``), ``0.1`` -> ``0.1``, ``1e-05`` ->
  ``1e-05``, ``1e16`` -> ``1e+16``, ``6.283185307179586`` ->
  ``6.283185307179586``. Not finite: ``inf``, ``-inf``, ``nan`` (never in
  generated C or JSON; only in messages). In C::

      for (p = 1; p < 17; p++) {
          snprintf(buf, sizeof buf, "%.*g", p, x);
          if (strtod(buf, NULL) == x) break;
      }
      const char *e = strchr(buf, 'e');
      if (e != NULL && atoi(e + 1) >= 0 && atoi(e + 1) < 16)
          snprintf(buf, sizeof buf, "%.*g", atoi(e + 1) + 1, x);

- ``c_double(x)``: ``shortest_g(x)`` plus ``.0`` when the text has none of
  ``.``, ``e``, ``n``, ``i`` -- a C double literal (``0`` -> ``0.0``).
- ``c_string(s)``: a C string literal of the UTF-8 bytes of ``s``.
- ``json_string(s)``: ``json.dumps(s, ensure_ascii=True)``; see
  ``tools/manifest_json/json.c`` for the exact escapes.
"""

import datetime
import json
import math

# Exponents from 0 up to this one are written out: 100, not 1e+02.
_FIXED_BELOW_EXPONENT = 16
# Longest array printed in full in a message; longer ones end in ", ...".
_MSG_ARRAY_ITEMS = 8
# Nesting depth beyond which arrays print as "[...]" in messages.
_MSG_ARRAY_DEPTH = 2


def shortest_g(x: float) -> str:
    """Shortest round-trip ``%g`` text of ``x``; see the module docstring."""
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    for precision in range(1, 18):
        text = "%.*g" % (precision, x)
        if float(text) == x:
            break
    _, e, exponent = text.partition("e")
    if e and 0 <= int(exponent) < _FIXED_BELOW_EXPONENT:
        # An integral value below 1e16: every digit of %.{exponent+1}g is
        # exact, so this is the same value, written the way people read it.
        text = "%.*g" % (int(exponent) + 1, x)
    return text


def c_double(x: float) -> str:
    """C double literal of ``x``: ``shortest_g`` with ``.0`` when needed."""
    text = shortest_g(x)
    if not any(c in text for c in ".eni"):
        text += ".0"
    return text


_C_ESCAPES = {
    ord('"'): '\\"',
    ord("\\"): "\\\\",
    ord("\n"): "\\n",
    ord("\t"): "\\t",
    ord("\r"): "\\r",
}


def c_string(s: str) -> str:
    """C string literal holding the UTF-8 bytes of ``s``, ASCII only.

    Printable ASCII stays as is, except that a ``?`` following a ``?`` is
    written ``\\?`` (no trigraph can form under -std=c11). Other bytes use
    three-digit octal escapes, which can never swallow a following digit.
    """
    out = ['"']
    prev = 0
    for byte in s.encode("utf-8"):
        if byte in _C_ESCAPES:
            out.append(_C_ESCAPES[byte])
        elif byte == ord("?") and prev == ord("?"):
            out.append("\\?")
        elif 0x20 <= byte < 0x7F:
            out.append(chr(byte))
        else:
            out.append("\\%03o" % byte)
        prev = byte
    out.append('"')
    return "".join(out)


def c_comment(text: str) -> str:
    """``text`` made safe inside a ``/* */`` comment (ASCII, no ``*/`` or ``/*``)."""
    safe = c_string(text)[1:-1]
    return safe.replace("*/", "*\\/").replace("/*", "/\\*")


def json_string(s: str) -> str:
    """JSON string literal, ASCII only (``\\uXXXX`` for the rest)."""
    return json.dumps(s, ensure_ascii=True)


def quote(s: str) -> str:
    """A string as a TOML basic string, for messages.

    ``\\`` and ``"`` are escaped, control characters become ``\\n``, ``\\t``,
    ``\\r``, ``\\b``, ``\\f`` or ``\\uXXXX``; everything else is kept as is.
    """
    out = ['"']
    for ch in s:
        code = ord(ch)
        if ch in '"\\':
            out.append("\\" + ch)
        elif ch in "\n\t\r\b\f":
            out.append(json.dumps(ch)[1:-1])
        elif code < 0x20 or code == 0x7F:
            out.append("\\u%04X" % code)
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def toml_value(value: object, depth: int = 0) -> str:
    """A parsed TOML value written back in TOML-ish form, for messages.

    Booleans ``true``/``false``, integers in decimal, floats as
    ``c_double`` (``2.0``, ``-inf``, ``nan``), strings as ``quote``, tables
    as ``{...}``, arrays in full up to 8 items (then ``, ...``) and 2 levels.
    """
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return c_double(value)
    if isinstance(value, str):
        return quote(value)
    if isinstance(value, dict):
        return "{...}"
    if isinstance(value, list):
        if depth >= _MSG_ARRAY_DEPTH:
            return "[...]"
        items = [toml_value(v, depth + 1) for v in value[:_MSG_ARRAY_ITEMS]]
        if len(value) > _MSG_ARRAY_ITEMS:
            items.append("...")
        return "[" + ", ".join(items) + "]"
    if isinstance(value, (datetime.datetime, datetime.date, datetime.time)):
        return value.isoformat()
    return repr(value)  # pragma: no cover - tomllib yields nothing else
