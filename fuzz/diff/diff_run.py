# SPDX-License-Identifier: Apache-2.0
"""diff_run: the differential test of roz's wasm3 against wabt's reference
interpreter. For each seed, wasmgen.py writes a module (.wat), wat2wasm
assembles it, wasm-validate must accept it, then roz_wasm_run (roz's
validator, then roz's patched wasm3; test/diff/roz_wasm_run.c) and
`wasm-interp --run-all-exports --dummy-import-func` each call every exported
function without parameters, in export order, imports returning zero. The
two transcripts are compared line by line:

  - integers by value; exported float bits (exports named *_f32 / *_f64 that
    return i32 / i64) and float results by bits, every NaN one class
    (payloads and signs may differ: WebAssembly allows it);
  - traps by class (unreachable, div-zero, int-overflow, conversion,
    oob-memory, table, stack, fuel); wasm3 and wasm-interp word them
    differently;
  - "one engine ran out of stack" (or both, at different depths) is a
    resource difference, counted and never a failure; so is any difference
    in the calls after it, whose state may then differ.

A finding: a result or trap mismatch, a crash or hang of roz_wasm_run, roz's
validator refusing a module wasm-validate accepts, or wasm3 refusing one
roz accepts. Findings whose class allowlist.txt lists (known wasm3 bugs
with a fix under way) are reported but do not fail; each allowlist entry
names a class that classify() recognises from the module and the mismatch.
Every finding keeps its module in WORK/findings/. The exit status is 1 when
an unexplained finding was seen.

Also: --corpus DIR writes each accepted module's .wasm there (seeds for the
fuzz_controller libFuzzer target); --modules DIR runs the .wasm files of DIR
(e.g. wasm-tools smith output) instead of, or as well as, generated seeds.

Usage (bounded, as the ctest runs it):
  diff_run.py --runner build/test/diff/roz_wasm_run --seeds 1:200 --work DIR
Long: add --seconds N and a wide seed range (fuzz/README.md).
"""
import argparse
import concurrent.futures
import os
import re
import shutil
import struct
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import wasmgen  # noqa: E402

LINE = re.compile(r"^(\S+)\(\) =>(?: (.*))?$")

TRAP_CLASSES = [
    ("stack", ("call stack exhausted", "value stack exhausted", "stack overflow",
               "native stack limit")),
    ("fuel", ("fuel exhausted",)),
    ("unreachable", ("unreachable",)),
    ("div-zero", ("divide by zero",)),
    ("int-overflow", ("integer overflow",)),
    ("conversion", ("invalid conversion",)),
    ("oob-memory", ("out of bounds memory",)),
    ("table", ("undefined element", "null table element", "uninitialized table element",
               "undefined table index", "indirect call", "table index")),
]


def trap_class(msg):
    for cls, keys in TRAP_CLASSES:
        if any(k in msg for k in keys):
            return cls
    return "other:" + msg


def norm_value(name, v):
    """A comparable form of one result: ('trap', class) or ('val', text)."""
    if v is None or v == "":
        return ("val", "void")
    if v.startswith("error: "):
        return ("trap", trap_class(v[7:]))
    t, _, x = v.partition(":")
    if t in ("i32", "i64"):
        n = int(x)
        if name.endswith("_f32") and t == "i32":
            return ("val", "f32:" + f32_class(n))
        if name.endswith("_f64") and t == "i64":
            return ("val", "f64:" + f64_class(n))
        return ("val", "%s:%d" % (t, n))
    if t in ("f32", "f64"):
        if x.startswith("0x"):        # roz_wasm_run: bits
            bits = int(x, 16)
            if t == "f32":
                val = struct.unpack("<f", struct.pack("<I", bits))[0]
            else:
                val = struct.unpack("<d", struct.pack("<Q", bits))[0]
            return ("val", "%s:%s" % (t, "nan" if val != val else "%f" % val))
        return ("val", "%s:%s" % (t, "nan" if "nan" in x else x))   # wasm-interp: %f text
    return ("val", v)


def f32_class(bits):
    if (bits >> 23) & 0xFF == 0xFF and bits & 0x7FFFFF:
        return "nan"
    return "0x%08x" % bits


def f64_class(bits):
    if (bits >> 52) & 0x7FF == 0x7FF and bits & 0xFFFFFFFFFFFFF:
        return "nan"
    return "0x%016x" % bits


def transcript(text):
    out = []
    for line in text.splitlines():
        m = LINE.match(line)
        if m:
            out.append((m.group(1), m.group(2)))
    return out


def run(cmd, timeout):
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
        return "timeout", out, ""


class Result:
    def __init__(self, label):
        self.label = label
        self.calls = 0
        self.resource = 0
        self.findings = []      # (kind, detail)
        self.skipped = None     # why the module was not compared
        self.w3 = self.wi = ()  # the transcripts


