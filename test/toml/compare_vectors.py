# SPDX-License-Identifier: Apache-2.0
"""Run every shared robot.toml vector through rozgen and the C reader.

    compare_vectors.py --root REPO --rozgen ROZGEN --c-tool ROZ_MANIFEST_JSON

Good vectors (manifests/*.toml, examples/my_arm/robot.toml, examples/can_leg/leg.toml,
test/vectors/good/*.toml): both exit 0 and print the same JSON, byte for
byte (``rozgen --json`` and ``roz_manifest_json``), and the same identity,
robot_id and interface hash (``--identity``: rozgen computes it from its
model, the C tool from the loaded roz_manifest_t).

Bad vectors (manifests/invalid/*.toml, test/vectors/bad/*.toml): both exit
2 and print the same problems with ``--error-ids``: the same number of
lines, the same rule id on each, and the same text, except that

- a TOML syntax problem needs only the same ``<file>:<line>:<col>`` (the
  wording is each reader's own), except for the refusals that rozgen makes
  itself in the C reader's words (``_SHARED_WORDING``): those are the same
  line, and
- a C line may be cut to ROZ_CFG_PROBLEM_LEN and end in "...", when it is
  a prefix of rozgen's.

The C tool checks a port's own [hardware] keys where the port registered
its rules (roz_add_port_rules(): socketcan, the DDS ports, the mujoco
port's keys that need no model); rozgen runs the same. A bad vector for
the mujoco port that rozgen refuses by the rules that need its model
(rozgen's own) is one the C tool reads (exit 0): the port refuses it at
open, and test_port_vectors checks that it does so in rozgen's words.

Paths are given relative to REPO, from REPO, as in the .expected files.
Exit status 0 when every vector agrees, 1 otherwise.
"""

import argparse
import concurrent.futures
import glob
import os
import re
import subprocess
import sys
import tomllib

_LINE = re.compile(r"^\[(?P<rule>[a-z0-9-]+)\] (?P<text>.*)$")
_SYNTAX = re.compile(r"^(?P<where>.*?:\d+:\d+): ")
# refusals worded alike by both (one reader now: every text is the same)
_SHARED_WORDING = ("integer does not fit in 64 bits", "nested more than")
# ports whose [hardware] keys are checked at open (test_port_vectors), and
# the rules rozgen refuses their keys by
_DDS_PORTS = ("unitree/G1", "agibot/X2", "engineai/PM01", "mujoco")
_DDS_PORT_RULES = ("g1-joint", "g1-channel", "g1-param", "ros2-joint", "ros2-channel",
                   "ros2-param", "mujoco-param", "mujoco-model", "mujoco-joint", "mujoco-imu",
                   "mujoco-effort", "unknown-key")


def _vectors(root: str, patterns: list[str]) -> list[str]:
    found = []
    for pattern in patterns:
        found += sorted(glob.glob(pattern, root_dir=root))
    return found


def _run(cmd: list[str], root: str) -> tuple[int, bytes, bytes]:
    done = subprocess.run(cmd, cwd=root, capture_output=True, timeout=60)
    return done.returncode, done.stdout, done.stderr


def _same_line(ours: str, theirs: str) -> bool:
    a, b = _LINE.match(ours), _LINE.match(theirs)
    if a is None or b is None or a["rule"] != b["rule"]:
        return False
    if a["text"] == b["text"]:
        return True
    if a["rule"] == "toml-syntax":
        if any(w in a["text"] or w in b["text"] for w in _SHARED_WORDING):
            return False
        wa, wb = _SYNTAX.match(a["text"]), _SYNTAX.match(b["text"])
        return wa is not None and wb is not None and wa["where"] == wb["where"]
    return a["text"].endswith("...") and b["text"].startswith(a["text"][:-3])


