# SPDX-License-Identifier: Apache-2.0
"""bench/toml: roz's C TOML reader and robot.toml loader beside Python's
tomllib and rozgen, on the built-in manifests and on generated large files.

    bench_toml.py --bench ROZ_BENCH_TOML --root REPO [--work DIR] [--keys N]
                  [--json FILE]

Generated (in DIR): ur5 with a [hardware.params] table of N keys (the
number of keys in one table is what made the C reader quadratic), and ur5
with a [hardware] joints array of N names (the loader compared every pair).
Both exceed the C loader's limits of this build (ROZ_CFG_MAX_PARAMS,
ROZ_CFG_MAX_JOINTS): it still parses and checks them in full, then says
"storage"; rozgen accepts them.

Every figure is CPU time of one read, the median of several runs (C:
roz_bench_toml; Python: tomllib.loads, and rozgen's load and validate in
process, i.e. `rozgen --check` without the interpreter's start). A
benchmark, not a test: it prints, it never fails on a time. --json appends
each median as a JSON line (p50 only: the runs give a median, no tail) for
bench/report.py.
"""

import argparse
import json
import statistics
import subprocess
import sys
import time
import tomllib
from pathlib import Path

from rozgen.checker import find
from rozgen.load import load
from rozgen.validate import validate

_CHECKER = find()  # rozgen runs roz's C rules (roz_manifest_json) as a child process


def _generate(work: Path, root: Path, n: int) -> list[Path]:
    ur5 = (root / "manifests" / "ur5.toml").read_text(encoding="utf-8")
    keys = work / f"ur5-params-{n}.toml"
    keys.write_text(ur5 + '\n[hardware]\nport = "loopback"\n\n[hardware.params]\n'
                    + "".join(f'param_{i} = "value {i}"\n' for i in range(n)), encoding="utf-8")
    joints = work / f"ur5-joints-{n}.toml"
    joints.write_text(ur5 + '\n[hardware]\nport = "loopback"\njoints = [\n'
                      + "".join(f'  "joint_{i}",\n' for i in range(n)) + "]\n", encoding="utf-8")
    return [keys, joints]


def _median_time(fn, min_seconds: float) -> float:
    times: list[float] = []
    while len(times) < 3 or (sum(times) < min_seconds and len(times) < 101):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return statistics.median(times)


def _rozgen(path: Path) -> str:
    loaded = load(str(path))
    problems = loaded.problems
    if loaded.data is not None:
        _, problems = validate(loaded.data, checker=_CHECKER)
    return "ok" if not problems else problems[0].rule


def _fmt(seconds: float) -> str:
    if seconds >= 0.1:
        return f"{seconds:.2f} s"
    if seconds >= 1e-4:
        return f"{seconds * 1e3:.2f} ms"
    return f"{seconds * 1e6:.1f} us"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--bench", required=True, help="roz_bench_toml")
    p.add_argument("--root", required=True, type=Path, help="the repository")
    p.add_argument("--work", type=Path, help="where to write the generated files")
    p.add_argument("--keys", type=int, default=100_000)
    p.add_argument("--min-seconds", type=float, default=0.5)
    p.add_argument("--json", type=Path, help="append the figures as JSON lines")
    args = p.parse_args()
    work = args.work or Path("bench-toml")
    work.mkdir(parents=True, exist_ok=True)

    files = sorted((args.root / "manifests").glob("*.toml")) + _generate(work, args.root, args.keys)
    out = subprocess.run([args.bench, "--min-seconds", str(args.min_seconds),
                          *map(str, files)], check=True, capture_output=True, text=True).stdout
    c_rows = [line.split("\t") for line in out.splitlines()]

    print(f"bench/toml: one read of each file, CPU time, median of runs "
          f"(Python {sys.version_info.major}.{sys.version_info.minor})")
    head = ("file", "bytes", "C reader", "C loader", "tomllib", "rozgen", "loader/rozgen")
    print(f"{head[0]:26} {head[1]:>9} {head[2]:>10} {head[3]:>10} {head[4]:>10} {head[5]:>10}"
          f" {head[6]:>14}")
    ratios = {}
    rows = []
    for path, (_, size, _, reader, loader, verdict) in zip(files, c_rows):
        text = path.read_text(encoding="utf-8")
        t_toml = _median_time(lambda: tomllib.loads(text), args.min_seconds)
        t_rozgen = _median_time(lambda: _rozgen(path), args.min_seconds)
        py_verdict = _rozgen(path)
        ratio = float(loader) / t_rozgen
        ratios[path.name] = ratio
        for what, sec in (("C reader", float(reader)), ("C loader", float(loader)),
                          ("tomllib", t_toml), ("rozgen", t_rozgen)):
            rows.append({"bench": "toml", "name": f"{path.name}: {what}", "unit": "us",
                         "p50": sec * 1e6, "bytes": int(size)})
        note = "" if verdict == py_verdict else f"  (C loader: {verdict}; rozgen: {py_verdict})"
        print(f"{path.name:26} {int(size):>9,} {_fmt(float(reader)):>10} {_fmt(float(loader)):>10}"
              f" {_fmt(t_toml):>10} {_fmt(t_rozgen):>10} {ratio:>13.3f}x{note}")
    worst = max(ratios, key=ratios.get)
    print(f"slowest C loader against rozgen: {ratios[worst]:.3f}x ({worst}); "
          f"the aim is at most 3x at 10^5 keys")
    if args.json:
        with args.json.open("a", encoding="utf-8") as f:
            for row in rows:
                f.write(json.dumps(row) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
