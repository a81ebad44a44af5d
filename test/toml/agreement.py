# SPDX-License-Identifier: Apache-2.0
"""rozgen's TOML reading and roz's C reader give the same verdict on every file.

    agreement.py --root REPO --decoder ROZ_TOML_DECODER [--toml-test TOML_TEST]
                 [--work DIR] [--mutations N]

The files: every case of toml-test (valid and invalid, copied out of the
toml-test binary with ``-copy`` when it is installed), the shared vectors
(test/vectors, manifests, manifests/invalid), and N variants of each made
by a fixed seed: a line inserted at a random line boundary (an integer
beyond 64 bits, arrays nested too deep, a leap second, digits and brackets
in strings and comments...) and an integer beyond 64 bits inserted at a
random byte. Inserted anywhere, these also land inside strings, comments,
keys and broken documents, where neither reader may see them as values.

For each file, ``rozgen.load.load`` (tomllib and rozgen.toml_limits) and
roz_toml_decoder (host/toml/src/toml.c) must both accept it, or both refuse it at
the same line and column (bytes); for the refusals that rozgen words as the
C reader does (integers beyond 64 bits, nesting beyond the limit), with the
same message. Exit status 0 when all agree, 1 otherwise.
"""

import argparse
import concurrent.futures
import os
import random
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from rozgen.load import load
from rozgen.toml_limits import DEPTH, INT_RANGE, MAX_DEPTH

_INSERTS = [
    "big = 99999999999999999999",
    "x = [1, -9223372036854775809]",
    "h = 0x8000_0000_0000_0000",
    "ok = [9223372036854775807, -9223372036854775808, 0x7fff_ffff_ffff_ffff]",
    "d = " + "[" * (MAX_DEPTH + 1) + "]" * (MAX_DEPTH + 1),
    "d = " + "{a=" * (MAX_DEPTH + 1) + "1" + "}" * (MAX_DEPTH + 1),
    "d = " + "[" * MAX_DEPTH + "]" * MAX_DEPTH,
    's = "[[[[ 99999999999999999999 \\" 99999999999999999999"',
    "m = '''\n99999999999999999999 [[[[ '''",
    '99999999999999999999 = "x"',
    "# 99999999999999999999 [[[[",
    "t = 23:59:60",
    "y = 0000-01-01",
    "f = 0." + "0" * 600 + "1e600",
]
_C_ERROR = re.compile(r"^<stdin>:(?P<line>\d+):(?P<col>\d+): (?P<what>.*) \([^()]*\)$", re.DOTALL)
_PY_ERROR = re.compile(r"^:(?P<line>\d+):(?P<col>\d+): (?:invalid|unsupported) TOML: (?P<what>.*)$",
                       re.DOTALL)
_SHARED = (INT_RANGE, DEPTH)


def _variants(name: str, data: bytes, n: int) -> list[bytes]:
    rng = random.Random(name)
    out = [data]
    lines = data.split(b"\n")
    for _ in range(n):
        if rng.random() < 0.5:
            k = rng.randrange(len(lines) + 1)
            out.append(b"\n".join(lines[:k] + [rng.choice(_INSERTS).encode()] + lines[k:]))
        else:
            at = rng.randrange(len(data) + 1)
            out.append(data[:at] + b"99999999999999999999" + data[at:])
    return out


def _python_verdict(path: Path) -> tuple[str, str]:
    loaded = load(str(path))
    if not loaded.problems:
        return "ok", ""
    message = loaded.problems[0].message
    if loaded.problems[0].rule == "utf8":
        return "utf8", ""
    m = _PY_ERROR.match(message)
    return (f"{m['line']}:{m['col']}", m["what"]) if m else ("?", message)


def _c_verdict(decoder: str, data: bytes) -> tuple[str, str]:
    done = subprocess.run([decoder], input=data, capture_output=True, timeout=60)
    if done.returncode == 0:
        return "ok", ""
    err = done.stderr.decode("utf-8", errors="replace").strip()
    m = _C_ERROR.match(err)
    if m is None:
        return "?", err
    if m["what"].startswith("not valid UTF-8"):
        return "utf8", ""
    return f"{m['line']}:{m['col']}", m["what"]


def _check(job: tuple[int, str, bytes], decoder: str, work: Path) -> str | None:
    index, name, data = job
    path = work / f"case-{index}.toml"
    path.write_bytes(data)
    try:
        py = _python_verdict(path)
    finally:
        path.unlink()
    c = _c_verdict(decoder, data)
    same = py[0] == c[0] and (py[1] == c[1] or not any(w in (py[1], c[1]) for w in _SHARED))
    return None if same else f"{name}: rozgen {py[0]} {py[1]!r}, C {c[0]} {c[1]!r}"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--root", required=True, type=Path)
    p.add_argument("--decoder", required=True)
    p.add_argument("--toml-test")
    p.add_argument("--work", type=Path)
    p.add_argument("--mutations", type=int, default=2)
    args = p.parse_args()

    work = args.work or Path(tempfile.mkdtemp(prefix="roz-agreement-"))
    files: list[tuple[str, Path]] = []
    if args.toml_test and os.path.exists(args.toml_test):
        cases = work / "toml-test"
        if not cases.exists():
            subprocess.run([args.toml_test, "-copy", str(cases), "-toml", "1.0.0"], check=True,
                           capture_output=True)
        files += [(str(f.relative_to(work)), f) for f in sorted(cases.rglob("*.toml"))]
    else:
        print("toml-test is not installed: the shared vectors only")
    for pattern in ("test/vectors/*/*.toml", "manifests/*.toml", "manifests/invalid/*.toml"):
        files += [(str(f.relative_to(args.root)), f) for f in sorted(args.root.glob(pattern))]

    jobs = []
    for name, path in files:
        for i, data in enumerate(_variants(name, path.read_bytes(), args.mutations)):
            jobs.append((len(jobs), f"{name}#{i}" if i else name, data))
    scratch = work / "scratch"
    scratch.mkdir(parents=True, exist_ok=True)
    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        results = list(pool.map(lambda job: _check(job, args.decoder, scratch), jobs))
    failed = [r for r in results if r is not None]
    for line in failed:
        print("DIFFERS", line)
    print(f"{len(files)} files, {len(jobs)} cases with variants, {len(failed)} disagreeing")
    return 1 if failed or not jobs else 0


if __name__ == "__main__":
    sys.exit(main())
