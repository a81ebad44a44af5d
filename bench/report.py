# SPDX-License-Identifier: Apache-2.0
"""bench/report.py: BENCHMARKS.md from the benches' machine-readable output.

    report.py --dir DIR --out BENCHMARKS.md [--command CMD] [--binary NAME=PATH ...]
    report.py --dir DIR --out BENCHMARKS.md --refresh --command CMD

DIR holds what `make bench` collected: JSON lines from the C benches and
bench_toml.py (one object per figure, bench/common/bench_json.h), and one
JSON object per peer harness (peer-*.json: roz's wasm3, wasmtime, wasmi).
Each figure is printed with p50/p99/max and its ratio to the reference it
is compared with, measured in the same run. A bench whose output is
missing is reported as not run, with the reason make bench left in DIR
(<name>.skipped). --binary gives an executable whose size (text + data,
as binutils' size reports it) goes into the peers' table. The headline
table (the figures users compare roz with) is the first section of
BENCHMARKS.md; no other file is written, README.md links to this one.
With --refresh, only the sections whose results DIR holds (SECTION_INPUTS)
replace theirs in the existing BENCHMARKS.md (make bench-firmware: section
6), and its banner says which command, commit and date they come from.
Prints, never fails on a time.
"""

import argparse
import datetime
import json
import os
import platform
import re
import subprocess
import sys
from pathlib import Path

# ---- input ---------------------------------------------------------------------


def read_lines(path: Path) -> dict:
    """JSON lines of one bench: name -> figure."""
    out = {}
    if not path.exists():
        return out
    for line in path.read_text(encoding="utf-8").splitlines():
        line = line.strip()
        if line:
            row = json.loads(line)
            out[row["name"]] = row
    return out


def read_peer(path: Path) -> dict | None:
    if not path.exists():
        return None
    text = path.read_text(encoding="utf-8").strip()
    if not text:
        return None
    doc = json.loads(text)
    doc["by_name"] = {f["name"]: f for f in doc["figures"]}
    return doc


def skipped(d: Path, name: str) -> str:
    p = d / f"{name}.skipped"
    if p.exists():
        return p.read_text(encoding="utf-8").strip()
    return "its output is missing (the bench failed or was not built)"


