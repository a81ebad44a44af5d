#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Fuzz rozgen with random and mutated robot.toml files.

    rozgen_fuzz.py [--seconds N] [--work DIR] [--seed N] [--engine atheris|random]
                   SEED...

SEED is a robot.toml or a folder of them (manifests/, manifests/invalid/,
...). Each input is run through rozgen in-process, in one of three modes
picked from the input (``--check``, ``--json``, or a full generation into a
scratch folder). rozgen must never raise (a traceback is a finding) and must
exit 0 or 2; nothing else is checked here (the pytest suite checks what the
messages say).

Inputs are made two ways, mixed: libFuzzer's byte-level mutations of the
file (with a dictionary of TOML tokens and rozgen's keys), and
structure-aware mutations: the file is parsed, one value in the document
changes (type, size, sign, NaN, Inf, a huge integer, an unknown key, a
missing key, a channel copied or dropped, ...) and it is written back as
TOML. With atheris installed (pinned in tools/requirements.txt) the search
is coverage-guided over rozgen and tomllib; without it, a seeded random
loop does the same mutations blind.

Exit status: 0 when the time ran out without a finding, 1 on a finding (the
input is saved in WORK/findings/ and the traceback printed), 2 on a usage
error.
"""

import argparse
import contextlib
import hashlib
import io
import json
import math
import os
import random
import shutil
import sys
import time
import traceback
from pathlib import Path

DEFAULT_SEED = 20260601

# Tokens for libFuzzer's dictionary: TOML syntax and rozgen's vocabulary.
DICTIONARY = [
    "[manifest]", "[[manifest.commands]]", "[[manifest.states]]", "[hardware]",
    "[hardware.params]", "robot_id", "robot_class", "control_rate_hz", "name",
    "interface_type", "unit", "limits", "default", "max_rate_of_change",
    "position_state_index", "limit_margin", "port", "joints", "position", "velocity", "effort",
    "stiffness", "damping", "acceleration", "orientation", "nan", "inf", "-inf",
    "+inf", "1e309", "-0.0", "9223372036854775808", "-9223372036854775809", "0x7f",
    "0o17", "0b1", "1_000", "true", "false", '"""', "'''", "\\u0000", "\\U0001F600",
    " = ", "[", "]", "{", "}", ",", ".", "\n", "#", "1979-05-27T07:32:00Z",
]


class Finding(Exception):
    """rozgen did something it must not: raised, or exited other than 0/2."""


# ---- running rozgen --------------------------------------------------------

class Runner:
    def __init__(self, work: Path) -> None:
        from rozgen import checker, cli  # imported late: atheris instruments it first
        # the rules' program (roz's C loader, roz_manifest_json): found or
        # built once, not on every run
        os.environ[checker.ENV] = checker.find()
        self.cli = cli
        self.work = work
        self.input = work / "robot.toml"
        self.out = work / "out"
        self.runs = 0

    def __call__(self, data: bytes) -> None:
        self.runs += 1
        self.input.write_bytes(data)
        mode = hashlib.sha1(data).digest()[0] % 3
        if mode == 0:
            argv = ["--check", str(self.input)]
        elif mode == 1:
            argv = ["--json", str(self.input)]
        else:
            shutil.rmtree(self.out, ignore_errors=True)
            argv = ["-o", str(self.out), "--registry", str(self.input)]
        sink = io.StringIO()
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            try:
                rc = self.cli.main(argv)
            except SystemExit as e:  # argparse
                rc = e.code
        if rc not in (0, 2):
            raise Finding(f"rozgen {' '.join(argv)} exited {rc!r}:\n{sink.getvalue()}")


# ---- structure-aware mutation ----------------------------------------------

def _toml_key(k: str) -> str:
    if k and all(c.isalnum() or c in "_-" for c in k):
        return k
    return json.dumps(k, ensure_ascii=False)


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"
    return json.dumps(str(v))


def to_toml(doc: dict) -> str:
    """A TOML document for a parsed one (tables, arrays of tables, values)."""
    lines: list[str] = []

    def table(prefix: str, d: dict) -> None:
        nested = []
        for k, v in d.items():
            if isinstance(v, dict):
                nested.append((k, v, False))
            elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
                nested.append((k, v, True))
            else:
                lines.append(f"{_toml_key(k)} = {_toml_value(v)}")
        for k, v, many in nested:
            name = f"{prefix}.{_toml_key(k)}" if prefix else _toml_key(k)
            for item in (v if many else [v]):
                lines.append("")
                lines.append(f"[[{name}]]" if many else f"[{name}]")
                table(name, item)

    table("", doc)
    return "\n".join(lines) + "\n"


