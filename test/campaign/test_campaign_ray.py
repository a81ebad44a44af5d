# SPDX-License-Identifier: Apache-2.0
"""roz-campaign on a Ray cluster of two nodes on 127.0.0.1 (ctest runs this in
a network namespace of its own, test/run_netns.sh): the second node is
killed while it runs a sample; Ray runs that sample again on the first, and
every sample is in the results exactly once."""
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time

import pytest

import campaign
from conftest import CAMPAIGN

ray = pytest.importorskip("ray", reason="Ray is not installed (tools/setup.sh --ray)")
RAY = os.path.join(os.path.dirname(sys.executable), "ray")


def _port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_for(port, head):
    """Until the head's GCS takes connections on @port."""
    deadline = time.monotonic() + 180
    while time.monotonic() < deadline:
        assert head.poll() is None, "ray start --head ended"
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return
        except OSError:
            time.sleep(0.2)
    raise AssertionError("the head never listened")


def _wait_for_nodes(port, n):
    """Until the cluster has @n nodes alive."""
    probe = ("import ray, time\n"
             f"ray.init(address='127.0.0.1:{port}', logging_level='ERROR')\n"
             "for _ in range(600):\n"
             f"    if sum(x['Alive'] for x in ray.nodes()) >= {n}: break\n"
             "    time.sleep(0.2)\n"
             f"else: raise SystemExit('fewer than {n} nodes')\n")
    p = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]


def test_node_killed_mid_run_every_sample_once(tiny, tmp_path):
    path = tiny(samples=2)
    tmp = tempfile.mkdtemp(prefix="rozray")  # short: Ray's sockets live under it
    port = _port()
    env = dict(os.environ, RAY_USAGE_STATS_ENABLED="0",
               # a dead node is noticed in about a second, not thirty
               RAY_health_check_initial_delay_ms="0", RAY_health_check_period_ms="300",
               RAY_health_check_timeout_ms="300", RAY_health_check_failure_threshold="3")
    # the tasks run in the nodes' workers, with the nodes' environment
    log = str(tmp_path / "tasks.log")
    env["ROZ_CAMPAIGN_TASK_LOG"] = log
    common = ["--node-ip-address=127.0.0.1", "--num-cpus=1", "--object-store-memory=80000000",
              "--disable-usage-stats"]
    # each node a process group of its own, ended by its id (never `ray stop`,
    # which ends every Ray process of the machine by name)
    head = subprocess.Popen([RAY, "start", "--head", f"--port={port}", f"--temp-dir={tmp}",
                             "--include-dashboard=false", "--block"] + common,
                            env=dict(env, ROZ_CAMPAIGN_NODE="head"), start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _wait_for(port, head)
    victim = subprocess.Popen([RAY, "start", f"--address=127.0.0.1:{port}", "--block"] + common,
                              env=dict(env, ROZ_CAMPAIGN_NODE="victim"), start_new_session=True,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    out = str(tmp_path / "out")
    driver = None
    try:
        _wait_for_nodes(port, 2)
        driver = subprocess.Popen(CAMPAIGN + ["run", path, "--out", out, "--ray",
                                              f"127.0.0.1:{port}", "--no-report"],
                                  env=env,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        # kill the second node while it runs a sample
        deadline = time.monotonic() + 300
        lost = None
        while lost is None and time.monotonic() < deadline and driver.poll() is None:
            if os.path.exists(log):
                lines = [x.split() for x in open(log).read().splitlines() if x.strip()]
                on_victim = [i for i, n in lines if n == "victim"]
                if on_victim:
                    lost = on_victim[-1]
                    os.killpg(victim.pid, signal.SIGKILL)
                    break
            time.sleep(0.05)
        if lost is None and driver.poll() is not None:
            o, e = driver.communicate()
            raise AssertionError(f"the driver ended first:\n{e[-3000:]}\n{o[-2000:]}")
        assert lost is not None, "no sample ran on the second node"
        stdout, stderr = driver.communicate(timeout=400)
        assert driver.returncode == 0, stderr[-3000:] + stdout[-2000:]
    finally:
        if driver is not None and driver.poll() is None:
            driver.kill()
        for node in (victim, head):
            try:
                os.killpg(node.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            node.wait()
    rows = campaign.read_results(os.path.join(out, "results.jsonl"))
    with open(os.path.join(out, "results.jsonl")) as f:
        lines = [x for x in f.read().splitlines() if x.strip()]
    assert len(lines) == len(rows) == 8  # every sample, each once
    assert all(r["status"] in (0, 1) and r["summary"] for r in rows.values())
    starts = [x.split() for x in open(log).read().splitlines() if x.strip()]
    # the sample the killed node was running started again on the head
    assert [n for i, n in starts if i == lost][-1] == "head", starts
    assert {n for _, n in starts} == {"head", "victim"}


def test_operator_steps_and_tracking_on_ray(tmp_path):
    """A family's own operator scripts and the tracking verdict on Ray: the
    scripts travel with the tasks, tools/tracking.py with this module, and
    every row is the local engine's (the same truth, segments, verdict)."""
    import test_operator
    from conftest import ROZRUN, need_mujoco, rows
    need_mujoco()
    if not os.path.exists(test_operator.STAND):
        pytest.skip("the 12-joint G1 stand is not built")
    path = test_operator.write(tmp_path, walk=1)
    tmp = tempfile.mkdtemp(prefix="rozray")
    port = _port()
    env = dict(os.environ, RAY_USAGE_STATS_ENABLED="0")
    head = subprocess.Popen([RAY, "start", "--head", f"--port={port}", f"--temp-dir={tmp}",
                             "--include-dashboard=false", "--block", "--num-cpus=2",
                             "--node-ip-address=127.0.0.1", "--object-store-memory=80000000",
                             "--disable-usage-stats"],
                            env=env, start_new_session=True, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        _wait_for(port, head)
        _wait_for_nodes(port, 1)
        p = subprocess.run(CAMPAIGN + ["run", path, "--out", str(tmp_path / "ray"), "--ray",
                                       f"127.0.0.1:{port}", "--no-report", "--rozrun", ROZRUN],
                           env=env, capture_output=True, text=True, timeout=600)
        assert p.returncode == 0, p.stderr[-3000:] + p.stdout[-2000:]
    finally:
        os.killpg(head.pid, signal.SIGKILL)  # the node this test started, by its id
        head.wait()
    p = subprocess.run(CAMPAIGN + ["run", path, "--out", str(tmp_path / "local"), "--no-report",
                                   "--rozrun", ROZRUN], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr[-3000:]
    on_ray = {r["id"]: r for r in rows(str(tmp_path / "ray"))}
    local = {r["id"]: r for r in rows(str(tmp_path / "local"))}
    assert set(on_ray) == set(local) == {"stay/0/stand", "walk/0/stand"}
    for k, r in on_ray.items():
        assert r["tracking"] and r["tracking"] == local[k]["tracking"], k
        assert r["summary"]["truth"] == local[k]["summary"]["truth"], k
        assert (r["passed"], r["reasons"]) == (local[k]["passed"], local[k]["reasons"]), k
    assert on_ray["stay/0/stand"]["passed"] and not on_ray["walk/0/stand"]["passed"]
