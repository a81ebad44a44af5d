# SPDX-License-Identifier: Apache-2.0
"""roz-campaign: a controller judged across many perturbed runs in simulation.

    python tools/campaign.py run FILE [--out DIR] [--build DIR] [--rozrun PATH]
                                      [--workers N] [--ray ADDRESS] [--samples N]
                                      [--family NAME]...
    python tools/campaign.py report DIR        (the report again, from the results)
    roz-campaign ...                           (the same, installed with roz)

A campaign file (TOML, docs/campaigns.md) names the robot, the port, the
controller builds to compare, a duration, invariants, and families of
perturbations with ranges and distributions. Each sample is one rozrun run in
simulated time, its values drawn from the campaign's seed; the same sample
of a family gets the same values under every controller (the builds are
compared on the same runs). Each run's summary (rozrun --summary-json) is
judged by the invariants: stands (lowest base height), the faults latched at
the end (none, or the expected ones), nothing outside the manifest on the
wire, follows the operator (tools/tracking.py's measures, from the run's
trace). The operator's commands are one script for every sample, or a
family's perturbation: each sample its own script, written under DIR.

Results are one JSON line per sample in DIR/results.jsonl, appended by this
process alone as each sample ends (one write, flushed to disk), so an
interrupted campaign resumes where it stopped: a sample whose line is there
is not run again; a line cut short by a crash is ignored and run again. The
engines: a pool of local workers (every core by default), or a Ray cluster
(--ray ADDRESS; `pip install ray` pinned, tools/requirements-ray.txt) where a
task lost with its worker or node is retried by Ray; a worker's rozrun
killed is retried here. Every sample ends in the results exactly once.

Every sample's rozrun command is in its row and in the report: run it, and
the same run happens again, bit for bit.
"""
import argparse
import hashlib
import json
import math
import os
import random
import shutil
import shlex
import signal
import subprocess
import sys
import tempfile
import threading
import time
import tomllib
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tracking  # noqa: E402  (beside this file: follows the operator, one implementation)

FORMAT = "roz-campaign/1"
RETRIES = 3  # a sample whose rozrun was killed is run again this many times

# ---- the campaign file ------------------------------------------------------------

#: the perturbations a family combines: each field's default (None: required)
#: and unit; a field is a number or word, or a distribution (DISTRIBUTIONS)
KINDS = {
    "push": {"force": (None, "N"), "direction": (0.0, "deg, 0 = +x (forward), 90 = +y (left)"),
             "lift": (0.0, "N, +z"), "body": ("pelvis", ""), "at": (None, "s"),
             "duration": (0.1, "s")},
    "payload": {"mass": (None, "kg"), "body": ("torso_link", ""), "x": (0.0, "m"),
                "y": (0.0, "m"), "z": (0.0, "m")},
    "mass": {"scale": (None, "")},
    "friction": {"scale": (None, "")},
    "gains": {"scale": (None, "")},
    "strength": {"scale": (None, ""), "joint": ("", "the model's joint; empty: every joint")},
    "joints": {"damping": (0.0, "N m s/rad"), "armature": (0.0, "kg m^2")},
    "latency": {"state_ticks": (0, "ticks"), "command_ticks": (0, "ticks")},
    "sensors": {"noise_position": (0.0, "rad"), "noise_velocity": (0.0, "rad/s"),
                "noise_gyro": (0.0, "rad/s"), "noise_accelerometer": (0.0, "m/s^2"),
                "bias_position": (0.0, "rad"), "bias_gyro": (0.0, "rad/s"),
                "bias_accelerometer": (0.0, "m/s^2"), "bias_orientation": (0.0, "rad")},
    "drop": {"at": (None, "s"), "duration": (None, "s")},
    "restart": {"at": (None, "s"), "duration": (None, "s")},
    "delay": {"ticks": (None, "ticks"), "at": (None, "s"), "duration": (None, "s")},
    "estop": {"at": (None, "s")},
    "swap": {"at": (None, "s"), "controller": (None, "a controller file")},
    # the operator's command: INPUT at VALUE from AT for DURATION (0: to the
    # end), at BASE before and after; a family's steps make each sample's
    # own script (rozrun --operator), docs/campaigns.md "The operator"
    "operator": {"input": ("operator/velocity.x", "an operator input of the robot"),
                 "value": (None, "the input's unit"), "at": (0.0, "s"),
                 "duration": (0.0, "s, 0 = to the end"), "base": (0.0, "the input's unit")},
}
DISTRIBUTIONS = ("uniform", "normal", "loguniform", "integer", "choice", "linspace")
#: the invariants a verdict checks, and their defaults
VERDICT = {"min_base_height": None, "min_final_base_height": None, "faults": [],
           "max_wire_violations": 0, "max_tilt_deg": None, "tracking": None}
#: follows the operator (verdict.tracking): tools/tracking.py's bounds, each
#: segment of constant command judged after SETTLE seconds (its --settle)
TRACKING = {"settle": 2.0, "max_speed_error": None, "max_yaw_rate_error": None,
            "max_stop_drift": None, "max_stop_turn": None, "heading_ratio": None}


class CampaignError(Exception):
    """A campaign file that cannot be run: the message names the file and key."""


def _fail(path, key, msg):
    raise CampaignError(f"{path}: {key}: {msg}")