WEIRD_VALUES = [
    0, -1, 1, 2**31, 2**63 - 1, -(2**63), 2**64, 10**30, 0.0, -0.0, 1e-320, 1e308, -1e308,
    math.nan, math.inf, -math.inf, 0.5, True, False, "", "x", "a" * 300, "joint/velocity",
    "\u0000", "é/ü", "velocity", "position", "bogus", [], [1.0], [2.0, -2.0], [-1.0, 1.0],
    [-1.0, 1.0, 3.0], ["a", "b"], [math.nan, 1.0], [-math.inf, math.inf], {}, {"x": 1},
]


def _containers(node, path=()):
    """Every (container, key) pair in the document."""
    if isinstance(node, dict):
        for k in list(node):
            yield node, k
            yield from _containers(node[k], path + (k,))
    elif isinstance(node, list):
        for i in range(len(node)):
            yield node, i
            yield from _containers(node[i], path + (i,))


def mutate_doc(doc: dict, rnd: random.Random) -> dict:
    spots = list(_containers(doc))
    op = rnd.randrange(9)
    if not spots or op == 0:
        # a whole channel list grown past the maxima, or emptied
        man = doc.setdefault("manifest", {})
        if not isinstance(man, dict):
            return doc
        key = rnd.choice(["commands", "states"])
        chans = man.get(key)
        if isinstance(chans, list) and chans and rnd.random() < 0.7:
            man[key] = [dict(chans[i % len(chans)]) if isinstance(chans[i % len(chans)], dict)
                        else chans[i % len(chans)] for i in range(rnd.choice([2, 300, 5000]))]
        else:
            man[key] = []
        return doc
    parent, key = rnd.choice(spots)
    value = parent[key]
    if op == 1:
        parent[key] = rnd.choice(WEIRD_VALUES)
    elif op == 2 and isinstance(parent, dict):
        del parent[key]
    elif op == 3 and isinstance(parent, dict):
        parent[rnd.choice(["limit", "defualt", "max_rate", "extra", key + "_"])] = value
    elif op == 4 and isinstance(value, (int, float)) and not isinstance(value, bool):
        parent[key] = rnd.choice([-value, value * 1e6, value + 1, value - 1, float(value),
                                  int(value) if math.isfinite(value) else 0, math.nextafter(value, math.inf)])
    elif op == 5 and isinstance(value, list):
        if value and rnd.random() < 0.5:
            value.append(value[rnd.randrange(len(value))])
        else:
            value.reverse()
    elif op == 6 and isinstance(value, str):
        parent[key] = rnd.choice([value * 3, value.upper(), value + "/x", value[:1],
                                  value.replace("_", "-"), value + "\u00e9"])
    elif op == 7 and isinstance(parent, list) and len(parent) > 1:
        parent.insert(rnd.randrange(len(parent)), parent.pop(rnd.randrange(len(parent))))
    else:
        parent[key] = [value, value] if rnd.random() < 0.5 else {"v": value}
    return doc


def structural(data: bytes, rnd: random.Random) -> bytes | None:
    import tomllib  # late, so that atheris can instrument it first

    try:
        doc = tomllib.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError, RecursionError, ValueError):
        return None
    for _ in range(1 + rnd.randrange(3)):
        doc = mutate_doc(doc, rnd)
    try:
        return to_toml(doc).encode("utf-8")
    except (RecursionError, ValueError):
        return None


def bytewise(data: bytes, rnd: random.Random) -> bytes:
    b = bytearray(data)
    for _ in range(1 + rnd.randrange(4)):
        op = rnd.randrange(5)
        pos = rnd.randrange(len(b) + 1)
        if op == 0 and b:
            b[min(pos, len(b) - 1)] ^= 1 << rnd.randrange(8)
        elif op == 1:
            b[pos:pos] = rnd.choice(DICTIONARY).encode()
        elif op == 2 and b:
            del b[pos:pos + rnd.randrange(1, 16)]
        elif op == 3 and b:
            start = rnd.randrange(len(b))
            b[pos:pos] = b[start:start + rnd.randrange(1, 64)]
        else:
            b[pos:pos] = bytes(rnd.randrange(256) for _ in range(rnd.randrange(1, 8)))
    return bytes(b)