def compare(res, w3, wi):
    """Compare the transcripts; fills res.findings."""
    after_stack = False
    wi_names = [n for n, _ in wi]
    for i, (name, v_i) in enumerate(wi):
        if i >= len(w3):
            res.findings.append(("missing", "%s(): wasm-interp %s, roz_wasm_run printed nothing"
                                 % (name, v_i)))
            break
        name3, v_3 = w3[i]
        if name3 != name:
            res.findings.append(("order", "call %d: %s vs %s" % (i, name3, name)))
            break
        res.calls += 1
        a, b = norm_value(name, v_3), norm_value(name, v_i)
        stack = ("trap", "stack") in (a, b)
        if a == b and not stack:
            continue
        if stack:
            after_stack = True
            if a != b:
                res.resource += 1
            continue
        if after_stack:
            res.resource += 1
            continue
        res.findings.append(("mismatch", "%s(): wasm3 %s, wasm-interp %s" % (
            name, "/".join(a), "/".join(b))))
    if len(w3) > len(wi_names) and not res.findings:
        res.findings.append(("extra", "roz_wasm_run printed more calls than wasm-interp"))


def check_module(args, label, wasm, wat=None):
    """Runs one module through both engines; returns a Result."""
    res = Result(label)
    rc, out, err = run([args.wasm_validate, wasm], 30)
    if rc != 0:
        if wat is not None:
            res.findings.append(("generator", "wasm-validate refuses it: " + (err or out).strip()))
        else:
            res.skipped = "invalid"
        return res
    rc3, out3, err3 = run([args.runner, wasm], args.timeout)
    if rc3 == 2:
        why = out3.strip()
        if wat is None and not args.strict_refusals:
            res.skipped = "roz-refused: " + why
        else:
            res.findings.append(("roz-refused", why))
        return res
    if rc3 == 3:
        res.findings.append(("wasm3-refused", out3.strip()))
        return res
    if rc3 == "timeout":
        res.findings.append(("hang", "roz_wasm_run did not finish in %ds" % args.timeout))
        return res
    if rc3 != 0:
        res.findings.append(("crash", "roz_wasm_run exit %s: %s" % (rc3, err3.strip()[-500:])))
        # compare what it printed before the crash too
    rci, outi, _ = run([args.wasm_interp, "--run-all-exports", "--dummy-import-func", wasm],
                       args.timeout)
    if rci == "timeout":
        res.skipped = "wasm-interp timeout"
        return res
    w3, wi = transcript(out3), transcript(outi)
    res.w3, res.wi = w3, wi
    if rc3 != 0:
        wi = wi[:len(w3)]
    compare(res, w3, wi)
    return res


# Classes of known wasm3 bugs whose fixes other engineers own. A class is
# recognised by regenerating the same seed with the generator's equivalent
# form for that class (wasmgen.generate(seed, neutral=[class]): the same
# program, same random choices, without the construct): when that module
# shows no finding at all, the class explains the finding. Nothing else is
# ever allowlisted, so a second bug in the same module still fails.
#
# "stack-overflow-heap" is recognised from the transcripts instead: the only
# finding is a crash of roz_wasm_run, and wasm3 had trapped on stack
# overflow before it crashed, or crashed in the call where wasm-interp ran
# out of stack (wasm3 writes a call's arguments past the end of its value
# stack before checking, and corrupts its heap).
NEUTRAL_CLASSES = ("float-branch",)
ALLOW_CLASSES = {
    "float-branch": "a br/br_if/br_table carrying an f32/f64 value out of a block while "
                    "other operands sit below it on that block's stack",
    "stack-overflow-heap": "a crash after or during a wasm3 stack overflow",
}


def stack_overflow_crash(res):
    if [k for k, _ in res.findings] != ["crash"]:
        return False
    if any(v and trap_class(v) == "stack" for _, v in res.w3):
        return True
    n = len(res.w3)
    return n < len(res.wi) and (res.wi[n][1] or "").startswith("error:") and \
        trap_class(res.wi[n][1]) == "stack"


def classify(args, allow, seed, res):
    """The allowlisted class that explains the findings of res (of seed), or None."""
    if "stack-overflow-heap" in allow and stack_overflow_crash(res):
        return "stack-overflow-heap"
    for cls in allow:
        if cls in NEUTRAL_CLASSES and seed is not None:
            nres, _, _, _ = gen_one(args, seed, (cls,))
            if not nres.findings and not nres.skipped:
                return cls
            if "stack-overflow-heap" in allow and stack_overflow_crash(nres):
                return cls + "+stack-overflow-heap"
    return None


def load_allowlist(path):
    allow = {}
    if path and os.path.exists(path):
        with open(path) as f:
            for line in f:
                line = line.split("#", 1)[0].strip()
                if line:
                    cls, _, reason = line.partition(" ")
                    if cls not in ALLOW_CLASSES:
                        sys.exit("allowlist %s: unknown class %s" % (path, cls))
                    allow[cls] = reason.strip()
    return allow


