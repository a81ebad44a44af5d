# SPDX-License-Identifier: Apache-2.0
"""bench/campaign: what roz-campaign costs over bare rozrun, how it scales,
and Ray against the local pool, on the G1 (the balancing stand, a push
family), all in the same run.

    bench_campaign.py --build BUILD [--samples N] [--seconds S] [--rounds R] [--json FILE]
                      [--ray]

Figures, each in simulated seconds per wall second (per core where said):
  - bare rozrun: the samples' own rozrun commands, one after another (one core);
  - bare rozrun, two at once: the same commands, two running at any time
    (as many as the campaign's workers), no campaign: the machine's own
    ceiling (shared caches, clocks that slow when both cores work);
  - the campaign on one local worker (the same samples): its cost over bare
    rozrun is the engine's (the driver, a temporary folder and the summary a
    sample, the results file), in wall time and in CPU time (the driver and
    its rozruns against the bare rozruns: what the engine spends, however
    loaded the machine is);
  - the campaign on two local workers: scaling = (two workers / one) / 2,
    against linear, and against the machine's ceiling (two bare at once /
    one bare); the engine's share of the gap to linear is the part of it
    the machine's ceiling does not explain;
  - with --ray: the campaign on a one-node Ray cluster of two CPUs on
    127.0.0.1 (run it in a network namespace: test/run_netns.sh), against
    the two local workers.
Bare rozrun and the campaigns alternate --rounds times (2), each figure the
best of its rounds. Then an estimate of a 10,000-sample G1 campaign (10 s simulated a sample) on
100 nodes of 32 cores from these figures. A benchmark, not a test: it
prints, it never fails on a time; --json appends JSON lines for
bench/report.py.
"""
import argparse
import json
from concurrent.futures import ThreadPoolExecutor
import os
import resource
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import campaign  # noqa: E402

FILE = """
[campaign]
name = "bench"
robot = "unitree_g1"
duration_s = {seconds}
seed = 3
samples = {samples}

[[controllers]]
name = "g1_stand"
wasm = "{wasm}"

[verdict]
min_base_height = 0.6

[[families]]
name = "push"
[[families.perturb]]
kind = "push"
force = {{ uniform = [30, 90] }}
direction = {{ uniform = [0, 360] }}
at = 1.5
"""


