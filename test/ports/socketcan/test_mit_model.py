# SPDX-License-Identifier: Apache-2.0
"""The MIT-mode model itself (mit_model.py): the byte layout against the
protocol's description, exact round trips, the quantisation table of
roz/port/mit_codec.h, and the committed vector table being the model's."""

import math
import os
import re
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
sys.path.insert(0, HERE)

import mit_model as mm  # noqa: E402


def test_layout_matches_the_description():
    # p[15:8] p[7:0] v[11:4] v[3:0]|kp[11:8] kp[7:0] kd[11:4] kd[3:0]|t[11:8] t[7:0]
    codes = {"position": 0x1234, "velocity": 0xABC, "kp": 0xDEF, "kd": 0x135, "torque": 0x79B}
    frame, what = mm.lay_out(codes)
    assert frame == bytes([0x12, 0x34, 0xAB, 0xCD, 0xEF, 0x13, 0x57, 0x9B])
    assert what == 0


def test_reply_fields():
    r = mm.RANGE_SETS[0]
    rc, ident, p, v, t, *_ = mm.unpack(r, "basic", bytes([0x05, 0x80, 0x01, 0x7F, 0xF8, 0x00]))
    assert (rc, ident, p, v, t) == (0, 5, 0x8001, 0x7FF, 0x800)
    assert mm.unpack(r, "temperature_error", bytes(7))[0] == mm.EINVAL
    full = mm.unpack(r, "temperature_error", bytes([1, 0, 0, 0, 0, 0, 40, 3]))
    assert full[-2:] == (40, 3)


def test_special_frames_are_avoided():
    top = {f: mm.top(w) for f, w in mm.WIDTHS.items()}
    for t in (0xFFC, 0xFFD, 0xFFE):
        frame, what = mm.lay_out(dict(top, torque=t))
        assert mm.special_of(frame) == 0 and what == mm.AVOIDED_SPECIAL
        assert frame[-1] == 0xFB
    frame, what = mm.lay_out(dict(top, torque=0xFFF))
    assert frame == b"\xff" * 8 and what == 0 and mm.special_of(frame) == 0


@pytest.mark.parametrize("lo,hi", [(-12.5, 12.5), (0.0, 500.0), (-5.0, -1.0), (0.0, 1e-3)])
def test_round_trip_of_every_code(lo, hi):
    for bits in list(range(1, 13)) + [16]:
        if bits == 16 and lo != -12.5:
            continue  # 2^16 exact divisions once is enough
        for code in range(mm.top(bits) + 1):
            assert mm.encode(mm.decode(code, lo, hi, bits), lo, hi, bits) == (code, 0)
        assert mm.decode(0, lo, hi, bits) == lo
        assert mm.decode(mm.top(bits), lo, hi, bits) == hi


def test_encoding_is_within_half_a_step():
    import random
    rng = random.Random(1)
    for lo, hi in ((-12.5, 12.5), (-22.5, 10.0), (0.0, 5.0)):
        for bits in (12, 16):
            step = (hi - lo) / mm.top(bits)
            for _ in range(2000):
                x = rng.uniform(lo, hi)
                code, what = mm.encode(x, lo, hi, bits)
                assert what == 0
                assert abs(mm.decode(code, lo, hi, bits) - x) <= step / 2 * (1 + 1e-12)


def test_saturation_and_non_finite():
    assert mm.encode(12.6, -12.5, 12.5, 16) == (0xFFFF, mm.SATURATED)
    assert mm.encode(-12.6, -12.5, 12.5, 16) == (0, mm.SATURATED)
    assert mm.encode(math.nan, -12.5, 12.5, 16) == (0x8000, mm.NONFINITE)  # 0, half up
    assert mm.encode(math.inf, 10.0, 20.0, 12) == (0, mm.NONFINITE)  # nearest 0 is min
    assert mm.encode(-math.inf, -5.0, -1.0, 12) == (4095, mm.NONFINITE)  # nearest 0 is max
    r = mm.RANGE_SETS[0]
    frame, what = mm.pack(r, {"position": math.nan, "velocity": 0.0, "kp": 500.0, "kd": 5.0,
                              "torque": 0.0})
    assert what == mm.NONFINITE_BIT["position"]
    assert (frame[3] & 0x0F, frame[4]) == (0, 0)  # kp code 0


def test_documented_quantisation_table():
    """The table in docs/ports/socketcan.md says what the model computes."""
    page = os.path.join(ROOT, "docs", "ports", "socketcan.md")
    rows = re.findall(r"^\| (\S+?)(?: \S+)?\s+\| (\d+)\s+\| (\S+)\s.*?\| (\S+?)(?: \S+)?\s*\|$",
                      open(page, encoding="utf-8").read(), re.M)
    rows = [r for r in rows if r[0] != "byte"]
    assert len(rows) == 5
    for span, bits, step, half in rows:
        if span.startswith("±"):
            lo, hi = -float(span[1:]), float(span[1:])
        else:
            lo, hi = map(float, span.split(".."))
        want = (hi - lo) / mm.top(int(bits))
        assert float(step) == pytest.approx(want, rel=5e-3), span
        assert float(half) == pytest.approx(want / 2, rel=5e-3), span


def test_vector_table_is_the_models():
    with open(os.path.join(HERE, "mit_vectors.txt"), encoding="ascii") as f:
        assert f.read() == "\n".join(mm.vectors()) + "\n", \
            "stale: python test/ports/socketcan/mit_model.py --write test/ports/socketcan/mit_vectors.txt"