def _check_value(path, key, v):
    if isinstance(v, dict):
        if len(v) != 1 or next(iter(v)) not in DISTRIBUTIONS:
            _fail(path, key, f"expected a value or one of {', '.join(DISTRIBUTIONS)} "
                  f"(e.g. {{uniform = [1, 2]}}), got {v!r}")
        name, arg = next(iter(v.items()))
        if not isinstance(arg, list) or not arg:
            _fail(path, key, f"{name} takes a list, got {arg!r}")
        if name != "choice" and (len(arg) != 2 or not all(
                isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
                for x in arg)):
            _fail(path, key, f"{name} takes [a, b], two numbers, got {arg!r}")
        if name in ("uniform", "loguniform", "integer", "linspace") and arg[0] > arg[1]:
            _fail(path, key, f"{name} = {arg!r}: the first must not exceed the second")
        if name == "loguniform" and arg[0] <= 0:
            _fail(path, key, f"loguniform = {arg!r}: both must be above 0")
        if name == "normal" and arg[1] < 0:
            _fail(path, key, f"normal = {arg!r}: the standard deviation must be 0 or more")
    elif not isinstance(v, (int, float, str)) or isinstance(v, bool):
        _fail(path, key, f"expected a number, a word or a distribution, got {v!r}")


def _verdict(path, key, table, base):
    out = dict(base)
    for k, v in (table or {}).items():
        if k not in VERDICT:
            _fail(path, f"{key}.{k}", f"unknown invariant (known: {', '.join(VERDICT)})")
        if k == "faults":
            if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
                _fail(path, f"{key}.{k}", "expected a list of fault names ([] for none)")
        elif k == "tracking":
            v = _tracking(path, f"{key}.{k}", v)
        elif not isinstance(v, (int, float)) or isinstance(v, bool):
            _fail(path, f"{key}.{k}", f"expected a number, got {v!r}")
        out[k] = v
    return out


def _tracking(path, key, table):
    """verdict.tracking, checked: TRACKING's keys, numbers (heading_ratio
    [lo, hi]), at least one bound."""
    if not isinstance(table, dict):
        _fail(path, key, "expected a table of bounds (e.g. {max_speed_error = 0.2})")
    out = dict(TRACKING)
    for k, v in table.items():
        if k not in TRACKING:
            _fail(path, f"{key}.{k}", f"unknown bound (known: {', '.join(TRACKING)})")
        num = (lambda x: isinstance(x, (int, float)) and not isinstance(x, bool)
               and math.isfinite(x) and x >= 0)
        if k == "heading_ratio":
            if not isinstance(v, list) or len(v) != 2 or not all(map(num, v)) or v[0] > v[1]:
                _fail(path, f"{key}.{k}", f"expected [lo, hi], got {v!r}")
        elif not num(v):
            _fail(path, f"{key}.{k}", f"expected a number, 0 or more, got {v!r}")
        out[k] = v
    if all(out[k] is None for k in TRACKING if k != "settle"):
        _fail(path, key, f"no bound (known: {', '.join(k for k in TRACKING if k != 'settle')})")
    return out


