# SPDX-License-Identifier: Apache-2.0
"""bench/report.py: the table of every engine side by side (section 2), from
the JSON lines bench/aot writes and the JSON the peer harnesses write, in
the formats bench/common/bench_json.h and bench/peers/common print."""

import argparse
import importlib.util
import json
from pathlib import Path

REPORT = Path(__file__).resolve().parents[2] / "bench" / "report.py"
spec = importlib.util.spec_from_file_location("roz_bench_report", REPORT)
report = importlib.util.module_from_spec(spec)
spec.loader.exec_module(report)

WORK = ("G1 PD", "G1 PD (bulk)", "G1 policy (nn)")


def timing(name, p50):
    return {"name": name, "unit": "us", "p50": p50, "p99": 2 * p50, "max": 4 * p50}


def write_aot(d: Path, scale=1.0):
    rows = []
    for k, work in enumerate(WORK):
        native = (k + 1) * 1.0
        rows += [timing(f"{work}: process(), native", native),
                 timing(f"{work}: process(), ahead of time", 1.25 * native * scale),
                 timing(f"{work}: process(), wasm3", 4.0 * native),
                 {"name": f"{work}: fuel per call", "value": 100.0, "unit": "units"},
                 {"name": f"{work}: targets differing", "value": 0.0, "unit": "values"}]
    (d / "aot.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows), encoding="utf-8")


def write_peer(d: Path, engine, version, factor):
    figs = [timing("process, metering off", 1.0 * factor),
            timing("process, metering fuel", 2.0 * factor),
            timing("process, bulk, metering fuel", 4.0 * factor),
            timing("process, nn policy, metering fuel", 6.0 * factor)]
    doc = {"engine": engine, "version": version, "figures": figs, "checked": "equal"}
    (d / f"peer-{engine}.json").write_text(json.dumps(doc), encoding="utf-8")


def build(d: Path) -> str:
    args = argparse.Namespace(dir=d, root=d, command="make bench", machine_note="", binary=None)
    doc, _ = report.build(args)
    return doc


def summary_rows(doc: str) -> dict:
    start = doc.index("**Every engine side by side**")
    rows = {}
    for line in doc[start:].splitlines()[2:]:
        if not line.startswith("|"):
            if rows:
                break
            continue
        cells = [c.strip() for c in line.strip("|").split("|")]
        rows[cells[0]] = cells[1:]
    return rows


def test_every_engine_beside_native(tmp_path):
    write_aot(tmp_path)
    write_peer(tmp_path, "roz", "0.5.0", 9.0)  # roz's own harness: not in this table
    write_peer(tmp_path, "wasmtime", "48.0.8", 1.0)
    write_peer(tmp_path, "wasmi", "2.0.0", 3.0)
    rows = summary_rows(build(tmp_path))
    assert rows["engine"] == ["G1 PD", "the bulk PD", "the nn policy"]
    assert rows["native C (reference)"] == ["1.00 (1.00x)", "2.00 (1.00x)", "3.00 (1.00x)"]
    assert rows["roz, ahead of time (rozaot + wasm2c)"] == ["1.25 (1.25x)", "2.50 (1.25x)",
                                                          "3.75 (1.25x)"]
    assert rows["roz, wasm3"] == ["4.00 (4.00x)", "8.00 (4.00x)", "12.0 (4.00x)"]
    # the peers' fuel-metered figures, against bench/aot's native ones
    assert rows["wasmtime 48.0.8"] == ["2.00 (2.00x)", "4.00 (2.00x)", "6.00 (2.00x)"]
    assert rows["wasmi 2.0.0"] == ["6.00 (6.00x)", "12.0 (6.00x)", "18.0 (6.00x)"]


def test_a_missing_engine_is_a_dash(tmp_path):
    write_aot(tmp_path)
    write_peer(tmp_path, "roz", "0.5.0", 9.0)
    write_peer(tmp_path, "wasmtime", "48.0.8", 1.0)
    rows = summary_rows(build(tmp_path))
    assert rows["wasmi"] == ["-", "-", "-"]
    assert rows["wasmtime 48.0.8"][0] == "2.00 (2.00x)"


def test_neither_bench_ran(tmp_path):
    doc = build(tmp_path)
    assert "Not measured (neither bench/aot nor bench/peers ran)" in doc


def test_the_headline_has_the_ahead_of_time_rows(tmp_path):
    write_aot(tmp_path, scale=1.2)
    _, headline = report.build(argparse.Namespace(dir=tmp_path, root=tmp_path, command="x",
                                                  machine_note="", binary=None))
    assert "| G1 PD `process()`, ahead of time | 1.50 us |" in headline
    assert "| G1 PD `process()` (bulk), ahead of time | 3.00 us |" in headline


# make firmware's output as tools/fw_run.sh prints it (two images, shortened)
FIRMWARE_TXT = """\
ninja: no work to do.
PYTHON=.venv/bin/python tools/fw_run.sh mps2-an500 build-fw-m7/roz_fw_g1_pd.elf 128 160 "G1"

==== Unitree G1, PD controller, Cortex-M7 (mps2-an500)
roz firmware: unitree_g1 on cortex-m7 (mps2-an500), controller g1_pd.wasm (601 bytes), 1000 ticks
cost: instructions per tick, emulation estimates (QEMU -icount shift=0)
cost: tick         mean  65903 max  74600
cost: process()    mean  28900 max  28920
result: as expected

footprint: Unitree G1, PD controller, Cortex-M7 (mps2-an500)
  component         flash KB  static RAM KB
  wasm3                 50.2            0.2
  total                139.3           74.8
  RAM all told         168.8 KB (static + reserved heap and stack; 159.9 KB used at most)
  aim: flash <= 128 KB: NOT met
  aim: RAM <= 160 KB: NOT met

==== Unitree G1, PD controller compiled ahead of time (no wasm3), Cortex-M7 (mps2-an500)
cost: tick         mean  44100 max  52000
cost: process()    mean   7050 max   7100
footprint: Unitree G1, PD controller compiled ahead of time (no wasm3), Cortex-M7 (mps2-an500)
  total                 63.4           86.0
  RAM all told         151.1 KB (static + reserved heap and stack; 140.2 KB used at most)
  aim: flash <= 128 KB: met
  aim: RAM <= 160 KB: met
"""


def test_firmware_images_at_a_glance(tmp_path):
    (tmp_path / "firmware.txt").write_text(FIRMWARE_TXT, encoding="utf-8")
    doc = build(tmp_path)
    assert ("| Unitree G1, PD controller, Cortex-M7 (mps2-an500) | 139.3 | 128 KB, NOT met | "
            "168.8 | 160 KB, NOT met | 65,903 | 28,900 |") in doc
    assert ("| Unitree G1, PD controller compiled ahead of time (no wasm3), Cortex-M7 "
            "(mps2-an500) | 63.4 | 128 KB, met | 151.1 | 160 KB, met | 44,100 | 7,050 |") in doc
    # the reports themselves follow, without the build's lines
    assert "cost: process()    mean   7050 max   7100" in doc
    assert "ninja: no work to do." not in doc


def test_no_firmware_no_glance():
    assert report.firmware_summary("make: nothing\n") == ""


def test_refresh_replaces_the_firmware_section_alone(tmp_path, monkeypatch):
    # the existing report: every section marked, its firmware at 139.3 KB NOT met
    old_dir, new_dir = tmp_path / "old", tmp_path / "new"
    old_dir.mkdir()
    new_dir.mkdir()
    (old_dir / "firmware.txt").write_text(FIRMWARE_TXT, encoding="utf-8")
    parts = report.split_sections(build(old_dir))
    old = "".join(p + f"kept {k}\n" for k, p in enumerate(parts))
    out = tmp_path / "BENCHMARKS.md"
    out.write_text(old, encoding="utf-8")
    # the new results: make firmware's and make firmware-options' alone
    (new_dir / "firmware.txt").write_text(
        FIRMWARE_TXT.replace("  total                139.3", "  total                127.1")
        .replace("aim: flash <= 128 KB: NOT met", "aim: flash <= 128 KB: met"), encoding="utf-8")
    (new_dir / "firmware_options.md").write_text("| option | saves |\n|---|---:|\n| x | 1 |\n",
                                                 encoding="utf-8")
    argv = ["report.py", "--dir", str(new_dir), "--out", str(out), "--root", str(tmp_path),
            "--refresh", "--command", "make bench-firmware"]
    monkeypatch.setattr("sys.argv", argv)
    assert report.main() == 0
    assert report.main() == 0  # twice: the header notes the latest refresh once
    got = report.split_sections(out.read_text(encoding="utf-8"))
    assert len(got) == len(parts)
    for k, (was, now) in enumerate(zip(parts, got)):
        if k == 0:
            continue
        if report.section_number(was) == "6":
            assert now.startswith("## 6. Firmware\n")
            assert f"kept {k}" not in now and "139.3 | 128 KB, NOT met" not in now
            assert "| Unitree G1, PD controller, Cortex-M7 (mps2-an500) | 127.1 | 128 KB, met |" in now
            assert "| x | 1 |" in now
        else:
            assert now == was + f"kept {k}\n"
    header = got[0]
    assert header != parts[0] + "kept 0\n"  # the Commit and Command lines changed
    assert header.count("its section 6 from make bench-firmware at unknown, ") == 1
    assert header.count("; section 6: unknown") == 1
    assert header.endswith("kept 0\n")


def test_refresh_needs_results_of_a_section(tmp_path, monkeypatch):
    out = tmp_path / "BENCHMARKS.md"
    out.write_text(build(tmp_path), encoding="utf-8")
    (tmp_path / "tick.jsonl").write_text("", encoding="utf-8")  # section 1: a whole make bench
    monkeypatch.setattr("sys.argv", ["report.py", "--dir", str(tmp_path), "--out", str(out),
                                     "--root", str(tmp_path), "--refresh"])
    before = out.read_text(encoding="utf-8")
    assert report.main() == 1
    assert out.read_text(encoding="utf-8") == before
