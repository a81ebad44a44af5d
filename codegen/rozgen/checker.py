# SPDX-License-Identifier: Apache-2.0
"""The robot.toml rules, run where they are written: in C.

Every rule of robot.toml, the TOML reader's refusals and the ports' rules
of their [hardware] keys have one implementation, roz's C loader
(``host/toml/src/manifest_toml.c``) and each port's registered check
(``roz_add_port_rules()``: ``ports/socketcan/src/can_config.c``, ...,
and the mujoco port's rules on the model a robot.toml names,
``ports/mujoco/src/mj_rules.c``),
as Cyclone DDS's idlc is the one parser of IDL. rozgen runs it as the
program ``roz_manifest_json --rozgen`` (``tools/manifest_json``), which
prints either every problem (``<rule>\\t<text>`` lines) or the manifest
as JSON, and builds its model from that; Python keeps the generation.

``find()`` looks for the program, first hit wins:

1. ``--checker PATH`` (``explicit``), then the environment variable
   ``ROZ_MANIFEST_CHECKER``;
2. beside the command that runs rozgen: an installed roz has
   ``<prefix>/bin/roz_manifest_json`` next to ``<prefix>/bin/rozgen``;
3. rozgen run from a roz source tree (``pip install -e codegen``): the
   tree's own, built with CMake (and a C compiler) on first use into
   ``$XDG_CACHE_HOME/roz/rozgen-checker/<tree>`` (``~/.cache`` by default)
   and brought up to date on every run, so it is always the tree's rules;
4. ``roz_manifest_json`` on PATH.
"""

import fcntl
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from rozgen.model import Channel, Fall, Hardware, Manifest, Maxima
from rozgen import problems as _problems
from rozgen.problems import Problem

ENV = "ROZ_MANIFEST_CHECKER"
TOOL = "roz_manifest_json"

# A host build of only what the program needs, whatever the caller builds
# (a firmware's cross build runs rozgen too).
_MINIMAL = ("-DROZ_BUILD_TESTS=OFF", "-DROZ_BUILD_EXAMPLES=OFF", "-DROZ_BUILD_BENCH=OFF",
            "-DROZ_INSTALL=OFF", "-DROZ_BUILTIN_MANIFESTS=OFF", "-DROZ_WITH_WASM3=OFF",
            "-DROZ_TOML=ON", "-DROZ_BUILD_TOOLS=ON", "-DROZ_PORT_DDS=OFF",
            "-DROZ_PORT_MUJOCO=OFF", "-DROZ_PORT_SOCKETCAN=OFF", "-DCMAKE_BUILD_TYPE=Release",
            # room for every message whole (a build's default cuts them at 384 bytes)
            "-DCMAKE_C_FLAGS=-DROZ_CFG_PROBLEM_LEN=4096")
# what would make the nested build a cross build or change its flags
_CROSS_ENV = ("CC", "CFLAGS", "LDFLAGS", "CPPFLAGS", "CMAKE_TOOLCHAIN_FILE",
              "CMAKE_GENERATOR_PLATFORM")


class CheckerError(Exception):
    """The checker cannot be found, built or run (not a problem of a file)."""


def find(explicit: str | None = None) -> str:
    """The path of roz_manifest_json; raises CheckerError (see the module's text)."""
    for given in (explicit, os.environ.get(ENV)):
        if given:
            if not os.access(given, os.X_OK):
                raise CheckerError(f"{given}: not an executable roz_manifest_json")
            return given
    beside = Path(os.path.realpath(sys.argv[0])).parent / TOOL
    if beside.is_file() and os.access(beside, os.X_OK):
        return str(beside)
    tree = _source_tree()
    if tree is not None:
        return _build_in(tree)
    on_path = shutil.which(TOOL)
    if on_path is not None:
        return on_path
    raise CheckerError(
        f"{TOOL}, roz's C implementation of the robot.toml rules, was not found: pass "
        f"--checker PATH or set {ENV} (an installed roz has it in <prefix>/bin; a roz build "
        f"in <build>/tools/manifest_json)")


def _source_tree() -> Path | None:
    """The roz source tree this package sits in, if it does."""
    root = Path(__file__).resolve().parent.parent.parent
    if (root / "tools" / "manifest_json" / "main.c").is_file() and \
            (root / "host" / "toml" / "src" / "manifest_toml.c").is_file():
        return root
    return None


