# SPDX-License-Identifier: Apache-2.0
"""bench/targets: the instruction counter (qemu_count.py) on an aarch64
program whose every instruction is known, under qemu-aarch64 (exact: the
tolerance is zero), its parsing of QEMU's lines for the three ISAs, and
the table bench/report.py renders from the bench's JSON lines."""

import argparse
import importlib.util
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench" / "targets"))
import qemu_count  # noqa: E402

spec = importlib.util.spec_from_file_location("roz_bench_report_t", ROOT / "bench" / "report.py")
report = importlib.util.module_from_spec(spec)
spec.loader.exec_module(report)

CC = shutil.which("aarch64-linux-gnu-gcc")
QEMU = shutil.which("qemu-aarch64")


@pytest.fixture(scope="module")
def ticks_program(tmp_path_factory):
    if CC is None or QEMU is None:
        pytest.skip("no aarch64-linux-gnu-gcc or qemu-aarch64 (tools/setup.sh installs them)")
    exe = tmp_path_factory.mktemp("ticks") / "ticks"
    subprocess.run([CC, "-o", str(exe), str(Path(__file__).with_name("ticks_aarch64.S"))],
                   check=True)
    return exe


def test_counts_every_part_of_a_known_program(ticks_program):
    c, _ = qemu_count.count([QEMU, "-d", "in_asm,exec,nochain", "-L", "/", str(ticks_program)],
                            {"part_a": "a", "part_b": "b", "inner": "inner", "tick": "runtime"},
                            "tick", 2, 10)
    res = qemu_count.summarise(c, 2, 10, ["a", "b", "inner", "runtime"])
    got = {p: (v["min"], v["max"]) for p, v in res["parts"].items()}
    # tolerance 0: every tick runs the same instructions
    assert got == {"tick": (219, 219), "a": (205, 205), "b": (4, 4), "inner": (3, 3),
                   "runtime": (7, 7)}
    assert res["entered"] == ["inner", "part_a", "part_b", "tick"]


def test_the_program_stops_once_the_ticks_are_counted(ticks_program):
    c, _ = qemu_count.count([QEMU, "-d", "in_asm,exec,nochain", "-L", "/", str(ticks_program)],
                            {"tick": "runtime"}, "tick", 0, 5)
    assert len(c.ticks) == 5
    with pytest.raises(SystemExit, match="50 ticks ran, 60 wanted"):
        c, _ = qemu_count.count([QEMU, "-d", "in_asm,exec,nochain", "-L", "/",
                                 str(ticks_program)], {"tick": "runtime"}, "tick", 10, 50)
        qemu_count.summarise(c, 10, 50, ["runtime"])


@pytest.mark.parametrize("line,want", [
    ("0x5500000754:  97fffff0  bl       #0x5500000714", (0x5500000754, 4, "bl")),
    ("0x4000001139:  48 85 ff                 testq    %rdi, %rdi", (0x4000001139, 3, "testq")),
    ("0x4000001150:  e8 12 34 56 78           callq    0x40000100", (0x4000001150, 5, "callq")),
    ("0x00001234:  f000 f800  bl       #0x1238", (0x1234, 4, "bl")),
    ("0x00001238:  4798      blx      r3", (0x1238, 2, "blx")),
    ("0x0000123a:  add3      adds     r3, r2, r3", (0x123a, 2, "adds")),
    ("IN: main", None),
])
def test_reads_the_instruction_lines_of_each_isa(line, want):
    assert qemu_count.parse_insn(line) == want


def fixture_rows():
    def parts(tick, process, filt, port, clock=0, pmax=None):
        runtime = tick - process - filt - port - clock
        d = {"tick": tick, "process": process, "filter": filt, "port": port, "clock": clock,
             "runtime": runtime}
        out = {k: {"mean": float(v), "min": v, "max": v} for k, v in d.items()}
        if pmax:
            out["process"]["max"] = pmax
            out["tick"]["max"] = pmax + (tick - process)
        return out
    return [
        {"controller": "ur5_sine", "target": "x86-64", "ticks": 100,
         "parts": parts(12000, 5000, 3000, 2000)},
        {"controller": "ur5_sine", "target": "m4f", "ticks": 100,
         "parts": parts(56000, 26000, 21000, 7000, 600)},
        {"controller": "ur5_sine", "target": "m7",
         "skipped": "no image of this controller for this board (examples/firmware)"},
        {"controller": "g1_policy", "target": "aarch64", "ticks": 100,
         "parts": parts(90000, 80000, 3000, 4000, pmax=750000)},
        {"controller": "g1_policy", "target": "m7",
         "skipped": "no image of this controller for this board (examples/firmware)"},
    ]