def cpu():
    """CPU seconds (user + system) of every child process waited for."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_campaign(path, out, *extra):
    t0 = time.monotonic()
    p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "campaign.py"), "run", path,
                        "--out", out, "--no-report", "--quiet"] + list(extra),
                       capture_output=True, text=True)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit(f"bench_campaign: the campaign failed:\n{p.stderr[-2000:]}")
    return wall


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--samples", type=int, default=8)
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--json")
    ap.add_argument("--ray", action="store_true")
    ap.add_argument("--rounds", type=int, default=2, help="alternations, each figure its best")
    a = ap.parse_args()
    rozrun = os.path.abspath(os.path.join(a.build, "tools", "rozrun", "rozrun"))
    wasm = os.path.abspath(os.path.join(a.build, "examples", "controllers", "g1_stand.wasm"))
    work = tempfile.mkdtemp(prefix="roz-bench-campaign-")
    figures = []

    def fig(name, value, unit, **more):
        figures.append(dict(name=name, value=value, unit=unit, **more))
        print(f"  {name}: {value:,.3f} {unit}")

    try:
        path = os.path.join(work, "bench.toml")
        with open(path, "w") as f:
            f.write(FILE.format(seconds=a.seconds, samples=a.samples, wasm=wasm))
        c = campaign.load(path)
        c["rate_hz"] = 500
        sim = a.samples * a.seconds
        print(f"bench_campaign: {a.samples} G1 samples of {a.seconds} s simulated")
        # bare rozrun and the campaign alternate, rounds times, each keeping its
        # best: a machine whose load drifts is less unfair to either
        cmds = [campaign.command(c, s, rozrun) + ["--summary-json",
                                                  os.path.join(work, f"bare-{i}.json")]
                for i, s in enumerate(campaign.samples(c))]

        def bare_run(cmd):
            subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

        bare = par = one = two = 0.0
        bare_cpu = one_cpu = float("inf")
        for k in range(a.rounds):
            t0, c0 = time.monotonic(), cpu()
            for cmd in cmds:
                bare_run(cmd)
            bare = max(bare, sim / (time.monotonic() - t0))
            bare_cpu = min(bare_cpu, cpu() - c0)
            t0 = time.monotonic()
            with ThreadPoolExecutor(max_workers=2) as pool:
                list(pool.map(bare_run, cmds))
            par = max(par, sim / (time.monotonic() - t0))
            c0 = cpu()
            one = max(one, sim / run_campaign(path, os.path.join(work, f"w1-{k}"), "--workers",
                                              "1", "--rozrun", rozrun))
            one_cpu = min(one_cpu, cpu() - c0)
            two = max(two, sim / run_campaign(path, os.path.join(work, f"w2-{k}"), "--workers",
                                              "2", "--rozrun", rozrun))
        fig("bare rozrun, one core", bare, "sim s / wall s")
        fig("campaign, one local worker", one, "sim s / wall s", ratio=one / bare)
        fig("campaign engine cost over bare rozrun", 100.0 * (1.0 - one / bare), "%")
        # the same in CPU time (the driver and its rozruns against the bare
        # rozruns): what the engine spends, whatever else the machine runs
        fig("campaign engine cost over bare rozrun, CPU time",
            100.0 * (one_cpu / bare_cpu - 1.0), "%", cpu_s=one_cpu, bare_cpu_s=bare_cpu)
        fig("bare rozrun, two at once (the machine's ceiling)", par, "sim s / wall s",
            ratio=par / (2.0 * bare))
        fig("campaign, two local workers", two, "sim s / wall s", ratio=two / par)
        scaling, ceiling = two / (2.0 * one), par / (2.0 * bare)
        fig("scaling, two workers / (2 x one)", scaling, "x linear")
        fig("scaling against the machine's ceiling", scaling / ceiling, "x ceiling")
        # of the gap to linear, the part the machine's own ceiling does not explain
        fig("the engine's share of the gap to linear",
            # (a ceiling measured above linear is noise: linear is the most)
            100.0 * min(1.0, max(0.0, min(1.0, ceiling) - scaling) / max(1e-9, 1.0 - scaling)),
            "%")
        ray_rate = None
        if a.ray:
            ray_rate = bench_ray(path, work, rozrun, sim)
            if ray_rate is not None:
                fig("campaign, Ray, one node of two CPUs", ray_rate, "sim s / wall s",
                    ratio=ray_rate / two)
        # the estimate: 10,000 samples of 10 s on 100 nodes of 32 cores
        per_core = one * min(1.0, two / (2.0 * one))
        if ray_rate is not None:
            per_core *= min(1.0, ray_rate / two)
        total = 10000 * 10.0 / (per_core * 100 * 32)
        fig("estimate: 10,000 G1 samples of 10 s on 100 nodes x 32 cores", total / 60.0,
            "min", per_core=per_core)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if a.json:
        with open(a.json, "a") as f:
            for x in figures:
                f.write(json.dumps(x) + "\n")
    return 0


def bench_ray(path, work, rozrun, sim):
    try:
        import ray  # noqa: F401
    except ImportError:
        print("  Ray: not installed (tools/setup.sh --ray)")
        return None
    exe = os.path.join(os.path.dirname(sys.executable), "ray")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    tmp = tempfile.mkdtemp(prefix="rozray")
    env = dict(os.environ, RAY_USAGE_STATS_ENABLED="0")
    head = subprocess.Popen([exe, "start", "--head", f"--port={port}", f"--temp-dir={tmp}",
                             "--node-ip-address=127.0.0.1", "--num-cpus=2",
                             "--include-dashboard=false", "--disable-usage-stats",
                             "--object-store-memory=80000000", "--block"],
                            env=env, start_new_session=True, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        for _ in range(900):
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                time.sleep(0.2)
        # a first campaign warms the workers up; the second is measured
        run_campaign(path, os.path.join(work, "ray0"), "--ray", f"127.0.0.1:{port}",
                     "--rozrun", rozrun)
        return sim / run_campaign(path, os.path.join(work, "ray1"), "--ray",
                                  f"127.0.0.1:{port}", "--rozrun", rozrun)
    finally:
        os.killpg(head.pid, signal.SIGKILL)  # the cluster this bench started, by its id
        head.wait()
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