def _cache_dir() -> Path:
    """$XDG_CACHE_HOME/roz/rozgen-checker (~/.cache/...), else a temporary folder."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    folder = Path(base) / "roz" / "rozgen-checker"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        folder = Path(tempfile.gettempdir()) / f"roz-rozgen-checker-{os.getuid()}"
        folder.mkdir(exist_ok=True)
    return folder


def _build_in(tree: Path) -> str:
    """Configure (once) and build (every time: a no-op when up to date) the
    tree's roz_manifest_json in the cache; one process at a time."""
    key = hashlib.sha256(str(tree).encode("utf-8")).hexdigest()[:16]
    env = {k: v for k, v in os.environ.items() if k not in _CROSS_ENV}
    try:
        cache = _cache_dir()
        build = cache / key
        with open(cache / f"{key}.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            if not any((build / f).is_file() for f in ("build.ninja", "Makefile")):
                generator = ["-G", "Ninja"] if shutil.which("ninja") else []
                _run(["cmake", "-S", str(tree), "-B", str(build), *generator, *_MINIMAL], env)
            _run(["cmake", "--build", str(build), "--target", TOOL], env)
    except OSError as e:
        raise CheckerError(f"cannot build {TOOL} of {tree}: {e.strerror or e}") from None
    return str(build / "tools" / "manifest_json" / TOOL)


def _run(command: list[str], env: dict) -> None:
    done = subprocess.run(command, env=env, capture_output=True, text=True,
                          errors="backslashreplace")
    if done.returncode != 0:
        raise CheckerError(f"building {TOOL} failed ({' '.join(command)}):\n"
                           f"{done.stdout}{done.stderr}")


def check(data: bytes, maxima: Maxima, checker: str,
          origin: str | None = None) -> tuple[Manifest | None, list[Problem]]:
    """Run the rules on a robot.toml's bytes: the model, or None and every
    problem. ``origin`` is the file's path as given: the files its keys
    name (the mujoco port's model) are read relative to its folder and
    named so (None: the working directory)."""
    command = [checker, "--rozgen", "--max-commands", str(maxima.commands), "--max-states",
               str(maxima.states), "--max-name-len", str(maxima.name_len)]
    if origin is not None:
        command += ["--origin", origin]
    command.append("-")
    _problems.used_checker = checker  # the ports' rule ids are this one's
    try:
        done = subprocess.run(command, input=data, capture_output=True)
    except OSError as e:
        raise CheckerError(f"{checker}: cannot run: {e.strerror or e}") from None
    out = done.stdout.decode("utf-8", "backslashreplace")
    if done.returncode == 0:
        return _manifest(json.loads(out, parse_int=str, parse_float=str)), []
    problems = []
    for line in out.splitlines():
        rule, tab, text = line.partition("\t")
        if not tab:
            break
        problems.append(Problem(rule, text))
    if done.returncode != 2 or not problems:
        raise CheckerError(f"{checker} failed (exit status {done.returncode}): "
                           f"{done.stderr.decode('utf-8', 'backslashreplace').strip()}")
    return None, problems


def canonical_json(data: bytes, checker: str) -> str:
    """``rozgen --json``: the canonical JSON of a valid robot.toml's bytes,
    as the checker writes it (``tools/manifest_json/json.c``)."""
    try:
        done = subprocess.run([checker, "-"], input=data, capture_output=True)
    except OSError as e:
        raise CheckerError(f"{checker}: cannot run: {e.strerror or e}") from None
    if done.returncode != 0:
        raise CheckerError(f"{checker} failed (exit status {done.returncode}): "
                           f"{done.stderr.decode('utf-8', 'backslashreplace').strip()}")
    return done.stdout.decode("utf-8")


def _channel(c: dict) -> Channel:
    low, high = c["limits"]
    if "stale_after_ms" in c:  # an operator input: none of the filter's keys
        return Channel(name=c["name"], interface_type=c["interface_type"], unit=c["unit"],
                       min=float(low), max=float(high), default=float(c["default"]),
                       max_rate=float(c["max_rate_of_change"]), position_state=-1,
                       limit_margin=0.0, stale_after_ms=int(c["stale_after_ms"]),
                       source=c.get("source", ""), scale=float(c.get("scale", 0.0)))
    return Channel(name=c["name"], interface_type=c["interface_type"], unit=c["unit"],
                   min=float(low), max=float(high), default=float(c["default"]),
                   max_rate=float(c["max_rate_of_change"]),
                   position_state=int(c["position_state_index"]),
                   limit_margin=float(c["limit_margin"]), safe_default=c["safe_default"])


def _manifest(doc: dict) -> Manifest:
    """The model of the checker's JSON (numbers kept as written: -0 stays -0.0)."""
    hw = doc["hardware"]
    hardware = None if hw is None else Hardware(
        port=hw["port"], joints=tuple(hw["joints"]), params=tuple(hw["params"].items()))
    fa = doc.get("fall")  # present only with a fall rule
    fall = None if fa is None else Fall(
        orientation=fa["orientation"], quaternion=tuple(int(i) for i in fa["quaternion"]),
        max_tilt=float(fa["max_tilt_rad"]), for_ms=int(fa["for_ms"]))
    return Manifest(robot_id=doc["robot_id"], robot_class=doc["robot_class"],
                    control_rate_hz=int(doc["control_rate_hz"]),
                    commands=tuple(_channel(c) for c in doc["commands"]),
                    states=tuple(_channel(c) for c in doc["states"]), hardware=hardware,
                    inputs=tuple(_channel(c) for c in doc.get("inputs", ())),
                    remote_estop=tuple(doc.get("remote_estop", ())), fall=fall)