def load(path, build="build"):
    """The campaign in @path, checked; CampaignError names what is wrong."""
    try:
        with open(path, "rb") as f:
            doc = tomllib.load(f)
    except OSError as e:
        raise CampaignError(f"{path}: {e.strerror}") from None
    except tomllib.TOMLDecodeError as e:
        raise CampaignError(f"{path}: {e}") from None
    known = {"campaign", "controllers", "verdict", "families"}
    for k in doc:
        if k not in known:
            _fail(path, k, f"unknown table (known: {', '.join(sorted(known))})")
    c = doc.get("campaign")
    if not isinstance(c, dict):
        _fail(path, "campaign", "missing: [campaign] names the robot, port and duration")
    ckeys = {"name", "robot", "port", "duration_s", "seed", "samples", "operator"}
    for k in c:
        if k not in ckeys:
            _fail(path, f"campaign.{k}", f"unknown key (known: {', '.join(sorted(ckeys))})")
    for k in ("robot", "duration_s"):
        if k not in c:
            _fail(path, f"campaign.{k}", "missing")
    if not isinstance(c["duration_s"], (int, float)) or not 0 < c["duration_s"] <= 3600:
        _fail(path, "campaign.duration_s", f"expected seconds in (0, 3600], got {c['duration_s']!r}")
    if c.get("port", "mujoco") != "mujoco":
        _fail(path, "campaign.port", f"\"{c['port']}\": campaigns run on the mujoco port only")
    here = os.path.dirname(os.path.abspath(path))

    def resolve(p):
        # "{build}/..." is in the build tree (--build); else relative to this file
        if p.startswith("{build}"):
            return os.path.abspath(p.replace("{build}", build, 1))
        return p if os.path.isabs(p) else os.path.normpath(os.path.join(here, p))

    # the operator's command sequence: rozrun --operator's CSV, the same for
    # every sample (docs/campaigns.md, "The operator")
    operator = None
    if "operator" in c:
        if not isinstance(c["operator"], str) or not c["operator"]:
            _fail(path, "campaign.operator", f"expected a file (rozrun --operator's CSV), got "
                  f"{c['operator']!r}")
        operator = resolve(c["operator"])
        if not os.path.isfile(operator):
            _fail(path, "campaign.operator", f"\"{c['operator']}\": no such file ({operator})")
        with open(operator, "rb") as f:
            operator_sha = hashlib.sha256(f.read()).hexdigest()

    ctls = doc.get("controllers")
    if not isinstance(ctls, list) or not ctls:
        _fail(path, "controllers", "missing: [[controllers]] name = ..., wasm = ...")
    names = set()
    controllers = []
    for i, ct in enumerate(ctls):
        key = f"controllers[{i}]"
        if not isinstance(ct.get("name"), str) or not isinstance(ct.get("wasm"), str):
            _fail(path, key, "expected name and wasm (a controller file)")
        for k in ct:
            if k not in ("name", "wasm"):
                _fail(path, f"{key}.{k}", "unknown key (known: name, wasm)")
        if ct["name"] in names or "/" in ct["name"]:
            _fail(path, f"{key}.name", f"\"{ct['name']}\": names are unique, without '/'")
        names.add(ct["name"])
        controllers.append({"name": ct["name"], "wasm": resolve(ct["wasm"])})
    base = _verdict(path, "verdict", doc.get("verdict"), VERDICT)
    fams = doc.get("families")
    if not isinstance(fams, list) or not fams:
        _fail(path, "families", "missing: [[families]] name = ..., [[families.perturb]] ...")
    families = []
    fnames = set()
    for i, fa in enumerate(fams):
        key = f"families[{i}]"
        for k in fa:
            if k not in ("name", "samples", "perturb", "verdict", "boundary", "controllers"):
                _fail(path, f"{key}.{k}", "unknown key (known: name, samples, perturb, verdict, "
                      "boundary, controllers)")
        name = fa.get("name")
        if not isinstance(name, str) or not name or "/" in name or name in fnames:
            _fail(path, f"{key}.name", "expected a unique name without '/'")
        fnames.add(name)
        n = fa.get("samples", c.get("samples", 8))
        if not isinstance(n, int) or isinstance(n, bool) or not 1 <= n <= 1_000_000:
            _fail(path, f"{key}.samples", f"expected 1..1000000, got {n!r}")
        perturb = []
        for j, pt in enumerate(fa.get("perturb", [])):
            pkey = f"{key}.perturb[{j}]"
            kind = pt.get("kind")
            if kind not in KINDS:
                _fail(path, f"{pkey}.kind", f"{kind!r}: expected one of {', '.join(KINDS)}")
            fields = {}
            for k, v in pt.items():
                if k == "kind":
                    continue
                if k not in KINDS[kind]:
                    _fail(path, f"{pkey}.{k}", f"unknown field of {kind} (known: "
                          f"{', '.join(KINDS[kind])})")
                _check_value(path, f"{pkey}.{k}", v)
                fields[k] = v
            for k, (default, _) in KINDS[kind].items():
                if k not in fields:
                    if default is None:
                        _fail(path, f"{pkey}.{k}", f"missing: {kind} needs it")
                    fields[k] = default
            perturb.append({"kind": kind, "fields": fields})
        boundary = fa.get("boundary")
        if boundary is not None:
            if not isinstance(boundary, dict) or set(boundary) != {"value", "worse"} or \
                    boundary["worse"] not in ("higher", "lower"):
                _fail(path, f"{key}.boundary", "expected {value = \"KIND.FIELD\", worse = "
                      "\"higher\" | \"lower\"}")
        only = fa.get("controllers", sorted(names))
        if not isinstance(only, list) or not only or any(x not in names for x in only):
            _fail(path, f"{key}.controllers", f"expected a list of the campaign's controllers "
                  f"({', '.join(sorted(names))}), got {only!r}")
        steps = [j for j, pt in enumerate(perturb) if pt["kind"] == "operator"]
        if steps and operator:
            _fail(path, f"{key}.perturb[{steps[0]}]", "an operator step makes each sample's own "
                  "script: not with [campaign] operator (put the file's commands in steps)")
        verdict = _verdict(path, f"{key}.verdict", fa.get("verdict"), base)
        if verdict["tracking"] is not None and not steps and not operator:
            _fail(path, f"{key}.verdict.tracking", "follows the operator: needs an operator "
                  "script ([campaign] operator, or operator steps in the family)")
        families.append({"name": name, "samples": n, "perturb": perturb, "controllers": only,
                         "verdict": verdict, "boundary": boundary})
    seed = c.get("seed", 1)
    if not isinstance(seed, int) or not 0 <= seed < 2**32:
        _fail(path, "campaign.seed", f"expected 0..4294967295, got {seed!r}")
    return {"name": c.get("name", os.path.splitext(os.path.basename(path))[0]),
            "file": os.path.abspath(path), "robot": c["robot"], "port": "mujoco",
            "duration_s": float(c["duration_s"]), "seed": seed, "controllers": controllers,
            "families": families, "operator": operator,
            "operator_sha256": operator_sha if operator else None}


# ---- the samples ------------------------------------------------------------------

def sample_seed(seed, family, index):
    """A sample's seed: the campaign's, the family and the index, hashed."""
    h = hashlib.sha256(f"{seed}/{family}/{index}".encode()).digest()
    return int.from_bytes(h[:4], "little")


def _draw(rng, v, index, n):
    if not isinstance(v, dict):
        return v
    name, a = next(iter(v.items()))
    if name == "uniform":
        return rng.uniform(a[0], a[1])
    if name == "normal":
        return rng.gauss(a[0], a[1])
    if name == "loguniform":
        return math.exp(rng.uniform(math.log(a[0]), math.log(a[1])))
    if name == "integer":
        return rng.randint(int(a[0]), int(a[1]))
    if name == "choice":
        return a[rng.randrange(len(a))]
    return a[0] + (a[1] - a[0]) * (index / (n - 1) if n > 1 else 0.5)  # linspace