def binary_size(path: str) -> int | None:
    """text + data + bss of an executable (debug info and symbols left out)."""
    try:
        out = subprocess.run(["size", path], check=True, capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    fields = out.splitlines()[1].split()
    return int(fields[0]) + int(fields[1])


# ---- formatting ----------------------------------------------------------------


def us(x) -> str:
    if x is None:
        return "-"
    if x >= 1000:
        return f"{x:,.0f}"
    if x >= 100:
        return f"{x:.0f}"
    if x >= 10:
        return f"{x:.1f}"
    if x >= 1:
        return f"{x:.2f}"
    return f"{x:.3f}"


def ratio(a, b) -> str:
    if a is None or b is None or b == 0:
        return "-"
    r = a / b
    return f"{r:.2f}x" if r >= 0.1 else f"{r:.3f}x" if r >= 0.001 else f"{r:.1e}x"


class Table:
    """A markdown table of timed figures: name, p50, p99, max, ratio."""

    def __init__(self, ref_label: str, percent: bool = False):
        self.rows = []
        self.ref_label = ref_label
        self.percent = percent

    def timing(self, label: str, fig: dict | None, ref: dict | None, note: str = ""):
        if fig is None:
            self.rows.append(f"| {label} | - | - | - | - | not measured |")
            return
        r = ratio(fig.get("p50"), ref.get("p50")) if ref else "-"
        if self.percent and ref and fig.get("p50") is not None:
            r = f"{100.0 * fig['p50'] / ref['p50']:.3f} %"
        self.rows.append(f"| {label} | {us(fig.get('p50'))} | {us(fig.get('p99'))} | "
                         f"{us(fig.get('max'))} | {r} | {note} |")

    def render(self) -> str:
        what = "p50 as a share of" if self.percent else "p50 ratio to"
        head = (f"| | p50 [us] | p99 [us] | max [us] | {what} {self.ref_label} | |\n"
                "|---|---:|---:|---:|---:|---|\n")
        return head + "\n".join(self.rows) + "\n"


def value(fig: dict | None, fmt: str = "{:,.0f}") -> str:
    if fig is None:
        return "-"
    return fmt.format(fig["value"]) + ("" if fig["unit"] in ("count", "values") else f" {fig['unit']}")


# ---- every engine side by side ---------------------------------------------------

# the three controllers: bench/aot's name, bench/peers' figure name (fuel metered)
SUMMARY_WORK = (("G1 PD", "G1 PD", "process, metering fuel"),
                ("G1 PD (bulk)", "the bulk PD", "process, bulk, metering fuel"),
                ("G1 policy (nn)", "the nn policy", "process, nn policy, metering fuel"))


def engines_summary(aot: dict, peers: dict) -> str:
    """One table of process() p50 for the three controllers under every
    engine, each with its ratio to native C: native, ahead of time and wasm3
    from bench/aot (one process, taking turns), wasmtime and wasmi from
    bench/peers (processes of their own), all of the same make bench run."""
    head = ("**Every engine side by side** (`process()` p50 in us and its ratio to the same "
            "source compiled natively; native C, roz ahead of time and roz on wasm3 from "
            "`bench/aot` (one process, taking turns on every call), wasmtime and wasmi from "
            "`bench/peers` below (processes of their own, run in turns), every engine charging "
            "fuel; the same `make bench` run):\n")
    if not aot and not any(peers.values()):
        return head + "\nNot measured (neither bench/aot nor bench/peers ran).\n"

    def cell(fig, native):
        if fig is None or fig.get("p50") is None:
            return "-"
        return f"{us(fig['p50'])} ({ratio(fig['p50'], native.get('p50') if native else None)})"

    natives = {work: aot.get(f"{work}: process(), native") for work, _, _ in SUMMARY_WORK}
    rows = [("native C (reference)", {w: natives[w] for w in natives}),
            ("roz, ahead of time (rozaot + wasm2c)",
             {w: aot.get(f"{w}: process(), ahead of time") for w in natives}),
            ("roz, wasm3", {w: aot.get(f"{w}: process(), wasm3") for w in natives})]
    for key in ("wasmtime", "wasmi"):
        p = peers.get(key)
        label = f"{p['engine']} {p.get('version', '')}".strip() if p else key
        rows.append((label, {w: (p["by_name"].get(pname) if p else None)
                             for w, _, pname in SUMMARY_WORK}))
    out = [head, "| engine | " + " | ".join(shown for _, shown, _ in SUMMARY_WORK) + " |",
           "|---|" + "---:|" * len(SUMMARY_WORK)]
    for label, figs in rows:
        out.append(f"| {label} | " + " | ".join(cell(figs[w], natives[w])
                                                 for w, _, _ in SUMMARY_WORK) + " |")
    return "\n".join(out) + "\n"


# ---- the firmware images at a glance ------------------------------------------------


def firmware_summary(text: str) -> str:
    """One row per image of make firmware's reports (tools/fw_run.sh): flash
    and RAM all told against the aims, and the instructions per tick and per
    process() call, so that an image compiled ahead of time reads beside the
    interpreter's build of the same controller. Empty when no image
    reported."""
    images = []
    for block in text.split("\n==== ")[1:]:
        lines = block.splitlines()
        img = {"title": lines[0].strip()}
        for line in lines[1:]:
            f = line.split()
            if line.startswith("cost: tick ") and "mean" in f:
                img["tick"] = int(f[f.index("mean") + 1])
            elif line.startswith("cost: process()") and "mean" in f:
                img["process"] = int(f[f.index("mean") + 1])
            elif line.startswith("  total ") and len(f) >= 2:
                img["flash"] = f[1]
            elif line.startswith("  RAM all told") and len(f) >= 4:
                img["ram"] = f[3]
            elif line.startswith("  aim: flash <="):
                img["flash_aim"] = f"{f[3]} KB, {'met' if line.endswith(': met') else 'NOT met'}"
            elif line.startswith("  aim: RAM <="):
                img["ram_aim"] = f"{f[3]} KB, {'met' if line.endswith(': met') else 'NOT met'}"
        images.append(img)
    if not images:
        return ""
    out = ["The images at a glance (from the reports below; instructions are QEMU's "
           "emulation estimates, means over the run's ticks):\n",
           "| image | flash [KB] | aim | RAM all told [KB] | aim | instructions per tick | "
           "per process() |", "|---|---:|---|---:|---|---:|---:|"]
    for img in images:
        tick = f"{img['tick']:,}" if "tick" in img else "-"
        proc = f"{img['process']:,}" if "process" in img else "-"
        out.append(f"| {img['title']} | {img.get('flash', '-')} | {img.get('flash_aim', '-')} | "
                   f"{img.get('ram', '-')} | {img.get('ram_aim', '-')} | {tick} | {proc} |")
    return "\n".join(out) + "\n"


# ---- the banner ----------------------------------------------------------------


def machine() -> str:
    cpu = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = ""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal"):
                mem = f", {int(line.split()[1]) / 1048576:.0f} GiB"
    except OSError:
        pass
    load = ""
    try:
        load = ", load average at the end " + " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        pass
    return (f"{cpu}, {os.cpu_count()} cores{mem}, Linux {platform.release()}"
            f" ({platform.machine()}){load}")


def commit(root: Path) -> str:
    try:
        h = subprocess.run(["git", "-C", str(root), "rev-parse", "--short=12", "HEAD"],
                           check=True, capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no"],
                               check=True, capture_output=True, text=True).stdout.strip()
        return h + (" (with uncommitted changes)" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


# ---- the tick on every target -------------------------------------------------------

TARGET_COLUMNS = [("x86-64", "x86-64"), ("aarch64", "aarch64"), ("m4f", "Cortex-M4F"),
                  ("m7", "Cortex-M7"), ("m33", "Cortex-M33")]
TARGET_CONTROLLERS = [("ur5_sine", "UR5, sine"), ("g1_pd", "G1 PD"),
                      ("g1_policy", "G1 learned policy")]
# (label, part, statistic): the rows of each controller
TARGET_ROWS = [("whole tick", "tick", "mean"), ("controller, `process()`", "process", "mean"),
               ("safety filter", "filter", "mean"), ("runtime's own work", "runtime", "mean"),
               ("port (loopback read + write)", "port", "mean"),
               ("the board's clock reads", "clock", "mean")]
POLICY_ROWS = [("inference tick: `process()`", "process", "max"),
               ("inference tick: whole tick", "tick", "max")]


def read_targets(path: Path) -> list:
    if not path.exists():
        return []
    return [json.loads(l) for l in path.read_text(encoding="utf-8").splitlines() if l.strip()]


def ticks_measured(rows: list) -> str:
    """The ticks each count is over ("100"; "80 to 100" if they differ)."""
    n = sorted({r["ticks"] for r in rows if "ticks" in r})
    if not n:
        return "the measured"
    return f"{n[0]:,}" if len(n) == 1 else f"{n[0]:,} to {n[-1]:,}"


def targets_table(rows: list) -> str:
    """The tick's instructions per part (rows) on every target (columns),
    from bench/targets' JSON lines; a combination not run is a dash, its
    reason listed under the table."""
    by = {(r["controller"], r["target"]): r for r in rows}
    head = "| instructions per tick | " + " | ".join(c for _, c in TARGET_COLUMNS) + " |"
    out = [head, "|---|" + "---:|" * len(TARGET_COLUMNS)]
    notes = {}
    for key, title in TARGET_CONTROLLERS:
        if not any(k[0] == key for k in by):
            continue
        out.append(f"| **{title}** |" + " |" * len(TARGET_COLUMNS))
        spec = TARGET_ROWS + (POLICY_ROWS if key == "g1_policy" else [])
        for label, part, stat in spec:
            cells = []
            for t, col in TARGET_COLUMNS:
                r = by.get((key, t))
                if r is None or "parts" not in r:
                    if r is not None and r.get("skipped"):
                        notes.setdefault(r["skipped"], []).append(f"{title} on {col}")
                    cells.append("-")
                    continue
                v = r["parts"].get(part, {}).get(stat)
                cells.append("-" if v is None else f"{v:,.0f}")
            out.append(f"| {label} | " + " | ".join(cells) + " |")
    text = "\n".join(out) + "\n"
    if notes:
        text += "\nNot run: " + "; ".join(
            f"{', '.join(dict.fromkeys(v))}: {why}" for why, v in notes.items()) + ".\n"
    return text


# ---- the document --------------------------------------------------------------


def build(args) -> tuple[str, str]:
    d = args.dir
    tick = read_lines(d / "tick.jsonl")
    fuel = read_lines(d / "fuel.jsonl")
    periodic = read_lines(d / "periodic.jsonl")
    alloc = read_lines(d / "alloc.jsonl")
    g1 = read_lines(d / "g1_latency.jsonl")
    can = read_lines(d / "can_codec.jsonl")
    toml = read_lines(d / "toml.jsonl")
    fw = read_lines(d / "firmware.jsonl")
    rec = read_lines(d / "record.jsonl")
    nn = read_lines(d / "nn.jsonl")
    aot = read_lines(d / "aot.jsonl")
    mujoco = read_lines(d / "mujoco.jsonl")
    camp = read_lines(d / "campaign.jsonl")
    targets = read_targets(d / "targets.jsonl")
    peers = {k: read_peer(d / f"peer-{k}.json") for k in ("roz", "wasmtime", "wasmi")}
    sizes = {}
    for b in args.binary or []:
        name, _, path = b.partition("=")
        sizes[name] = binary_size(path)

    out = []
    w = out.append
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    w("# roz benchmarks\n")
    w("<!-- Generated by bench/report.py from `make bench`; do not edit by hand. -->\n")
    w(f"- **Machine:** {machine()}. {args.machine_note}")
    w(f"- **Date:** {now}")
    w(f"- **Commit:** {commit(args.root)}")
    w(f"- **Command:** `{args.command}`\n")
    w("Every figure is from this one run; each ratio compares two figures of the same run, "
      "so drift on the machine hits both sides. Times are wall-clock microseconds unless "
      "a row says otherwise: p50, p99 and the largest of the samples. A loaded, shared "
      "machine shows in the p99 and max columns (preemption, other builds), much less in "
      "p50. Benchmarks print; none fails on a time.\n")

    # 1. tick
    w("## 1. Tick cost: wasm3 vs native, runtime overhead, metering\n")
    w("`bench/tick`: the runtime's whole tick on the loopback simulator, the controller's "
      "`process()` under wasm3 (as the runtime times it), the same C source compiled natively "
      "against the same ABI functions on the same snapshots (outputs compared every tick), "
      "the runtime's own overhead (tick - process - the port's read and write) and the "
      "loopback port itself (it simulates the robot and moves CRC'd frames inside the tick; "
      "a hardware port does that on its own threads).\n")
    for robot, ctl in (("unitree_g1", "G1 PD, 145 commands, 97 states"),
                       ("unitree_g1 (bulk)", "the same PD through state.get_all and "
                        "command.set_all, one host call each way"),
                       ("ur5", "UR5 PD hold, 6 commands, 12 states")):
        w(f"**{robot}** ({ctl}):\n")
        t = Table("native process()")
        native = tick.get(f"{robot}: process(), native")
        t.timing("process(), wasm3", tick.get(f"{robot}: process(), wasm3"), native)
        t.timing("process(), native (reference)", native, native)
        t.timing("runtime overhead (tick - process - port)", tick.get(f"{robot}: runtime (tick - process - port)"), native)
        t.timing("port read + write (loopback simulator)", tick.get(f"{robot}: port read + write (loopback sim)"), native)
        t.timing("whole tick, wasm3", tick.get(f"{robot}: whole tick, wasm3"), native)
        w(t.render())
        diff = tick.get(f"{robot}: wasm3 and native targets differing")
        if diff is not None:
            w(f"Outputs: wasm3 and native targets {'identical' if diff['value'] == 0 else 'DIFFER'} "
              f"({value(diff)} differing values).\n")
    if not tick:
        w(f"Not run: {skipped(d, 'tick')}.\n")
    w("**Metering** (fuel charged per run of straight-line code, a budget and the deadline "
      "check, vs the same module compiled without charges):\n")
    t = Table("no charges")
    for k, label in (("G1 PD (host calls)", "G1 PD"), ("loop-heavy (29x29 loops)", "loop-heavy (29x29 loops)")):
        bare = tick.get(f"metering: {k}, no charges")
        units = tick.get(f"metering: {k}, units per call")
        t.timing(f"{label}, charged", tick.get(f"metering: {k}, charged"), bare,
                 f"{value(units)} a call" if units else "")
        t.timing(f"{label}, no charges (reference)", bare, bare)
    w(t.render())
    if fuel:
        med = fuel.get("cost of 1000 units, median over the kinds of work")
        w("What a fuel unit costs (`bench/fuel`, CPU time per 1000 units, median call per kind of work):\n")
        w("| work | ns per 1000 units | ratio to the median |\n|---|---:|---:|")
        for name, fig in fuel.items():
            if name.startswith("cost of 1000 units, ") and fig is not med:
                w(f"| {name.removeprefix('cost of 1000 units, ')} | {fig['value']:.0f} | "
                  f"{ratio(fig['value'], med['value'] if med else None)} |")
        w("")
        for name, fig in fuel.items():
            if "longest call" in name:
                w(f"- {name}: {fig['value']:.2f}x")
        w("")

    # a learned policy's inference
    w("**A learned policy** (`bench/nn`: one inference of the G1 policy's shape, 47 -> LSTM 64 "
      "-> 32 ELU -> 12, random weights; CPU time per call; the nn imports, roz_nn.h):\n")
    if nn:
        t = Table("native C")
        native = nn.get("policy inference, native C")
        f_sdk = nn.get("policy inference fuel, nn imports")
        f_plain = nn.get("policy inference fuel, plain wasm")
        t.timing("wasm3, roz_nn.h + nn imports", nn.get("policy inference, wasm3 + nn imports"),
                 native, f"fuel: {value(f_sdk)}" if f_sdk else "")
        t.timing("wasm3, the same loops as plain wasm", nn.get("policy inference, wasm3, plain wasm"),
                 native, f"fuel: {value(f_plain)}" if f_plain else "")
        t.timing("native C (reference)", native, native)
        w(t.render())
        dep_native = nn.get("deployed inference tick, native C")
        if dep_native:
            w("The same shape deployed by `rozgen-nn deploy` (`roz_policy.h` over the G1's "
              "deploy_real configuration, `g1_deployed_full`): an inference tick, observations "
              "from 97 states, the network, 145 targets:\n")
            t = Table("native C")
            f_dep = nn.get("deployed inference tick fuel")
            t.timing("wasm3 + nn imports, deployed controller",
                     nn.get("deployed inference tick, wasm3 + nn imports"), dep_native,
                     f"fuel: {value(f_dep)}" if f_dep else "")
            t.timing("native C (the same generated C)", dep_native, dep_native)
            w(t.render())
        w("What the nn imports' work costs the host per fuel unit (CPU time; a unit of wasm "
          "costs the median above):\n")
        w("| work | ns per unit |\n|---|---:|")
        for name, fig in nn.items():
            if name.endswith(", ns per unit"):
                w(f"| {name.removesuffix(', ns per unit')} | {fig['value']:.2f} |")
        w("")
    else:
        w(f"Not run: {skipped(d, 'nn')}.\n")

    # the ahead-of-time engine
    w("**Ahead of time** (`bench/aot`: the same module through rozaot and wasm2c, linked in, "
      "against wasm3 and the same source compiled natively, taking turns on every call on the "
      "same states; both engines charge fuel, and the same fuel, checked on every call; "
      "aim: ahead of time <= 1.3x native):\n")
    if aot:
        for work in ("G1 PD", "G1 PD (bulk)", "G1 policy (nn)"):
            native = aot.get(f"{work}: process(), native")
            fuel_fig = aot.get(f"{work}: fuel per call")
            differ = aot.get(f"{work}: targets differing")
            t = Table("native C")
            t.timing(f"{work}, ahead of time", aot.get(f"{work}: process(), ahead of time"), native,
                     f"fuel: {value(fuel_fig)}" if fuel_fig else "")
            t.timing(f"{work}, wasm3", aot.get(f"{work}: process(), wasm3"), native)
            t.timing(f"{work}, native C (reference)", native, native,
                     f"targets differing: {value(differ)}" if differ else "")
            w(t.render())
    else:
        w(f"Not run: {skipped(d, 'aot')}.\n")

    # 2 + 3. peers
    w("## 2. Peer engines: the same controller under wasmtime and wasmi\n")
    w(engines_summary(aot, peers))
    w("`bench/peers`: the G1 PD module that roz runs (`g1_pd.wasm`, built by the host build) "
      "with roz's host functions (the same ABI: `command.set` clamps, refuses non-finite "
      "values and counts, `state.get` reads a snapshot), the G1 manifest read from "
      "`rozgen --json`, and the same deterministic state sequence (bench/peers/README.md). "
      "Small Rust harnesses, crates pinned in `bench/peers/Cargo.lock`. Before any figure "
      "is printed each harness runs the module for the reference ticks in every metering "
      "mode and compares every command target (bit for bit) and the ABI's counters with "
      "roz's own outputs; a harness that differs prints no figure.\n")
    roz = peers["roz"]
    ref = roz["by_name"].get("process, metering fuel+deadline") if roz else None
    t = Table("roz (wasm3, metered)")
    rows_present = False
    for key, label in (("roz", "roz (wasm3)"), ("wasmtime", "wasmtime"), ("wasmi", "wasmi")):
        p = peers[key]
        if p is None:
            t.rows.append(f"| {label} | - | - | - | - | not shown: {skipped(d, 'peer-' + key)} |")
            continue
        rows_present = True
        for fname, f in p["by_name"].items():
            if fname.startswith("process, "):
                t.timing(f"{label} {p['version']}, {fname.removeprefix('process, ')}", f, ref,
                         "reference" if f is ref else "")
    w("**`process()` per call** (the call through the engine's API, the budget set before "
      "each call as a tick loop does; \"bulk\" rows run `g1_pd_bulk.wasm`, the same PD "
      "through `state.get_all` and `command.set_all`, whose outputs are checked against the "
      "same reference; \"nn policy\" rows run `bench_nn_policy.wasm`, one inference of the "
      "G1 policy's shape through `nn.matvec` and `nn.act` a call, its outputs checked against "
      "roz's bit for bit):\n")
    w(t.render())
    if rows_present:
        for key in ("roz", "wasmtime", "wasmi"):
            if peers[key]:
                w(f"- {peers[key]['engine']}: {peers[key].get('checked', '')}.")
        w("")
        rounds = {k: peers[k]["rounds"] for k in ("roz", "wasmtime", "wasmi")
                  if peers[k] and "rounds" in peers[k]}
        if rounds:
            runs = max(r["runs"] for r in rounds.values())
            spread = "; ".join(f"{peers[k]['engine']} " + ", ".join(f"{v:.3g}" for v in r["p50s"])
                               for k, r in rounds.items())
            w(f"The engines run in processes of their own, so each ran {runs} times, taking "
              "turns (roz, wasmtime, wasmi, roz, ...), and its figures are those of its median "
              f"run by `process()` p50 with metering off (those p50s, us: {spread}).\n")
        w("Metering modes: roz charges fuel per run of straight-line code and reads the clock "
          "for the deadline every 4096 units (the runtime's default budget: a tick's fuel and "
          "the period); wasmtime's fuel counts instructions in compiled code and its epoch "
          "interruption checks a counter at function entries and loop back-edges (no thread "
          "advances the epoch here: the figure is the checks' cost); wasmi's fuel is charged "
          "per instruction group.\n")
    w("**Load, compile, instantiate** (20 times each; item 3 of the issue: roz's validator, "
      "wasm3's compile and the 100 verification ticks against wasmtime's compile):\n")
    wt = peers["wasmtime"]
    wt_compile = wt["by_name"].get("compile") if wt else None
    t = Table("wasmtime compile")
    if roz:
        t.timing("roz: validate (module scan)", roz["by_name"].get("validate (roz's module scan)"), wt_compile)
        t.timing("roz: load (validate, parse, link, wasm3 compile)",
                 roz["by_name"].get("compile (validate, parse, link, compile)"), wt_compile)
        t.timing("roz: verify (100 ticks)", roz["by_name"].get("verify (100 ticks)"), wt_compile)
    for key in ("wasmtime", "wasmi"):
        p = peers[key]
        if p:
            t.timing(f"{key}: compile", p["by_name"].get("compile"), wt_compile,
                     "reference" if p is wt else "")
            t.timing(f"{key}: instantiate", p["by_name"].get("instantiate"), wt_compile)
    w(t.render())
    w("**Memory and size:**\n")
    w("| engine | resident memory added by one loaded controller that ran | harness executable (text + data) |")
    w("|---|---:|---:|")
    for key, binname in (("roz", "roz"), ("wasmtime", "wasmtime"), ("wasmi", "wasmi")):
        p = peers[key]
        size = sizes.get(binname)
        mem = value(p["by_name"].get("resident memory added")) if p else "-"
        label = p["engine"] if p else key
        w(f"| {label} | {mem} | {f'{size / 1024:,.0f} KiB' if size else '-'} |")
    w("\nThe executables hold the harness too (JSON, the manifest reader, timing); roz's links "
      "roz's core, the G1 tables and wasm3.\n")

    # 4. periodic
    w("## 3. Periodic runner at 1 kHz\n")
    if periodic:
        secs = periodic.get("seconds per side")
        w(f"`bench/periodic`: the runner (`roz/runner.h`) at 1 kHz running the G1 tick on the "
          f"loopback, against a bare `clock_nanosleep(TIMER_ABSTIME)` loop doing nothing else, "
          f"{value(secs)} each in alternating 5 s rounds, normal scheduling (no SCHED_FIFO, no "
          f"mlockall). Wake-up latency is the time woken minus the deadline slept for; at "
          f"normal scheduling Linux lets a sleep end up to the thread's timer slack late (50 us "
          f"by default; none for SCHED_FIFO threads, which rozrun asks for with --realtime).\n")
        t = Table("bare loop")
        bare = periodic.get("wake-up latency, bare clock_nanosleep loop")
        t.timing("roz runner + G1 tick", periodic.get("wake-up latency, roz runner + G1 tick"), bare,
                 f"{value(periodic.get('missed deadlines, roz runner'))} deadlines missed by more than a period")
        t.timing("bare clock_nanosleep loop (reference)", bare, bare,
                 f"{value(periodic.get('missed deadlines, bare loop'))} missed")
        w(t.render())
    else:
        w(f"Not run: {skipped(d, 'periodic')}.\n")

    # 5. alloc
    w("## 4. Heap calls in the tick\n")
    if alloc:
        w("`bench/alloc`: malloc, calloc, realloc and free wrapped by the linker and counted "
          "while the runtime ticks (the load is counted too, to show the counter is live). "
          "Must be 0.\n")
        w("| controller | ticks | heap calls in the ticks | heap calls of the load |\n|---|---:|---:|---:|")
        for robot in ("unitree_g1, g1_pd", "ur5, pd_hold"):
            ticks = [n for n in alloc if n.startswith(robot + ": heap calls in")]
            if ticks:
                n = ticks[0].split(" in ")[1].split()[0]
                w(f"| {robot} | {int(n):,} | {value(alloc[ticks[0]])} | "
                  f"{value(alloc.get(robot + ': heap calls of the load'))} |")
        w("")
    else:
        w(f"Not run: {skipped(d, 'alloc')}.\n")

    # 6. ports
    w("## 5. Ports: DDS latency, CAN codec\n")
    if g1:
        spin_fig = g1.get("writer spin (us)")
        spin = f"{spin_fig['value']:.0f}" if spin_fig else "?"
        w("`bench/g1_latency`: a LowState_ out to the LowCmd_ that answers it through roz (the "
          "unitree/G1 port, the G1 PD under wasm3, the event-driven writer: woken by the "
          f"tick's write, or spinning up to {spin} us for it after each state frame, "
          "`command_writer_spin_us`), against a raw Cyclone DDS ping-pong of the same sizes; "
          "the three interleaved round trip by round trip, two processes on loopback in a "
          "network namespace of their own, the robot's on CPU 0 and roz's on CPU 1 (as two "
          "machines would be). Figures are given only when no roz tick ran under a fault. "
          "The spinning writer is for a machine with a core to spare for it: here it shares "
          "roz's one CPU with the tick.\n")
        t = Table("raw ping-pong")
        raw = g1.get("raw Cyclone ping-pong")
        t.timing("roz: unitree/G1, G1 PD under wasm3, writer woken by the tick",
                 g1.get("roz: unitree/G1, G1 PD under wasm3"), raw,
                 f"{value(g1.get('lost round trips'))} round trips lost (all paths)")
        t.timing(f"roz: the same, writer spinning (command_writer_spin_us={spin})",
                 g1.get("roz: unitree/G1, G1 PD under wasm3, writer spin"), raw)
        t.timing("raw Cyclone DDS ping-pong (reference)", raw, raw)
        w(t.render())
    else:
        w(f"DDS latency not run: {skipped(d, 'g1_latency')}.\n")
    if can:
        w("`bench/can_codec`: the MIT-mode codec per joint, and the socketcan port's read() and "
          "write() in the tick on the example leg against fake actuators on a socketpair.\n")
        t = Table("the 2 ms period (500 Hz)", percent=True)
        period = {"p50": 2000.0}
        for name, fig in can.items():
            t.timing(name, fig, period)
        w(t.render())
        w("The codec has no timed reference of its own (its exact reference is the Python "
          "model its test vectors come from); the ratio is the share of a 500 Hz tick.\n")
    else:
        w(f"CAN codec not run: {skipped(d, 'can_codec')}.\n")

    # 7. firmware
    w("## 6. Firmware\n")
    fw_text = d / "firmware.txt"
    if fw:
        w("From the firmware build (QEMU, `-icount shift=0`):\n")
        w("| figure | value |\n|---|---:|")
        for name, fig in fw.items():
            w(f"| {name} | {value(fig) if 'value' in fig else us(fig.get('p50')) + ' us'} |")
        w("")
    elif fw_text.exists():
        w("`make firmware`: the images booted in QEMU (`-icount shift=0`, one instruction "
          "per virtual nanosecond: per-tick instruction counts are emulation estimates), "
          "their reports and their footprint against the aims, as printed:\n")
        # the reports only: from the first image's heading on, without the
        # build's own lines (which name this machine's paths)
        text = fw_text.read_text(encoding="utf-8")
        start = text.find("==== ")
        text = text[start:] if start >= 0 else ""
        lines = [l for l in text.splitlines()
                 if not l.startswith(("make[", "ninja:", "[", "PYTHON=", "cmake ", "/usr/bin/cmake",
                                      "-- ", "setup:"))
                 and "CMAKE_" not in l and not l.lstrip().startswith('"')]
        glance = firmware_summary("\n" + "\n".join(lines))
        if glance:
            w(glance)
        w("```\n" + "\n".join(lines).strip() + "\n```\n")
    else:
        w(f"Not built: {skipped(d, 'firmware')}.\n")
    # the flash each option saves (make firmware-options: a Markdown table)
    fw_options = d / "firmware_options.md"
    w("### Footprint per build option\n")
    if fw_options.exists():
        w(fw_options.read_text(encoding="utf-8").strip() + "\n")
    else:
        w(f"Not built: {skipped(d, 'firmware_options')}.\n")

    # 8. toml
    w("## 7. robot.toml: the C reader and loader vs tomllib and rozgen\n")
    if toml:
        w("`bench/toml`: one read of each file, CPU time, the median of runs (no tail: p50 "
          "only). The large files are generated: a UR5 with 10^5 `[hardware.params]` keys "
          "and one with 10^5 joint names.\n")
        w("| file | bytes | C reader [us] | C loader [us] | tomllib [us] | rozgen [us] | C loader / rozgen |")
        w("|---|---:|---:|---:|---:|---:|---:|")
        files = []
        for name in toml:
            f = name.rsplit(": ", 1)[0]
            if f not in files:
                files.append(f)
        for f in files:
            g = lambda what: toml.get(f"{f}: {what}", {}).get("p50")
            size = toml.get(f"{f}: C loader", {}).get("bytes", 0)
            w(f"| {f} | {size:,} | {us(g('C reader'))} | {us(g('C loader'))} | {us(g('tomllib'))} | "
              f"{us(g('rozgen'))} | {ratio(g('C loader'), g('rozgen'))} |")
        w("")
    else:
        w(f"Not run: {skipped(d, 'toml')}.\n")

    # 9. the recorder
    w("## 8. The flight recorder\n")
    if rec:
        w("`bench/record`: the same controller on two runtimes side by side on the loopback, "
          "one recording into a ring drained into an MCAP file every few ticks, one not; "
          "the ticks alternate, so drift hits both.\n")
        t = Table("recorder off")
        robots = []
        for name in rec:
            r = name.split(": ", 1)[0]
            if r not in robots:
                robots.append(r)
        for r in robots:
            t.timing(f"{r}: whole tick, recorder on", rec.get(f"{r}: whole tick, recorder on"),
                     rec.get(f"{r}: whole tick, recorder off"))
            t.timing(f"{r}: whole tick, recorder off (reference)",
                     rec.get(f"{r}: whole tick, recorder off"),
                     rec.get(f"{r}: whole tick, recorder off"))
        w(t.render())
        w("| robot | ring bytes per tick | MCAP bytes per tick | drain into MCAP [ticks/s] | "
          "drain into a counting sink [ticks/s] | records dropped |")
        w("|---|---:|---:|---:|---:|---:|")
        for r in robots:
            v = lambda what: value(rec.get(f"{r}: {what}"))
            w(f"| {r} | {v('ring bytes per tick')} | {v('MCAP bytes per tick')} | "
              f"{v('drain into the MCAP file')} | {v('drain into a counting sink')} | "
              f"{v('records dropped')} |")
        w("")
    else:
        w(f"Not run: {skipped(d, 'record')}.\n")

    # 10. physics
    w("## 9. Physics (the mujoco port)\n")
    if mujoco:
        w("`bench/mujoco`: the whole roz tick on the MuJoCo G1 (the example stand controller, "
          "the filter, the port's actuator law and sensors, one 2 ms step a tick) against a bare "
          "loop of the same `mj_step` calls on the same model in the same run, replaying the "
          "controls the roz run applied (the same states, the same contacts); the two alternate "
          "in blocks of 100; the tick is also shown less its controller's process() (the "
          "balancing stand's IMU feedback is the user's work, not roz's). Aim: roz adds at most "
          "5 %, and the G1 runs at least 10x real time.\n")
        t = Table("bare mj_step")
        t.timing("G1: whole roz tick", mujoco.get("unitree_g1: whole roz tick"),
                 mujoco.get("unitree_g1: bare mj_step"))
        t.timing("G1: the tick less the controller's process()",
                 mujoco.get("unitree_g1: roz tick less process()"),
                 mujoco.get("unitree_g1: bare mj_step"))
        t.timing("G1: process() (the controller, in the tick)",
                 mujoco.get("unitree_g1: process()"), mujoco.get("unitree_g1: bare mj_step"))
        t.timing("G1: bare mj_step (reference)", mujoco.get("unitree_g1: bare mj_step"),
                 mujoco.get("unitree_g1: bare mj_step"))
        w(t.render())
        v = lambda what: value(mujoco.get(f"unitree_g1: {what}"), "{:,.1f}")
        w(f"Simulated time: {v('real-time factor (roz)')} real time through roz, "
          f"{v('real-time factor (bare)')} bare; the port's open (parse, spec edits, compile, "
          f"data): {v('open')}.\n")
    else:
        w(f"Not run: {skipped(d, 'mujoco')}.\n")

    # 11. campaigns
    w("## 10. Campaigns (roz-campaign)\n")
    if camp:
        w("`bench/campaign`: G1 samples (the balancing stand, pushed from any side) run as bare "
          "rozrun commands one after another, then as a campaign (docs/campaigns.md) on one and "
          "on two local workers and on a one-node Ray cluster of two CPUs on 127.0.0.1, all in "
          "the same run, bare and local runs alternating twice (each figure the best of its "
          "rounds); each figure in simulated seconds per wall second. A campaign's wall "
          "time includes its first one-tick run (the robot's rate, on the loopback port) and "
          "writing the results. "
          "Aims: the engine costs at most 5 %, two workers give at least 0.9x linear. Two "
          "processes rarely get twice one's rate from a machine (shared caches, clocks that "
          "slow when every core works): the same bare commands, two at once, measure the "
          "machine's own ceiling, and the engine's share of the gap to linear is what that "
          "ceiling does not explain. Ratios: one worker over bare rozrun; two bare at once "
          "over twice one bare; two workers over two bare at once; Ray over two local "
          "workers. The engine's cost is given in wall time and in CPU time (the driver and "
          "its rozruns against the bare rozruns), which a loaded machine does not inflate.\n")
        w("| figure | value | ratio |")
        w("|---|---:|---:|")
        for name, fig in camp.items():
            r = f"{fig['ratio']:.2f}" if "ratio" in fig else ""
            w(f"| {name} | {fig['value']:,.2f} {fig['unit']} | {r} |")
        est = next((f for n, f in camp.items() if n.startswith("estimate")), None)
        if est:
            w(f"\nThe estimate takes the one-worker rate ({est['per_core']:,.2f} simulated s per "
              "wall s per core) times the scaling measured here (at most linear), for 3,200 "
              "cores, as if every node kept this machine's rate per core; a Ray cluster adds its "
              "start and the driver's results (a line a sample), which do not grow with the "
              "nodes.\n")
        w("")
    else:
        w(f"Not run: {skipped(d, 'campaign')}.\n")

    # 11. the tick on every target
    w("## 11. The tick on every target, in instructions\n")
    if targets:
        w("`bench/targets` (`make bench-targets`): one program on every target, the firmware "
          "images' application (`examples/firmware/app`: `roz_runtime_tick()` on the loopback "
          "simulator, the same controllers' same bytes), run under QEMU with every executed "
          "block logged; `bench/targets/qemu_count.py` sums the guest instructions of the "
          "ticks and gives each to the innermost of these functions on a call stack rebuilt "
          "from the blocks: the controller (`roz_controller_process_from`: wasm3 and the "
          "imports), the safety filter (`roz_filter_apply`), the port (the loopback's read "
          "and write: it simulates the robot), the board's clock (`fw_clock_ns`, read by the "
          "runtime's monitor and the deadline in the images that run with a clock), and the "
          "tick itself (`roz_runtime_tick`: the runtime's own work, with the helpers it "
          "calls). Counts are exact and repeatable (no timer, no load): the mean over "
          f"{ticks_measured(targets)} ticks after the first ones; the policy's inference tick "
          "is the largest (its network runs once every few ticks, its decimation).\n")
        w(targets_table(targets))
        w("How each column was counted: **x86-64**, `roz_fw_host` built by this build "
          "(RelWithDebInfo, gcc -O2), under `qemu-x86_64 -cpu max` (glibc picks the routines "
          "of a CPU with AVX2); **aarch64**, the same program cross-built (test/aarch64's "
          "tree, Debian's gcc-aarch64-linux-gnu) under `qemu-aarch64`; **Cortex-M**, the "
          "images of `make firmware` (MinSizeRel, LTO), and the other robot's built the "
          "same way for the bench (`-DROZ_FW_VARIANT=ur5` or `g1`), under `qemu-system-arm "
          "-icount shift=0`. What they leave out: a real core's cycles per instruction (caches, "
          "pipelines, FPU latency: instructions are not time), the Linux kernel's work "
          "(system calls are one instruction here), the Cortex-M's interrupts that fall "
          "between two ticks; the single-precision FPU of the M4F (ARMv7-M) and the M33 "
          "(ARMv8-M) has no double, so their doubles are library calls, counted in the part "
          "that makes them.\n")
    else:
        w(f"Not run: {skipped(d, 'targets')}.\n")

    # the headline
    h = ["| figure | p50 | p99 | reference (same run) | ratio p50 |", "|---|---:|---:|---|---:|"]

    def hrow(label, fig, refname, reffig):
        if fig is None:
            return
        h.append(f"| {label} | {us(fig['p50'])} us | {us(fig['p99'])} us | {refname}: "
                 f"{us(reffig['p50']) + ' us' if reffig else '-'} | {ratio(fig['p50'], reffig['p50'] if reffig else None)} |")

    native = tick.get("unitree_g1: process(), native")
    hrow("G1 PD `process()`, wasm3", tick.get("unitree_g1: process(), wasm3"), "native", native)
    hrow("G1 PD `process()` through the bulk calls, wasm3", tick.get("unitree_g1 (bulk): process(), wasm3"),
         "native", tick.get("unitree_g1 (bulk): process(), native"))
    for work in ("G1 PD", "G1 PD (bulk)"):
        hrow(f"{work.replace('G1 PD', 'G1 PD `process()`')}, ahead of time",
             aot.get(f"{work}: process(), ahead of time"), "native",
             aot.get(f"{work}: process(), native"))
    hrow("G1 runtime overhead per tick", tick.get("unitree_g1: runtime (tick - process - port)"),
         "native process()", native)
    if wt:
        hrow("G1 PD `process()`, roz (wasm3, metered)", ref, "wasmtime, metering off",
             wt["by_name"].get("process, metering off"))
        wi = peers["wasmi"]
        if wi:
            hrow("G1 PD `process()`, roz (wasm3, metered)", ref, "wasmi, fuel",
                 wi["by_name"].get("process, metering fuel"))
        hrow("roz load + validate (wasm3)", roz["by_name"].get("compile (validate, parse, link, compile)"),
             "wasmtime compile", wt_compile)
    if periodic:
        hrow("1 kHz runner wake-up latency", periodic.get("wake-up latency, roz runner + G1 tick"),
             "bare clock_nanosleep", periodic.get("wake-up latency, bare clock_nanosleep loop"))
    if g1:
        hrow("G1 state-to-command over DDS", g1.get("roz: unitree/G1, G1 PD under wasm3"),
             "raw ping-pong", g1.get("raw Cyclone ping-pong"))
        if g1.get("roz: unitree/G1, G1 PD under wasm3, writer spin"):
            hrow("G1 state-to-command over DDS, writer spinning",
                 g1.get("roz: unitree/G1, G1 PD under wasm3, writer spin"),
                 "raw ping-pong", g1.get("raw Cyclone ping-pong"))
    a = alloc.get("unitree_g1, g1_pd: heap calls in 1000000 ticks") or next(
        (v for k, v in alloc.items() if k.startswith("unitree_g1, g1_pd: heap calls in")), None)
    headline = "\n".join(h) + "\n"
    if a:
        n = int(a["name"].split(" in ")[1].split()[0])
        headline += f"\nHeap calls in the tick: {value(a)} (G1 PD, {n:,} ticks).\n"
    w("## Headline\n")
    w(headline)
    return "\n".join(out) + "\n", headline


# ---- refreshing some sections of an existing report ------------------------------

# The sections a directory of results can refresh on its own (--refresh), with
# the files each is rendered from. Sections 1 to 5 feed the headline and are
# only written by a whole make bench.
SECTION_INPUTS = {
    "6": ("firmware.txt", "firmware.jsonl", "firmware_options.md"),
    "7": ("toml.jsonl",),
    "8": ("record.jsonl",),
    "9": ("mujoco.jsonl",),
    "10": ("campaign.jsonl",),
    "11": ("targets.jsonl",),
}


def held_sections(d: Path) -> list:
    """The sections of SECTION_INPUTS whose results d holds."""
    return [n for n, files in SECTION_INPUTS.items() if any((d / f).exists() for f in files)]


def split_sections(doc: str) -> list:
    """The document cut before each "## " heading: the header first."""
    return re.split(r"(?m)^(?=## )", doc)


def section_number(part: str) -> str | None:
    m = re.match(r"## (\d+)\. ", part)
    return m.group(1) if m else None


def refresh(old: str, new: str, numbers: list, command: str, at: str, date: str) -> str:
    """old with its sections `numbers` replaced by new's, every other part
    kept byte for byte; the header's Commit and Command lines say which
    command, commit and date these sections now come from."""
    fresh = {section_number(p): p for p in split_sections(new)}
    parts = split_sections(old)
    found = {section_number(p) for p in parts}
    for n in numbers:
        if n not in found or n not in fresh:
            raise SystemExit(f"report.py: no section {n} to refresh")
    parts = [fresh[section_number(p)] if section_number(p) in numbers else p for p in parts]
    header = parts[0]
    for n in numbers:
        # a later refresh of a section replaces the earlier one's note
        header = re.sub(rf"; section {n}: [^;\n]*", "", header)
        header = re.sub(rf"; its section {n} from [^;`]*", "", header)
        header = re.sub(r"(?m)^(- \*\*Commit:\*\* .*)$",
                        lambda m: f"{m.group(1)}; section {n}: {at}", header, count=1)
        header = re.sub(r"(?m)^(- \*\*Command:\*\* `[^`]*)`",
                        lambda m: f"{m.group(1)}; its section {n} from {command} at {at}, {date}`",
                        header, count=1)
    return header + "".join(parts[1:])


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--dir", type=Path, required=True)
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--root", type=Path, default=Path("."))
    p.add_argument("--command", default="make bench")
    p.add_argument("--machine-note", default="")
    p.add_argument("--binary", action="append")
    p.add_argument("--refresh", action="store_true",
                   help="replace in the existing --out only the sections whose results --dir "
                        "holds (SECTION_INPUTS), keeping every other section as it is")
    args = p.parse_args()
    doc, _ = build(args)
    if args.refresh:
        numbers = held_sections(args.dir)
        if not numbers:
            print(f"report.py: {args.dir} holds the results of no section of "
                  f"{', '.join(SECTION_INPUTS)}", file=sys.stderr)
            return 1
        now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        doc = refresh(args.out.read_text(encoding="utf-8"), doc, numbers,
                      args.command, commit(args.root), now)
        print(f"report.py: refreshed section {', '.join(numbers)} of {args.out}")
    else:
        print(f"report.py: wrote {args.out}")
    args.out.write_text(doc, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