def _dds_port(path: str, root: str) -> bool:
    """Whether the file's [hardware] port is a DDS port."""
    try:
        with open(os.path.join(root, path), "rb") as f:
            doc = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError):
        return False
    hardware = doc.get("hardware")
    return isinstance(hardware, dict) and hardware.get("port") in _DDS_PORTS


def _check_good(path: str, args) -> tuple[bool, str]:
    rc_py, out_py, err_py = _run(args.rozgen + ["--json", path], args.root)
    rc_c, out_c, err_c = _run([args.c_tool, path], args.root)
    if rc_py != 0:
        return False, f"rozgen refuses it (exit {rc_py}): {err_py.decode(errors='replace')}"
    if rc_c != 0:
        return False, f"C reader refuses it (exit {rc_c}): {err_c.decode(errors='replace')}"
    if out_py != out_c:
        return False, "JSON differs"
    rc_py, id_py, err_py = _run(args.rozgen + ["--identity", path], args.root)
    rc_c, id_c, err_c = _run([args.c_tool, "--identity", path], args.root)
    if rc_py != 0 or rc_c != 0 or id_py != id_c or not id_py:
        return False, (f"identity differs: rozgen {id_py!r} (exit {rc_py}), "
                       f"C {id_c!r} (exit {rc_c})")
    return True, f"same JSON, same identity {id_py.decode().split()[1]}"


def _check_bad(path: str, args) -> tuple[bool, str]:
    rc_py, _, err_py = _run(args.rozgen + ["--check", "--error-ids", path], args.root)
    rc_c, _, err_c = _run([args.c_tool, "--check", "--error-ids", path], args.root)
    ours = err_c.decode("utf-8", errors="replace").splitlines()
    theirs = err_py.decode("utf-8", errors="replace").splitlines()
    if rc_py == 2 and rc_c == 0 and _dds_port(path, args.root):
        rules = [m["rule"] if m else "?" for m in map(_LINE.match, theirs)]
        if rules and set(rules) <= set(_DDS_PORT_RULES):
            return True, f"{len(rules)} x [{rules[0]}...], the port's at open (test_port_vectors)"
        return False, f"rozgen refuses it by other rules than the port's: {sorted(set(rules))}"
    if rc_py != 2 or rc_c != 2:
        return False, f"exit {rc_py} (rozgen), {rc_c} (C), want 2"
    if not theirs or len(ours) != len(theirs):
        return False, f"{len(theirs)} problems (rozgen), {len(ours)} (C)"
    for a, b in zip(ours, theirs):
        if not _same_line(a, b):
            return False, f"differs:\n      C:      {a}\n      rozgen: {b}"
    rule = _LINE.match(theirs[0])["rule"]
    exact = sum(a == b for a, b in zip(ours, theirs))
    return True, f"{len(theirs)} x [{rule}...], {exact} identical"


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--root", required=True, help="the repository")
    p.add_argument("--rozgen", required=True, nargs="+", help="rozgen command")
    p.add_argument("--c-tool", required=True, help="roz_manifest_json")
    args = p.parse_args()
    args.c_tool = os.path.abspath(args.c_tool)

    good = _vectors(args.root, ["manifests/*.toml", "examples/my_arm/robot.toml",
                                "examples/can_leg/leg.toml",
                                "test/vectors/good/*.toml"])
    bad = _vectors(args.root, ["manifests/invalid/*.toml", "test/vectors/bad/*.toml"])
    jobs = [(path, _check_good) for path in good] + [(path, _check_bad) for path in bad]
    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        results = list(pool.map(lambda job: job[1](job[0], args), jobs))

    failed = 0
    for (path, check), (ok, what) in zip(jobs, results):
        kind = "good" if check is _check_good else "bad "
        print(f"{'ok  ' if ok else 'FAIL'} {kind} {path}: {what}")
        failed += not ok
    print(f"\n{len(good)} good and {len(bad)} bad vectors, {failed} disagreeing")
    return 1 if failed or not good or not bad else 0


if __name__ == "__main__":
    sys.exit(main())