def _g(x):
    """A value on rozrun's command line: short, and exact enough to be the run."""
    return f"{x:.6g}" if isinstance(x, float) else str(x)


def operator_script(steps, end):
    """The operator's script (rozrun --operator's CSV) of @steps, each an
    operator perturbation's values: a column per input, a row at 0 and at
    every step's start and end before @end (s) where a value changes, each
    row every input's value then (the last step in force, else the input's
    first step's base)."""
    inputs = list(dict.fromkeys(st["input"] for st in steps))
    times = {0.0}
    for st in steps:
        times.add(float(st["at"]))
        if st["duration"] > 0:
            times.add(float(st["at"] + st["duration"]))
    lines, last = ["time_s," + ",".join(inputs)], None
    for t in sorted(x for x in times if x < end):
        row = []
        for name in inputs:
            mine = [st for st in steps if st["input"] == name]
            v = mine[0]["base"]
            for st in mine:
                if st["at"] <= t and (st["duration"] <= 0 or t < st["at"] + st["duration"]):
                    v = st["value"]
            row.append(_g(float(v)))
        if row != last:  # a row that changes nothing would split a segment
            lines.append(f"{_g(t)}," + ",".join(row))
        last = row
    return "\n".join(lines) + "\n"


def draw(campaign, family, index):
    """Sample @index of @family: its seed, the values drawn (KIND.FIELD, a
    kind's second entry KIND2.FIELD), rozrun's arguments (without the
    program, the controller and the output files) and the operator's script
    its operator steps make (None without)."""
    seed = sample_seed(campaign["seed"], family["name"], index)
    rng = random.Random(seed)
    rate = campaign["rate_hz"]
    values = {}
    params = {"noise_seed": [str(seed)]}
    extra = []
    seen = {}
    steps = []

    def tick(s):
        return max(0, int(round(s * rate)))

    for pt in family["perturb"]:
        kind = pt["kind"]
        seen[kind] = seen.get(kind, 0) + 1
        label = kind if seen[kind] == 1 else f"{kind}{seen[kind]}"
        v = {}
        for k in sorted(pt["fields"]):
            v[k] = _draw(rng, pt["fields"][k], index, family["samples"])
            if isinstance(v[k], float):
                v[k] = float(_g(v[k]))  # the value the command line carries
            values[f"{label}.{k}"] = v[k]

        def param(key, text):
            params.setdefault(key, []).append(text)

        if kind == "push":
            a = math.radians(v["direction"])
            f = (v["force"] * math.cos(a), v["force"] * math.sin(a), v["lift"])
            t0 = tick(v["at"])
            param("push", f"{_g(f[0])},{_g(f[1])},{_g(f[2])}@{v['body']}@{t0}:"
                  f"{max(t0 + 1, tick(v['at'] + v['duration']))}")
        elif kind == "payload":
            off = "" if (v["x"], v["y"], v["z"]) == (0.0, 0.0, 0.0) else \
                f"@{_g(v['x'])},{_g(v['y'])},{_g(v['z'])}"
            param("payload", f"{_g(v['mass'])}@{v['body']}{off}")
        elif kind in ("mass", "friction", "gains"):
            param(f"{kind}_scale", _g(v["scale"]))
        elif kind == "strength":
            param("strength_scale", _g(v["scale"]) + (f"@{v['joint']}" if v["joint"] else ""))
        elif kind == "joints":
            param("joint_damping", _g(v["damping"]))
            param("joint_armature", _g(v["armature"]))
        elif kind == "latency":
            param("latency_ticks", str(int(v["state_ticks"])))
            param("command_latency_ticks", str(int(v["command_ticks"])))
        elif kind == "sensors":
            for k in KINDS["sensors"]:
                if v[k]:
                    param(k, _g(v[k]))
        elif kind in ("drop", "restart"):
            t0 = tick(v["at"])
            param(kind, f"{t0}:{max(t0 + 1, tick(v['at'] + v['duration']))}")
        elif kind == "delay":
            t0 = tick(v["at"])
            param("delay", f"{int(v['ticks'])}@{t0}:{max(t0 + 1, tick(v['at'] + v['duration']))}")
        elif kind == "estop":
            extra += ["--estop-at", str(max(1, tick(v["at"])))]
        elif kind == "swap":
            extra += ["--swap-at", f"{max(1, tick(v['at']))}:{{swap:{v['controller']}}}"]
        elif kind == "operator":
            steps.append(v)
    args = []
    for k in sorted(params):
        args += ["--param", f"{k}={';'.join(params[k])}"]
    script = operator_script(steps, campaign["duration_s"]) if steps else None
    return seed, values, args + extra, script


def samples(campaign):
    """Every sample of the campaign, in order: family, index, controller."""
    ticks = int(round(campaign["duration_s"] * campaign["rate_hz"]))
    out = []
    for fam in campaign["families"]:
        for i in range(fam["samples"]):
            seed, values, args, script = draw(campaign, fam, i)
            for ct in campaign["controllers"]:
                if ct["name"] not in fam["controllers"]:
                    continue
                out.append({
                    "id": f"{fam['name']}/{i}/{ct['name']}", "family": fam["name"], "index": i,
                    "controller": ct["name"], "seed": seed, "values": values,
                    "args": ["--robot", campaign["robot"], "--port", campaign["port"],
                             "--controller", "{controller}", "--ticks", str(ticks)] +
                            (["--operator", "{operator}"]
                             if campaign.get("operator") or script else []) +
                            args,
                    # the sample's own script (its family's operator steps):
                    # the file the command names, under --out (operator_file)
                    "script": script, "operator_file": script and
                    os.path.join(campaign.get("out", ""), "operators", f"{fam['name']}-{i}.csv"),
                })
    return out


