# SPDX-License-Identifier: Apache-2.0
"""An independent model of the MIT-mode CAN frames, and the test vectors
the C codec (ports/socketcan/src/mit_codec.c) is checked against.

Written from the protocol's description (roz/port/mit_codec.h repeats it), not
from the C code: values are mapped with exact rational arithmetic
(fractions.Fraction), fields are laid out one bit at a time.

    python mit_model.py --write mit_vectors.txt   # regenerate the table
    python mit_model.py --check mit_vectors.txt   # exit 1 if it is stale

The table, one vector a line:

    encode BITS MIN MAX X -> CODE WHAT
    decode BITS MIN MAX CODE -> VALUE
    ranges NAME PMIN PMAX VMIN VMAX KPMIN KPMAX KDMIN KDMAX TMIN TMAX
    pack   NAME P V KP KD T -> BYTES WHAT
    unpack LAYOUT NAME BYTES -> RC ID PCODE VCODE TCODE P V T TEMP ERROR
    special BYTES -> WHICH

A ranges line names an actuator's ten range ends for the lines after it.
Doubles are written as Python's repr() (the shortest text that reads back
as the same double; C's strtod reads it back exactly), BYTES in hex ("-"
for none). WHAT is the report: for encode 0, 1 (saturated) or 2 (not finite);
for pack the ROZ_MIT_* bits. A decoded VALUE is the exact value rounded
once to a double; the C code may round more than once, so the C test takes
VALUE within 1e-12 of the range's size, and exactly at the two ends.
Encodings whose exact value lies within 1e-9 of a rounding tie are left
out unless double arithmetic reaches the tie exactly (then the C code must
round it up, as the model does).
"""

import argparse
import math
import random
import sys
from fractions import Fraction

# field widths, in frame order
WIDTHS = {"position": 16, "velocity": 12, "kp": 12, "kd": 12, "torque": 12}
FIELDS = tuple(WIDTHS)

SATURATED, NONFINITE = 1, 2
SAT_BIT = {f: 1 << i for i, f in enumerate(FIELDS)}
NONFINITE_BIT = {f: 1 << (5 + i) for i, f in enumerate(FIELDS)}
AVOIDED_SPECIAL = 1 << 10

ENTER, EXIT, ZERO = 0xFC, 0xFD, 0xFE
LAYOUTS = {"basic": 6, "temperature_error": 8}
EINVAL = -1


# ---- the model ---------------------------------------------------------------

def top(bits: int) -> int:
    return (1 << bits) - 1


def exact_position(x: float, lo: float, hi: float, bits: int) -> Fraction:
    """Where x falls on the code scale, exactly."""
    return (Fraction(x) - Fraction(lo)) * top(bits) / (Fraction(hi) - Fraction(lo))


def encode(x: float, lo: float, hi: float, bits: int) -> tuple[int, int]:
    """(code, what): round half up; saturate; non-finite -> nearest 0."""
    if not math.isfinite(x):
        safe = min(max(0.0, lo), hi)
        return encode(safe, lo, hi, bits)[0], NONFINITE
    if x > hi:
        return top(bits), SATURATED
    if x < lo:
        return 0, SATURATED
    q = exact_position(x, lo, hi, bits)
    return min(math.floor(q + Fraction(1, 2)), top(bits)), 0


def decode(code: int, lo: float, hi: float, bits: int) -> float:
    """The exact value of a code, rounded once to a double."""
    code &= top(bits)
    return float(Fraction(lo) + code * (Fraction(hi) - Fraction(lo)) / top(bits))


def put_bits(bits_out: list[int], value: int, width: int) -> None:
    for i in range(width - 1, -1, -1):
        bits_out.append((value >> i) & 1)


def to_bytes(bits_in: list[int]) -> bytes:
    assert len(bits_in) % 8 == 0
    return bytes(int("".join(map(str, bits_in[i:i + 8])), 2) for i in range(0, len(bits_in), 8))


def take(bits_in: list[int], start: int, width: int) -> int:
    return int("".join(map(str, bits_in[start:start + width])), 2)


def lay_out(codes: dict) -> tuple[bytes, int]:
    """The frame of five codes, and AVOIDED_SPECIAL when the torque code moved."""
    what = 0
    t = codes["torque"]
    if all(codes[f] == top(WIDTHS[f]) for f in FIELDS[:4]) and 0xFFC <= t <= 0xFFE:
        t, what = 0xFFB, AVOIDED_SPECIAL
    bits_out: list[int] = []
    for f in FIELDS:
        put_bits(bits_out, t if f == "torque" else codes[f], WIDTHS[f])
    return to_bytes(bits_out), what