def test_the_table_has_targets_as_columns_and_parts_as_rows():
    text = report.targets_table(fixture_rows())
    lines = text.splitlines()
    assert lines[0] == ("| instructions per tick | x86-64 | aarch64 | Cortex-M4F | Cortex-M7 "
                        "| Cortex-M33 |")
    rows = {}
    group = None
    for line in lines[2:]:
        if not line.startswith("|"):
            continue
        cells = [c.strip() for c in line.strip("|").split("|")]
        if cells[0].startswith("**"):
            group = cells[0].strip("*")
            continue
        rows[(group, cells[0])] = cells[1:]
    assert rows[("UR5, sine", "whole tick")] == ["12,000", "-", "56,000", "-", "-"]
    assert rows[("UR5, sine", "safety filter")] == ["3,000", "-", "21,000", "-", "-"]
    assert rows[("UR5, sine", "runtime's own work")] == ["2,000", "-", "1,400", "-", "-"]
    assert rows[("UR5, sine", "the board's clock reads")] == ["0", "-", "600", "-", "-"]
    assert rows[("G1 learned policy", "inference tick: `process()`")] == [
        "-", "750,000", "-", "-", "-"]
    assert ("G1 PD", "whole tick") not in rows  # no row of it: no table group
    assert ("UR5, sine", "inference tick: `process()`") not in rows
    assert ("Not run: UR5, sine on Cortex-M7, G1 learned policy on Cortex-M7: no image of this "
            "controller for this board (examples/firmware).") in text


def test_the_section_renders_from_the_json_alone(tmp_path):
    (tmp_path / "targets.jsonl").write_text(
        "".join(json.dumps(r) + "\n" for r in fixture_rows()), encoding="utf-8")
    args = argparse.Namespace(dir=tmp_path, root=tmp_path, command="make bench",
                              machine_note="", binary=None)
    doc, _ = report.build(args)
    sec = doc[doc.index("## 11. The tick on every target"):]
    assert "| **UR5, sine** |" in sec and "How each column was counted" in sec


def test_no_json_says_why(tmp_path):
    (tmp_path / "targets.skipped").write_text("no qemu-aarch64\n", encoding="utf-8")
    args = argparse.Namespace(dir=tmp_path, root=tmp_path, command="make bench",
                              machine_note="", binary=None)
    doc, _ = report.build(args)
    assert "## 11. The tick on every target, in instructions\n\nNot run: no qemu-aarch64." in doc


def block(name, ptr, insns):
    """QEMU's in_asm lines of one block, then its execution's line."""
    pc = insns[0][0]
    lines = ["----------------", f"IN: {name}"]
    lines += [f"0x{a:08x}:  {enc}  {asm}" for a, enc, asm in insns]
    return lines + ["", trace(name, ptr, pc)]


def trace(name, ptr, pc):
    return f"Trace 0: {ptr:#x} [00000000/{pc:08x}/00000150/ff020200] {name}"


def test_an_inlined_tick_a_tail_call_and_a_rewound_block():
    # Thumb, as a Cortex-M image under -icount: the tick's code inlined in
    # app at 0x110..0x117; it calls now() (blx), which jumps to the tracked
    # clock (bx: a tail call); the clock's first block is rewound at its
    # second load (an I/O access) and run again from there.
    log = block("main", 0x1000, [(0x80, "f000 f800", "bl #0x100")])
    first = {
        "loop": [(0x120, "e7f6", "b #0x110")],
        "t1": [(0x110, "2001", "movs r0, #1"), (0x112, "4798", "blx r3")],
        "now": [(0x200, "b508", "push {r3, lr}"), (0x202, "4718", "bx r3")],
        "clk": [(0x300, "6810", "ldr r0, [r2]"), (0x302, "6811", "ldr r1, [r2]"),
                (0x304, "4770", "bx lr")],
        "clk2": [(0x302, "6811", "ldr r1, [r2]"), (0x304, "4770", "bx lr")],
        "t2": [(0x114, "1c40", "adds r0, r0, #1"), (0x116, "1c40", "adds r0, r0, #1"),
               (0x118, "e002", "b #0x120")],
    }
    names = {"loop": "app", "t1": "app", "now": "now", "clk": "clk", "clk2": "clk", "t2": "app"}
    ptrs = {k: 0x2000 + 0x100 * i for i, k in enumerate(first)}
    for rnd in range(4):
        for k in ("loop", "t1", "now", "clk", "clk2", "t2"):
            if k == "clk2":
                log.append("cpu_io_recompile: rewound execution of TB to 00000302")
            if rnd == 0:
                log += block(names[k], ptrs[k], first[k])
            else:
                log.append(trace(names[k], ptrs[k], first[k][0][0]))
    log += block("app", 0x9000, [(0x120, "e7f6", "b #0x110")])
    c = qemu_count.Counter({"clk": "clock", "tick": "runtime"}, "tick",
                           ("app", {0x110, 0x112, 0x114, 0x116}))
    assert qemu_count.feed(c, iter(log), 4)
    res = qemu_count.summarise(c, 1, 3, ["clock", "runtime"])
    got = {p: (v["min"], v["max"]) for p, v in res["parts"].items()}
    # runtime: the tick's own 2 + 2 in app and now()'s 2; the clock's 3 run
    # (1 of the rewound block, then 2)
    assert got == {"tick": (9, 9), "clock": (3, 3), "runtime": (6, 6)}