# ---- engines ---------------------------------------------------------------

def seeds_from(paths: list[str]) -> list[bytes]:
    out = []
    for p in map(Path, paths):
        files = sorted(p.glob("*.toml")) if p.is_dir() else [p]
        out += [f.read_bytes() for f in files if f.is_file()]
    return out


def save_finding(work: Path, data: bytes) -> Path:
    d = work / "findings"
    d.mkdir(parents=True, exist_ok=True)
    f = d / ("finding-" + hashlib.sha1(data).hexdigest()[:16] + ".toml")
    f.write_bytes(data)
    return f


def run_random(args, seeds: list[bytes], runner: Runner) -> int:
    rnd = random.Random(args.seed)
    deadline = time.monotonic() + args.seconds
    for s in seeds:  # every seed as it is, first
        runner(s)
    while time.monotonic() < deadline:
        data = rnd.choice(seeds)
        if rnd.random() < 0.5:
            data = structural(data, rnd) or bytewise(data, rnd)
        else:
            data = bytewise(data, rnd)
        try:
            runner(data)
        except Exception:  # noqa: BLE001 - any exception is the finding
            traceback.print_exc()
            print(f"rozgen_fuzz: finding saved as {save_finding(args.work, data)}")
            return 1
    print(f"rozgen_fuzz: random engine, seed {args.seed}: {runner.runs} runs, no finding")
    return 0


def _dict_entry(token: str) -> str:
    """A libFuzzer dictionary line: printable ASCII, escaped quotes and
    backslashes, and hex escapes for every other byte."""
    out = []
    for b in token.encode("utf-8"):
        c = chr(b)
        out.append("\\" + c if c in '\\"' else c if 0x20 <= b < 0x7f else f"\\x{b:02x}")
    return '"' + "".join(out) + '"'


def run_atheris(args, seeds: list[bytes]) -> int:
    import atheris

    with atheris.instrument_imports(include=["rozgen", "tomllib"]):
        import rozgen.cli  # noqa: F401
    runner = Runner(args.work)
    rnd = random.Random(args.seed)
    corpus = args.work / "corpus"
    corpus.mkdir(parents=True, exist_ok=True)
    for s in seeds:
        (corpus / ("seed-" + hashlib.sha1(s).hexdigest()[:16])).write_bytes(s)
    dict_file = args.work / "toml.dict"
    dict_file.write_text("".join(_dict_entry(t) + "\n" for t in DICTIONARY))
    findings = args.work / "findings"
    findings.mkdir(parents=True, exist_ok=True)

    def mutator(data: bytes, max_size: int, seed: int) -> bytes:
        rnd.seed(seed)
        if rnd.random() < 0.5:
            out = structural(data, rnd)
            if out is not None and len(out) <= max_size:
                return out
        return atheris.Mutate(data, max_size)

    atheris.Setup([sys.argv[0], f"-max_total_time={args.seconds}", f"-seed={args.seed}",
                   f"-dict={dict_file}", "-timeout=20", "-max_len=65536",
                   "-print_final_stats=1", f"-artifact_prefix={findings}/", str(corpus)],
                  runner, custom_mutator=mutator)
    atheris.Fuzz()  # exits the process
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("seeds", nargs="+", metavar="SEED")
    ap.add_argument("--seconds", type=int, default=15,
                    help="how long to run (the environment's ROZ_FUZZ_SECONDS wins)")
    ap.add_argument("--work", type=Path, default=Path("rozgen-fuzz"))
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED)
    ap.add_argument("--engine", choices=["atheris", "random"])
    args = ap.parse_args()
    if os.environ.get("ROZ_FUZZ_SECONDS"):
        args.seconds = int(os.environ["ROZ_FUZZ_SECONDS"])
    args.work = args.work.resolve()
    args.work.mkdir(parents=True, exist_ok=True)
    seeds = seeds_from(args.seeds)
    if not seeds:
        ap.error("no robot.toml among the seeds")
    engine = args.engine
    if engine is None:
        try:
            import atheris  # noqa: F401
            engine = "atheris"
        except ImportError:
            engine = "random"
    print(f"rozgen_fuzz: {engine} engine, {len(seeds)} seeds, {args.seconds} s, "
          f"seed {args.seed}", flush=True)
    if engine == "atheris":
        return run_atheris(args, seeds)
    return run_random(args, seeds, Runner(args.work))


if __name__ == "__main__":
    sys.exit(main())