def pack(ranges: dict, command: dict) -> tuple[bytes, int]:
    codes, what = {}, 0
    for f in FIELDS:
        codes[f], w = encode(command[f], *ranges[f], WIDTHS[f])
        what |= (SAT_BIT[f] if w == SATURATED else 0) | (NONFINITE_BIT[f] if w == NONFINITE else 0)
    if what & NONFINITE_BIT["position"]:
        codes["kp"] = 0
    if what & NONFINITE_BIT["velocity"]:
        codes["kd"] = 0
    frame, avoided = lay_out(codes)
    return frame, what | avoided


def unpack(ranges: dict, layout: str, data: bytes):
    """(rc, id, pcode, vcode, tcode, p, v, t, temperature, error)."""
    if len(data) < LAYOUTS[layout]:
        return (EINVAL,) + (0,) * 9
    bits_in: list[int] = []
    for b in data:
        put_bits(bits_in, b, 8)
    pcode, vcode, tcode = take(bits_in, 8, 16), take(bits_in, 24, 12), take(bits_in, 36, 12)
    temperature = error = 0
    if layout == "temperature_error":
        temperature, error = data[6], data[7]
    return (0, data[0], pcode, vcode, tcode,
            decode(pcode, *ranges["position"], 16), decode(vcode, *ranges["velocity"], 12),
            decode(tcode, *ranges["torque"], 12), temperature, error)


def special_of(data: bytes) -> int:
    if len(data) == 8 and data[:7] == b"\xff" * 7 and data[7] in (ENTER, EXIT, ZERO):
        return data[7]
    return 0


# ---- vectors -----------------------------------------------------------------

RANGE_SETS = (
    # a common quasi-direct-drive firmware
    {"position": (-12.5, 12.5), "velocity": (-45.0, 45.0), "kp": (0.0, 500.0),
     "kd": (0.0, 5.0), "torque": (-18.0, 18.0)},
    # another firmware's wider speed and torque
    {"position": (-12.5, 12.5), "velocity": (-65.0, 65.0), "kp": (0.0, 500.0),
     "kd": (0.0, 5.0), "torque": (-65.0, 65.0)},
    # asymmetric; gains that cannot be 0; a torque range below 0
    {"position": (-1.0, 3.0), "velocity": (-22.5, 10.0), "kp": (10.0, 20.0),
     "kd": (0.5, 1.5), "torque": (-5.0, -1.0)},
    # tiny and huge
    {"position": (0.0, 1e-3), "velocity": (-1e6, 1e6), "kp": (0.0, 0.1),
     "kd": (0.0, 1e-9), "torque": (-0.3, 0.7)},
)


def tie_is_unsafe(x: float, lo: float, hi: float, bits: int) -> bool:
    """Near a rounding tie that double arithmetic may not reach exactly."""
    if not math.isfinite(x):
        x = min(max(0.0, lo), hi)  # what it is sent as
    if not lo <= x <= hi:
        return False
    q = exact_position(x, lo, hi, bits)
    frac = q - math.floor(q)
    if abs(frac - Fraction(1, 2)) > Fraction(1, 10**9):
        return False
    # the C code computes (x - min) * top / (max - min) in doubles
    t = (x - lo) * float(top(bits)) / (hi - lo)
    return Fraction(t) != q


def candidates(lo: float, hi: float, bits: int, rng: random.Random) -> list[float]:
    step = (hi - lo) / top(bits)
    mid = lo + (hi - lo) / 2
    xs = [lo, hi, math.nextafter(lo, -math.inf), math.nextafter(hi, math.inf),
          lo - abs(lo) - 1.0, hi + abs(hi) + 1.0, mid, math.nextafter(mid, -math.inf),
          math.nextafter(mid, math.inf), lo + step, hi - step, lo + 0.5 * step,
          hi - 0.5 * step, lo + 0.49999 * step, lo + 0.50001 * step, 0.0, -0.0,
          math.nan, math.inf, -math.inf]
    xs += [rng.uniform(lo, hi) for _ in range(4)]
    xs += [lo + rng.randrange(top(bits) + 1) * step for _ in range(2)]
    return [x for x in xs if not tie_is_unsafe(x, lo, hi, bits)]