def write_scripts(todo):
    """Writes the operator scripts of the samples in @todo where their
    commands name them (a file already there with the same bytes stays)."""
    for s in todo:
        if not s["script"]:
            continue
        data = s["script"].encode()
        try:
            with open(s["operator_file"], "rb") as f:
                if f.read() == data:
                    continue
        except FileNotFoundError:
            pass
        os.makedirs(os.path.dirname(s["operator_file"]), exist_ok=True)
        with open(s["operator_file"] + ".tmp", "wb") as f:
            f.write(data)
        os.replace(s["operator_file"] + ".tmp", s["operator_file"])


def _swap_path(campaign, name):
    """A swap's controller file, as the file's controllers are found."""
    if name.startswith("{build}"):
        return os.path.abspath(name.replace("{build}", campaign.get("build", "build"), 1))
    if os.path.isabs(name):
        return name
    return os.path.normpath(os.path.join(os.path.dirname(campaign["file"]), name))


def command(campaign, sample, rozrun):
    """The rozrun command that is this sample's run, as a list."""
    wasm = next(c["wasm"] for c in campaign["controllers"] if c["name"] == sample["controller"])
    out = [rozrun]
    for a in sample["args"]:
        a = a.replace("{controller}", wasm)
        if a == "{operator}":
            a = sample.get("operator_file") or campaign["operator"]
        if "{swap:" in a:
            pre, rest = a.split("{swap:", 1)
            a = pre + _swap_path(campaign, rest[:-1])
        out.append(a)
    return out


def shell(cmd):
    """A command as one line a shell takes."""
    return " ".join(shlex.quote(a) for a in cmd)


# ---- one sample (a worker's part, on either engine) ---------------------------------

