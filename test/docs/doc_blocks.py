# SPDX-License-Identifier: Apache-2.0
"""test/docs/doc_blocks.py: every ```sh, ```c and ```rust block of README.md
and docs/ is run or compiled, or says why it cannot be.

    doc_blocks.py --source DIR --build DIR --work DIR [--cc CC] [--clang CLANG]
                  [--include DIR ...] [--check-only] [FILE ...]
    doc_blocks.py --source DIR --work DIR --installed PREFIX [--forbid DIR ...] FILE

The line before each such block (blank lines aside) is one marker:

    <!-- test: docs_blocks run -->            sh: run with bash -e
    <!-- test: docs_blocks file NAME -->      any block: written to NAME
    <!-- test: docs_blocks wasm32 MANIFEST --> c: a controller, built for
                                              wasm32 against the SDK and
                                              MANIFEST's channel header
    <!-- test: docs_blocks host -->           c: compiled natively against
                                              roz's public headers
    <!-- test: docs_firmware -->              c: compiled and run by the
                                              docs_firmware test (CMakeLists)
    <!-- test: getting_started run -->        sh: run from the installed
    <!-- test: getting_started file NAME -->  package (--installed, below)
    <!-- not run: REASON -->                  not runnable here, and why

Each page's blocks run in order in a fresh folder of their own under
--work, which holds a link to every top-level entry of the source tree
and `build`, a link to the build tree: `build/tools/rozrun/rozrun`,
`.venv/bin/rozgen` and `manifests/ur5.toml` mean there what they mean in a
checkout after `make build`. A block without a marker, a marker without a
block, or a block that fails fails the test, naming the file and line.
Blocks of other languages (toml, cmake, text) need no marker. A run block
finds RUSTC and CARGO in its environment where the test was given them (a
rustc with the wasm32 target, docs/rust.md).

With --installed PREFIX (the docs_getting_started test, run_installed.cmake)
only the `getting_started` blocks of FILE run, in order, in an empty folder
--work with no link to any tree, with PREFIX/bin first on PATH, PATH cleared
of every --forbid folder (the source tree, the build tree, the virtual
environment) and VIRTUAL_ENV, PYTHONPATH, ROZGEN_EXECUTABLE and
CMAKE_PREFIX_PATH unset: what a user has after `make install`. Such a
page takes no `docs_blocks` marker, and a `getting_started` block that
names a path of the checkout (`.venv/`, `build/tools/`, `examples/`, ...,
or a --forbid folder) fails in either mode.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

MARK = re.compile(r"^<!--\s*(test:\s*(\S+)(.*?)|not run:\s*(.+?))\s*-->\s*$")
FENCE = re.compile(r"^\s*```(\S*)\s*$")
CHECKED = {"sh", "c", "rust"}
# A path into a checkout, as a block run from the installed package must not
# name one: the venv, the build tree's parts, the source tree's folders.
CHECKOUT = re.compile(r"(?<![\w./-])(\.venv|build/(tools|examples|manifests|lib|test|ports)"
                      r"|examples|tools|sdk|codegen|manifests|ports|hal|lib/include|test)/")


class Block:
    def __init__(self, path, line, lang, text, marker):
        self.path, self.line, self.lang, self.text, self.marker = path, line, lang, text, marker

    def where(self):
        return f"{self.path}:{self.line}"


def parse(path: Path, rel: str):
    """The fenced blocks of one file, each with the marker before it."""
    blocks, problems = [], []
    lines = path.read_text(encoding="utf-8").splitlines()
    i, pending = 0, None
    while i < len(lines):
        line = lines[i].strip()
        m = MARK.match(line)
        f = FENCE.match(lines[i])
        if m:
            if pending:
                problems.append(f"{rel}:{pending[0]}: marker without a block after it")
            pending = (i + 1, m)
        elif f:
            lang, start = f.group(1), i + 1
            body = []
            i += 1
            while i < len(lines) and not lines[i].lstrip().startswith("```"):
                body.append(lines[i])
                i += 1
            marker = pending[1] if pending else None
            if lang in CHECKED or marker:
                blocks.append(Block(rel, start, lang, "\n".join(body) + "\n", marker))
            pending = None
        elif line and pending and not line.startswith("<!--"):
            problems.append(f"{rel}:{pending[0]}: marker not followed by a block")
            pending = None
        i += 1
    if pending:
        problems.append(f"{rel}:{pending[0]}: marker at the end of the file")
    return blocks, problems


def workdir(args, rel: str) -> Path:
    d = args.work / re.sub(r"[^A-Za-z0-9]+", "_", rel)
    if d.exists():
        shutil.rmtree(d)
    d.mkdir(parents=True)
    if args.installed:                          # nothing of the trees in reach
        return d
    for entry in args.source.iterdir():
        if entry.name not in ("build", ".git"):
            (d / entry.name).symlink_to(entry)
    (d / "build").symlink_to(args.build)
    return d


def run(cmd, cwd, what, env=None):
    p = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, timeout=120)
    if p.returncode != 0:
        return f"{what}: exit {p.returncode}\n{p.stdout}"
    return None


def installed_env(args):
    """The environment of a user who installed roz into args.installed."""
    env = dict(os.environ)
    for k in ("VIRTUAL_ENV", "PYTHONPATH", "ROZGEN_EXECUTABLE", "CMAKE_PREFIX_PATH"):
        env.pop(k, None)
    keep = [p for p in env.get("PATH", "").split(":")
            if p and not any(Path(p).resolve() == f or f in Path(p).resolve().parents
                             for f in args.forbid)]
    env["PATH"] = ":".join([str(args.installed / "bin")] + keep)
    return env


def checkout_reference(args, b: Block):
    """What in a getting_started block names the checkout, or None."""
    m = CHECKOUT.search(b.text)
    if m:
        return f"names {m.group(0)!r}, a path of the checkout: it must run from the installed package"
    for f in args.forbid:
        if str(f) in b.text:
            return f"names {f}, which the installed package must not need"
    return None


def do_block(args, b: Block, cwd: Path, n: int):
    """Runs one block; returns None or what went wrong."""
    kind = b.marker.group(2) if b.marker.group(2) else None
    words = (b.marker.group(3) or "").split()
    if b.marker.group(4):                       # not run: REASON
        return None
    if kind == "docs_firmware":
        return None if b.lang == "c" else "docs_firmware takes a c block"
    if kind not in ("docs_blocks", "getting_started") or not words:
        return f"unknown marker {b.marker.group(0)!r}"
    if args.installed and kind != "getting_started":
        return "a page run from the installed package takes getting_started markers only"
    if kind == "getting_started":
        if not (words == ["run"] and b.lang == "sh" or words[0] == "file" and len(words) == 2):
            return f"marker {b.marker.group(0)!r} does not fit a {b.lang or 'plain'} block"
    mode = words[0]
    if mode == "file" and len(words) == 2:
        target = cwd / words[1]
        real = target.parent.resolve()
        if real != cwd.resolve() and cwd.resolve() not in real.parents:
            return f"file {words[1]}: outside the page's folder (in the source tree?)"
        target.parent.mkdir(parents=True, exist_ok=True)
        if target.is_symlink():
            target.unlink()
        target.write_text(b.text, encoding="utf-8")
        return None
    if mode == "run" and b.lang == "sh":
        script = cwd / f".block{n}.sh"
        script.write_text(b.text, encoding="utf-8")
        env = installed_env(args) if args.installed else dict(os.environ)
        return run(["bash", "-e", "-o", "pipefail", script.name], cwd, "the block", env)
    if mode == "host" and b.lang == "c":
        src = cwd / f".block{n}.c"
        src.write_text(b.text, encoding="utf-8")
        inc = [f"-I{d}" for d in args.include]
        return run([args.cc, "-std=c11", "-Wall", "-Wextra", "-Werror", "-fsyntax-only", *inc,
                    src.name], cwd, "compiling it")
    if mode == "wasm32" and b.lang == "c" and len(words) == 2:
        src = cwd / f".block{n}.c"
        src.write_text(b.text, encoding="utf-8")
        gen = cwd / f".gen{n}"
        err = run([str(args.rozgen), words[1], "-o", str(gen)], cwd, "rozgen")
        if err:
            return err
        sdk = args.source / "sdk" / "include"
        # the flags of roz_add_wasm_controller() (cmake/RozWasm.cmake)
        return run([args.clang, "--target=wasm32", "-O2", "-nostdlib", "-fno-builtin", "-std=c11",
                    "-Wall", "-Wextra", "-Werror", f"-I{sdk}",
                    f"-I{args.source / 'lib' / 'math'}", f"-I{gen}", "-Wl,--no-entry",
                    "-Wl,--strip-all", "-Wl,-z,stack-size=16384", "-o", f".block{n}.wasm",
                    src.name], cwd, "clang wasm32")
    return f"marker {b.marker.group(0)!r} does not fit a {b.lang or 'plain'} block"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--source", type=Path, required=True)
    p.add_argument("--build", type=Path)
    p.add_argument("--work", type=Path)
    p.add_argument("--cc", default="cc")
    p.add_argument("--clang", default="clang")
    p.add_argument("--rozgen", type=Path)
    p.add_argument("--include", action="append", default=[])
    p.add_argument("--check-only", action="store_true", help="check the markers, run nothing")
    p.add_argument("--installed", type=Path, metavar="PREFIX",
                   help="run FILE's getting_started blocks from this installed prefix alone")
    p.add_argument("--forbid", type=Path, action="append", default=[],
                   help="a folder the installed run must not reach (repeatable)")
    p.add_argument("files", nargs="*")
    args = p.parse_args()
    args.source = args.source.resolve()
    if args.build:
        args.build = args.build.resolve()
    if args.work:
        args.work = args.work.resolve()
    args.forbid = [f.resolve() for f in args.forbid]
    if args.installed:
        args.installed = args.installed.resolve()
        if not args.files or not args.work:
            p.error("--installed takes --work and the FILE to run")
        for f in args.forbid:
            if args.work == f or f in args.work.parents:
                p.error(f"--work {args.work} is inside {f}, which it must not reach")
    files = args.files or ["README.md"] + sorted(
        str(f.relative_to(args.source)) for f in (args.source / "docs").rglob("*.md"))
    failed, ran, skipped = [], 0, []
    for rel in files:
        blocks, problems = parse(args.source / rel, rel)
        failed += problems
        for b in blocks:
            if b.marker is None:
                failed.append(f"{b.where()}: a ```{b.lang} block without a marker "
                              "(test/docs/doc_blocks.py says which)")
            elif b.marker.group(4):
                skipped.append(f"{b.where()}: not run: {b.marker.group(4)}")
            elif b.marker.group(2) == "getting_started" and checkout_reference(args, b):
                failed.append(f"{b.where()}: {checkout_reference(args, b)}")
        if args.check_only or problems or any(b.marker is None for b in blocks):
            continue
        cwd = None
        for n, b in enumerate(blocks):
            if b.marker.group(4) or b.marker.group(2) == "docs_firmware":
                continue
            if b.marker.group(2) == "getting_started" and not args.installed:
                continue                        # run by docs_getting_started
            if args.installed and b.marker.group(2) == "getting_started" \
                    and checkout_reference(args, b):
                break                           # counted above
            if cwd is None:
                cwd = workdir(args, rel)
            err = do_block(args, b, cwd, n)
            ran += 1
            if err:
                failed.append(f"{b.where()}: {err.rstrip()}")
                break                           # later blocks of the page build on it
    if args.installed and ran == 0 and not failed:
        failed.append(f"{', '.join(files)}: no getting_started block to run")
    for s in skipped:
        print(s)
    print(f"doc_blocks: {ran} blocks run or compiled, {len(skipped)} marked not run, "
          f"{len(failed)} failed")
    for f in failed:
        print(f"FAIL {f}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