def num(x: float) -> str:
    return repr(float(x))


def ranges_line(name: str, r: dict) -> str:
    return f"ranges {name} " + " ".join(f"{num(r[f][0])} {num(r[f][1])}" for f in FIELDS)


def vectors() -> list[str]:
    rng = random.Random(15)
    out = ["# MIT-mode codec vectors, generated by test/ports/socketcan/mit_model.py; do not edit.",
           "# Format: see mit_model.py."]

    # every width, a few ranges: encode at and beyond the ends, and inside
    for bits in range(1, 17):
        more = ((0.0, 500.0), (-1.0, 3.0), (0.0, 1e-3)) if bits in (12, 16) else ()
        for lo, hi in ((-12.5, 12.5), (-5.0, -1.0)) + more:
            for x in candidates(lo, hi, bits, rng):
                code, what = encode(x, lo, hi, bits)
                out.append(f"encode {bits} {num(lo)} {num(hi)} {num(x)} -> {code} {what}")
            codes = {0, 1, top(bits) // 2, top(bits) // 2 + 1, top(bits) - 1, top(bits)}
            codes |= {rng.randrange(top(bits) + 1) for _ in range(4)}
            for code in sorted(c for c in codes if 0 <= c <= top(bits)):
                out.append(f"decode {bits} {num(lo)} {num(hi)} {code} -> "
                           f"{num(decode(code, lo, hi, bits))}")

    # whole commands
    for k, r in enumerate(RANGE_SETS):
        out.append(ranges_line(f"R{k}", r))
        per_field = {f: candidates(*r[f], WIDTHS[f], rng) for f in FIELDS}
        combos = []
        for f in FIELDS:  # each candidate of each field once, the others random
            for x in per_field[f]:
                c = {g: rng.choice(per_field[g]) for g in FIELDS}
                c[f] = x
                combos.append(c)
        combos += [{f: rng.choice(per_field[f]) for f in FIELDS} for _ in range(10)]
        # every field at the top, torque around the codes of the special frames
        t_lo, t_hi = r["torque"]
        for code in range(0xFF9, 0x1000):
            t = decode(code, t_lo, t_hi, 12)
            combos.append({"position": r["position"][1], "velocity": r["velocity"][1],
                           "kp": r["kp"][1], "kd": r["kd"][1], "torque": t})
        for c in combos:
            frame, what = pack(r, c)
            values = " ".join(num(c[f]) for f in FIELDS)
            out.append(f"pack R{k} {values} -> {frame.hex()} {what}")

    # replies: random frames of every length, both layouts
    for k, r in enumerate(RANGE_SETS):
        out.append(ranges_line(f"R{k}", r))
        for layout in LAYOUTS:
            for n in range(0, 9):
                for _ in range(6 if n >= 6 else 1):
                    data = bytes(rng.randrange(256) for _ in range(n))
                    fields = unpack(r, layout, data)
                    text = " ".join(num(v) if isinstance(v, float) else str(v) for v in fields)
                    out.append(f"unpack {layout} R{k} {data.hex() or '-'} -> {text}")
            for data in (bytes(8), b"\xff" * 8, bytes([0x7f, 0xff, 0xff, 0xff, 0xff, 0xff, 0, 0])):
                fields = unpack(r, layout, data)
                text = " ".join(num(v) if isinstance(v, float) else str(v) for v in fields)
                out.append(f"unpack {layout} R{k} {data.hex()} -> {text}")

    # special frames and near misses
    specials = [b"\xff" * 7 + bytes([k]) for k in range(0xF8, 0x100)]
    specials += [b"\xff" * 6 + b"\xfe\xfc", b"\xff" * 7, b"\xff" * 8 + b"\xfc", bytes(8),
                 b"\x7f" + b"\xff" * 6 + b"\xfd"]
    for data in specials:
        out.append(f"special {data.hex()} -> {special_of(data)}")
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--write", metavar="FILE")
    group.add_argument("--check", metavar="FILE")
    args = parser.parse_args()
    text = "\n".join(vectors()) + "\n"
    if args.write:
        with open(args.write, "w", encoding="ascii") as f:
            f.write(text)
        return 0
    with open(args.check, encoding="ascii") as f:
        if f.read() != text:
            print(f"{args.check} is stale: run mit_model.py --write {args.check}", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