def gen_one(args, seed, neutral=()):
    d = os.path.join(args.work, "mod")
    tag = "".join("-" + n for n in neutral)
    wat = os.path.join(d, "s%d%s.wat" % (seed, tag))
    wasm = os.path.join(d, "s%d%s.wasm" % (seed, tag))
    text = wasmgen.generate(seed, neutral)
    with open(wat, "w") as f:
        f.write(text)
    rc, out, err = run([args.wat2wasm, wat, "-o", wasm], 30)
    if rc != 0:
        res = Result("seed %d" % seed)
        res.findings.append(("generator", "wat2wasm refuses it: " + err.strip()[:1000]))
        return res, wat, None, text
    res = check_module(args, "seed %d" % seed, wasm, wat)
    return res, wat, wasm, text


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runner", required=True, help="roz_wasm_run")
    ap.add_argument("--seeds", default="1:100", help="FIRST:LAST, inclusive")
    ap.add_argument("--seconds", type=float, default=0,
                    help="stop after this long (0: run every seed)")
    ap.add_argument("--modules", help="also run every .wasm in this folder (e.g. smith's)")
    ap.add_argument("--work", required=True)
    ap.add_argument("--corpus", help="copy every module roz accepts here (fuzz seeds)")
    ap.add_argument("--allowlist", default=os.path.join(HERE, "allowlist.txt"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=int, default=60)
    ap.add_argument("--strict-refusals", action="store_true",
                    help="a --modules file roz refuses is a finding too")
    ap.add_argument("--wat2wasm", default="wat2wasm")
    ap.add_argument("--wasm-validate", default="wasm-validate")
    ap.add_argument("--wasm-interp", default="wasm-interp")
    args = ap.parse_args()

    first, _, last = args.seeds.partition(":")
    seeds = range(int(first), int(last or first) + 1)
    os.makedirs(os.path.join(args.work, "mod"), exist_ok=True)
    fdir = os.path.join(args.work, "findings")
    shutil.rmtree(fdir, ignore_errors=True)
    os.makedirs(fdir)
    if args.corpus:
        os.makedirs(args.corpus, exist_ok=True)
    allow = load_allowlist(args.allowlist)

    start = time.monotonic()
    n_mod = n_calls = n_res = n_skipped = 0
    failed, allowed = [], []

    def jobs():
        for s in seeds:
            yield ("seed", s)
        if args.modules:
            for name in sorted(os.listdir(args.modules)):
                if name.endswith(".wasm"):
                    yield ("file", os.path.join(args.modules, name))

    def work(job):
        kind, x = job
        if kind == "seed":
            res, wat, wasm, text = gen_one(args, x)
            cls = classify(args, allow, x, res) if res.findings else None
            return res, wat, wasm, cls
        res = check_module(args, x, x)
        return res, None, x, classify(args, allow, None, res) if res.findings else None

    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as ex:
        pending = set()
        it = jobs()
        done_all = False
        while True:
            while not done_all and len(pending) < 2 * args.jobs:
                if args.seconds and time.monotonic() - start > args.seconds:
                    done_all = True
                    break
                try:
                    pending.add(ex.submit(work, next(it)))
                except StopIteration:
                    done_all = True
            if not pending:
                break
            done, pending = concurrent.futures.wait(pending,
                                                    return_when=concurrent.futures.FIRST_COMPLETED)
            for fut in done:
                res, wat, wasm, cls = fut.result()
                n_mod += 1
                n_calls += res.calls
                n_res += res.resource
                if res.skipped:
                    n_skipped += 1
                    continue
                if args.corpus and wasm and not any(k in ("roz-refused", "generator")
                                                    for k, _ in res.findings):
                    shutil.copy(wasm, os.path.join(args.corpus, os.path.basename(wasm)))
                if not res.findings:
                    continue
                keep = os.path.join(fdir, os.path.basename(wat or wasm))
                shutil.copy(wat or wasm, keep)
                line = "%s: %s (module %s)" % (res.label, "; ".join(
                    "%s: %s" % f for f in res.findings[:3]), keep)
                if cls:
                    allowed.append("%s [allowlisted: %s]" % (line, cls))
                else:
                    failed.append(line)
                    print("FINDING " + line, flush=True)

    dt = time.monotonic() - start
    for line in allowed:
        print("known   " + line)
    print("diff_run: %d modules (%d skipped), %d calls compared, %d resource (stack) "
          "differences, %d allowlisted, %d findings, %.1f s, %.1f modules/s" % (
              n_mod, n_skipped, n_calls, n_res, len(allowed), len(failed), dt,
              n_mod / dt if dt else 0))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