def run_sample(task):
    """Runs one sample: @task carries the rozrun program, the arguments with
    the controllers' place holders and the controllers' bytes (a Ray node may
    not share the driver's files). Returns the result row's measured part."""
    log = os.environ.get("ROZ_CAMPAIGN_TASK_LOG")
    node = task.get("node") or os.uname().nodename
    if log:  # tests: which sample started where (one line, appended); a node's name
        with open(log, "a") as f:  # from ROZ_CAMPAIGN_NODE in its environment
            f.write(f"{task['id']} {os.environ.get('ROZ_CAMPAIGN_NODE', node)}\n")
    t0 = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="roz-campaign-") as tmp:
        files = {}
        for name, data in task["files"].items():
            p = os.path.join(tmp, f"{len(files)}-{os.path.basename(name)}")
            with open(p, "wb") as f:
                f.write(data)
            files[name] = p
        args = []
        for a in task["args"]:
            a = a.replace("{controller}", files[task["controller_file"]])
            if a == "{operator}":
                a = files[task["operator_file"]]
            if "{swap:" in a:
                pre, rest = a.split("{swap:", 1)
                a = pre + files[rest[:-1]]
            args.append(a)
        out = os.path.join(tmp, "summary.json")
        # follows the operator: judged from the trace's truth (tools/tracking.py)
        trace = ["--trace", os.path.join(tmp, "trace.csv")] if task.get("settle") is not None \
            else []
        p = subprocess.run([task["rozrun"]] + args + ["--summary-json", out] + trace,
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        summary = segments = None
        if os.path.exists(out):
            with open(out) as f:
                summary = json.load(f)
        if trace and summary is not None:
            segments = _segments(trace[1], files[task["operator_file"]], task["settle"])
    return {"status": p.returncode, "summary": summary, "stderr": p.stderr[-2000:],
            "wall_s": time.monotonic() - t0, "node": node, "tracking": segments}


def _segments(trace, script, settle):
    """tools/tracking.py's segments of a run (its trace and operator script),
    or a sentence saying why there are none."""
    try:
        segs = tracking.judge(tracking.read_trace(trace), tracking.read_operator(script), settle)
    except SystemExit as e:  # tracking.py says what it cannot read, and exits
        return str(e)
    except (ValueError, IndexError, KeyError) as e:  # a trace cut short
        return f"{type(e).__name__}: {e}"
    return [{k: (round(v, 6) if isinstance(v, float) else v) for k, v in sg.items()}
            for sg in segs]


def _task(campaign, sample, rozrun, blobs):
    wasm = next(c["wasm"] for c in campaign["controllers"] if c["name"] == sample["controller"])
    files = {wasm: blobs[wasm]}
    for a in sample["args"]:
        if "{swap:" in a:
            name = a.split("{swap:", 1)[1][:-1]
            p = _swap_path(campaign, name)
            files[name] = blobs[p]
    op = sample.get("operator_file") or campaign.get("operator")
    if op:
        files[op] = sample["script"].encode() if sample.get("script") else blobs[op]
    bounds = next(f["verdict"]["tracking"] for f in campaign["families"]
                  if f["name"] == sample["family"])
    return {"id": sample["id"], "rozrun": rozrun, "args": sample["args"], "files": files,
            "controller_file": wasm, "operator_file": op,
            "settle": bounds and bounds["settle"]}


# ---- the results file ---------------------------------------------------------------

def read_results(path):
    """The rows of results.jsonl by id: a line cut short (a crash mid-write)
    is ignored, and so is a second line of an id (none is written)."""
    rows = {}
    try:
        with open(path, "rb") as f:
            data = f.read()
    except FileNotFoundError:
        return rows
    for line in data.split(b"\n"):
        if not line.strip():
            continue
        try:
            row = json.loads(line)
        except ValueError:
            continue
        if isinstance(row, dict) and "id" in row:
            rows.setdefault(row["id"], row)
    return rows


class Results:
    """results.jsonl: one line per sample, appended by one writer, each line
    one write() of whole bytes then fsync, so it is there or not at all. A
    file that ends in a cut line gets a newline first, so the next line is
    whole."""

    def __init__(self, path):
        self.path = path
        self.rows = read_results(path)
        self.fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
        if os.fstat(self.fd).st_size > 0:
            with open(path, "rb") as f:
                f.seek(-1, os.SEEK_END)
                if f.read(1) != b"\n":
                    os.write(self.fd, b"\n")

    def add(self, row):
        if row["id"] in self.rows:
            return False  # exactly once: a sample already there is not written again
        os.write(self.fd, (json.dumps(row, sort_keys=True) + "\n").encode())
        os.fsync(self.fd)
        self.rows[row["id"]] = row
        return True

    def close(self):
        os.close(self.fd)


# ---- verdicts -----------------------------------------------------------------------

def judge(row, inv):
    """(passed, reasons) of one result row against a family's invariants."""
    s = row.get("summary")
    if s is None or row.get("status") not in (0, 1):
        err = (row.get("stderr") or "").strip().splitlines()
        return False, [f"rozrun exit {row.get('status')}" + (f": {err[-1]}" if err else "")]
    why = []
    truth = s.get("truth")
    if inv.get("min_base_height") is not None:
        low = truth and truth.get("base_height_min")
        if low is None:
            why.append("no base height (the robot has no floating base)")
        elif low < inv["min_base_height"]:
            why.append(f"fell: base down to {low:.3f} m (< {inv['min_base_height']} m) at "
                       f"{truth['base_height_min_time_s']:.2f} s")
    if inv.get("min_final_base_height") is not None and truth and \
            truth["base_height_final"] < inv["min_final_base_height"]:
        why.append(f"down at the end: base at {truth['base_height_final']:.3f} m "
                   f"(< {inv['min_final_base_height']} m)")
    if inv.get("max_tilt_deg") is not None and truth and \
            truth.get("tilt_max_deg", 0) > inv["max_tilt_deg"]:
        why.append(f"tilted {truth['tilt_max_deg']:.1f} deg (> {inv['max_tilt_deg']})")
    latched = sorted(s["faults"]["latched"])
    if latched != sorted(inv.get("faults", [])):
        want = ", ".join(inv.get("faults", [])) or "none"
        why.append(f"faults latched: {', '.join(latched) or 'none'} (expected {want})")
    wire = s.get("wire_violations", 0) + ((s.get("port_counters") or {}).get("violations") or 0)
    if wire > inv.get("max_wire_violations", 0):
        why.append(f"{wire} values outside the manifest on the wire")
    if inv.get("tracking") is not None:
        segs = row.get("tracking")
        if not isinstance(segs, list) or not segs:
            why.append(f"follows the operator: not judged ({segs or 'no segment settled'})")
        else:
            bounds = dict(inv["tracking"])
            if bounds["heading_ratio"] is not None:
                bounds["heading_ratio"] = tuple(bounds["heading_ratio"])
            why += [f"does not follow the operator: {b}"
                    for b in tracking.check(segs, argparse.Namespace(**bounds))]
    return not why, why


# ---- engines ------------------------------------------------------------------------

def run_local(tasks, workers, done):
    """Runs @tasks on @workers threads, each waiting on its rozrun; @done(task,
    result) as each ends. A rozrun killed by a signal is run again (RETRIES)."""
    stop = threading.Event()

    def one(task):
        for attempt in range(1, RETRIES + 2):
            if stop.is_set():
                return None
            r = run_sample(task)
            r["attempts"] = attempt
            if r["status"] >= 0 or attempt > RETRIES:
                return r
        return None

    with ThreadPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(one, t): t for t in tasks}
        try:
            while futures:
                ready, _ = wait(futures, return_when=FIRST_COMPLETED)
                for fu in ready:
                    t = futures.pop(fu)
                    r = fu.result()
                    if r is not None:
                        done(t, r)
        except BaseException:
            stop.set()
            for fu in futures:
                fu.cancel()
            raise


def run_ray(tasks, address, done):
    """Runs @tasks on the Ray cluster at @address: a task whose worker or node
    died is retried by Ray (max_retries); one whose rozrun was killed, here."""
    try:
        import ray
    except ImportError:
        sys.exit("roz-campaign: --ray needs Ray: pip install --require-hashes -r "
                 "tools/requirements-ray.txt (docs/campaigns.md)")
    ray.init(address=address, logging_level="ERROR", log_to_driver=False)
    # this module is not importable on the nodes: its functions travel by value
    ray.cloudpickle.register_pickle_by_value(sys.modules[__name__])
    ray.cloudpickle.register_pickle_by_value(tracking)

    @ray.remote(num_cpus=1, max_retries=RETRIES * 3, retry_exceptions=False)
    def remote(task):
        task = dict(task, node=ray.get_runtime_context().get_node_id())
        for attempt in range(1, RETRIES + 2):
            r = run_sample(task)
            r["attempts"] = attempt
            if r["status"] >= 0 or attempt > RETRIES:
                return r
        return r

    # in flight at once: a few per CPU of the cluster, so the driver holds
    # no more than that (a 10,000-sample campaign is not submitted at once)
    window = max(4, int(ray.cluster_resources().get("CPU", 1)) * 4)
    pending = {}
    it = iter(tasks)
    try:
        while True:
            while len(pending) < window:
                t = next(it, None)
                if t is None:
                    break
                pending[remote.remote(t)] = t
            if not pending:
                break
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                t = pending.pop(ref)
                try:
                    r = ray.get(ref)
                except (ray.exceptions.RayError) as e:  # retries spent: the row says so
                    r = {"status": -1, "summary": None, "stderr": str(e)[-2000:], "wall_s": 0.0,
                         "node": "", "attempts": RETRIES + 1}
                done(t, r)
    finally:
        ray.shutdown()


# ---- the command ----------------------------------------------------------------------

class Refused(Exception):
    """rozrun refused a sample's arguments (exit 2, no summary): the
    campaign cannot run as written."""


def _probe(campaign, rozrun):
    """The robot's rate, from a one-tick run of the first controller, which
    also says early what rozrun refuses: a bad robot, controller or operator
    script. It runs on the loopback port, which opens in milliseconds where
    MuJoCo loads the robot's model (as long as a short sample's simulation
    takes, on the G1: the engine's largest cost); only when loopback
    refuses does it run on the campaign's port, for that port's words. What
    only the port refuses (the robot's model) the first sample says, and
    the campaign stops there (Refused)."""
    wasm = campaign["controllers"][0]["wasm"]
    op = ["--operator", campaign["operator"]] if campaign.get("operator") else []
    # the families' operator steps: every input they may set, at 0
    inputs = []
    for fam in campaign["families"]:
        for pt in fam["perturb"]:
            if pt["kind"] == "operator":
                v = pt["fields"]["input"]
                inputs += v["choice"] if isinstance(v, dict) and "choice" in v else [v]
    with tempfile.TemporaryDirectory(prefix="roz-campaign-") as tmp:
        out = os.path.join(tmp, "probe.json")
        if inputs:
            bad = [x for x in inputs if not isinstance(x, str)]
            if bad:
                sys.exit(f"roz-campaign: {campaign['file']}: operator input {bad[0]!r}: "
                         "expected an input's name")
            op = ["--operator", os.path.join(tmp, "operator-steps.csv")]
            names = list(dict.fromkeys(inputs))
            with open(op[1], "w") as f:
                f.write("time_s," + ",".join(names) + "\n0" + ",0" * len(names) + "\n")
        try:
            h = subprocess.run([rozrun, "--port", campaign["port"], "--help"],
                               capture_output=True, text=True)
        except OSError as e:
            sys.exit(f"roz-campaign: {rozrun}: {e.strerror} (build it first: make build)")
        if f"Port {campaign['port']}" not in h.stdout:
            sys.exit(f"roz-campaign: {rozrun}: this rozrun has no {campaign['port']} port")
        for port in ("loopback", campaign["port"]):
            p = subprocess.run([rozrun, "--robot", campaign["robot"], "--port", port,
                                "--controller", wasm, "--ticks", "1", "--summary-json", out] + op,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if os.path.exists(out):
                break
        if not os.path.exists(out):
            sys.exit(f"roz-campaign: {campaign['file']}: rozrun refuses the campaign's robot, "
                     f"port, operator script or first controller:\n{p.stderr.strip()}")
        with open(out) as f:
            return json.load(f)["rate_hz"]


def default_rozrun(build):
    p = os.path.join(build, "tools", "rozrun", "rozrun")
    return p if os.path.exists(p) else shutil.which("rozrun") or p


def cmd_run(a):
    try:
        campaign = load(a.file, a.build)
    except CampaignError as e:
        print(f"roz-campaign: {e}", file=sys.stderr)
        return 2
    campaign["build"] = a.build
    if a.samples is not None:
        for fam in campaign["families"]:
            fam["samples"] = min(fam["samples"], a.samples)
    if a.family:
        names = [f["name"] for f in campaign["families"]]
        for x in a.family:
            if x not in names:
                print(f"roz-campaign: {a.file}: --family {x}: no such family (families: "
                      f"{', '.join(names)})", file=sys.stderr)
                return 2
        campaign["families"] = [f for f in campaign["families"] if f["name"] in a.family]
    rozrun = os.path.abspath(a.rozrun or default_rozrun(a.build))
    for c in campaign["controllers"]:
        if not os.path.exists(c["wasm"]):
            print(f"roz-campaign: {a.file}: controller {c['name']}: {c['wasm']}: no such file "
                  "(build it first: make build)", file=sys.stderr)
            return 2
    campaign["rate_hz"] = _probe(campaign, rozrun)
    out = a.out or os.path.join("campaign-out", campaign["name"])
    os.makedirs(out, exist_ok=True)
    campaign["out"] = os.path.abspath(out)  # the samples' operator scripts are there
    meta = {"format": FORMAT, "campaign": {k: campaign[k] for k in
            ("name", "file", "robot", "port", "duration_s", "seed", "rate_hz", "controllers",
             "families", "operator", "operator_sha256")}, "rozrun": rozrun}
    # what the samples are drawn from: a resumed campaign must be the same one
    meta["fingerprint"] = hashlib.sha256(json.dumps(
        {k: meta["campaign"][k] for k in ("robot", "duration_s", "seed", "rate_hz", "families",
                                          "operator_sha256")}
        | {"controllers": [c["name"] for c in campaign["controllers"]]},
        sort_keys=True).encode()).hexdigest()
    old = os.path.join(out, "campaign.json")
    if os.path.exists(old) and os.path.exists(os.path.join(out, "results.jsonl")):
        with open(old) as f:
            was = json.load(f).get("fingerprint")
        if was != meta["fingerprint"]:
            print(f"roz-campaign: {out} holds the results of another campaign (or of this one "
                  "with other families, samples, seed or controllers); name another --out",
                  file=sys.stderr)
            return 2
    with open(os.path.join(out, "campaign.json.tmp"), "w") as f:
        json.dump(meta, f, indent=1, sort_keys=True)
    os.replace(os.path.join(out, "campaign.json.tmp"), os.path.join(out, "campaign.json"))
    results = Results(os.path.join(out, "results.jsonl"))
    todo = [s for s in samples(campaign) if s["id"] not in results.rows]
    write_scripts(todo)
    total = len(results.rows) + len(todo)
    blobs = {}
    for c in campaign["controllers"]:
        with open(c["wasm"], "rb") as f:
            blobs[c["wasm"]] = f.read()
    if campaign.get("operator"):
        with open(campaign["operator"], "rb") as f:
            blobs[campaign["operator"]] = f.read()
    for s in todo:
        for x in s["args"]:
            if "{swap:" in x:
                p = _swap_path(campaign, x.split("{swap:", 1)[1][:-1])
                if p not in blobs:
                    with open(p, "rb") as f:
                        blobs[p] = f.read()
    by_id = {s["id"]: s for s in todo}
    fams = {f["name"]: f for f in campaign["families"]}
    workers = a.workers or os.cpu_count() or 1
    engine = f"Ray at {a.ray}" if a.ray else f"{workers} local workers"
    print(f"roz-campaign: {campaign['name']}: {total} samples ({total - len(todo)} done before), "
          f"{engine}; results in {out}/results.jsonl", flush=True)
    t0 = time.monotonic()
    counts = {"done": 0, "failed": 0}

    ticks = int(round(campaign["duration_s"] * campaign["rate_hz"]))

    def done(task, r):
        s = by_id[task["id"]]
        if r["status"] == 2 and r["summary"] is None:
            raise Refused(f"roz-campaign: {a.file}: rozrun refuses sample {s['id']}:\n"
                          f"{(r.get('stderr') or '').strip()}\n{shell(command(campaign, s, rozrun))}")
        if r["summary"] is not None and r["summary"]["ticks"] != ticks:
            return  # a run cut short (Ctrl-C reached its rozrun too): not a result
        row = {"id": s["id"], "family": s["family"], "index": s["index"],
               "controller": s["controller"], "seed": s["seed"], "values": s["values"],
               "command": command(campaign, s, rozrun), **r}
        ok, why = judge(row, fams[s["family"]]["verdict"])
        row["passed"], row["reasons"] = ok, why
        if results.add(row):
            counts["done"] += 1
            counts["failed"] += not ok
            if not a.quiet:
                print(f"  [{len(results.rows)}/{total}] {s['id']}: "
                      f"{'pass' if ok else 'FAIL: ' + '; '.join(why)}", flush=True)

    tasks = [_task(campaign, s, rozrun, blobs) for s in todo]
    try:
        if a.ray:
            run_ray(tasks, a.ray, done)
        else:
            run_local(tasks, workers, done)
    except Refused as e:
        print(e, file=sys.stderr)
        results.close()
        return 2
    except KeyboardInterrupt:
        print(f"roz-campaign: interrupted; {len(results.rows)} of {total} samples in the "
              "results, run the same command again to go on", file=sys.stderr)
        results.close()
        return 130
    results.close()
    wall = time.monotonic() - t0
    rows = read_results(os.path.join(out, "results.jsonl"))
    print(f"roz-campaign: {len(rows)} of {total} samples, {counts['done']} run now in "
          f"{wall:.1f} s, {sum(not r['passed'] for r in rows.values())} failed", flush=True)
    if not a.no_report:
        import campaign_report  # noqa: E402  (beside this file)
        page = campaign_report.write(out)
        print(f"roz-campaign: report {page}")
    return 0 if len(rows) == total else 1


def cmd_report(a):
    import campaign_report  # noqa: E402
    print(campaign_report.write(a.dir))
    return 0


def main(argv=None):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(prog="roz-campaign", description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="run a campaign file (or resume it)")
    r.add_argument("file")
    r.add_argument("--out", help="results and report (default campaign-out/NAME)")
    r.add_argument("--build", default="build", help="the build tree ({build} in the file)")
    r.add_argument("--rozrun", help="the rozrun program (default BUILD/tools/rozrun/rozrun)")
    r.add_argument("--workers", type=int, help="local workers (default: every core)")
    r.add_argument("--ray", metavar="ADDRESS", help="run on the Ray cluster at ADDRESS")
    r.add_argument("--samples", type=int, help="at most N samples a family (a quick look)")
    r.add_argument("--family", action="append", metavar="NAME",
                   help="only this family (repeat for more; a quick look)")
    r.add_argument("--no-report", action="store_true")
    r.add_argument("--quiet", action="store_true")
    p = sub.add_parser("report", help="write the report of a campaign's results again")
    p.add_argument("dir")
    a = ap.parse_args(argv)
    signal.signal(signal.SIGTERM, signal.default_int_handler)
    return cmd_run(a) if a.cmd == "run" else cmd_report(a)


if __name__ == "__main__":
    sys.exit(main())
