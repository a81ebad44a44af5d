# SPDX-License-Identifier: Apache-2.0
"""roz-campaign on local workers: the file's rules, the samples drawn, every
sample exactly once (resumed after an interruption, a killed rozrun run
again), the report read back, and a failing sample's printed command that
runs it again bit for bit."""
import csv
import filecmp
import json
import os
import signal
import subprocess
import time

import matplotlib.image
import pytest

import campaign
from conftest import CAMPAIGN, rows, run


def test_file_errors_name_file_and_key(tmp_path):
    cases = [
        ("[campaign]\nrobot='unitree_g1'\nduration_s=1\nspeed=2\n", "campaign.speed: unknown key"),
        ("[campaign]\nduration_s=1\n", "campaign.robot: missing"),
        ("[campaign]\nrobot='r'\nduration_s=-1\n", "campaign.duration_s: expected seconds"),
        ("[campaign]\nrobot='r'\nduration_s=1\nport='unitree/G1'\n", "mujoco port only"),
        ("[campaign]\nrobot='r'\nduration_s=1\noperator='walk.csv'\n",
         "campaign.operator: \"walk.csv\": no such file"),
        ("[campaign]\nrobot='r'\nduration_s=1\noperator=3\n",
         "campaign.operator: expected a file"),
        ("[campaign]\nrobot='r'\nduration_s=1\n[[controllers]]\nname='a'\nwasm='a.wasm'\n"
         "[[families]]\nname='f'\n[[families.perturb]]\nkind='shove'\n",
         "families[0].perturb[0].kind: 'shove'"),
        ("[campaign]\nrobot='r'\nduration_s=1\n[[controllers]]\nname='a'\nwasm='a.wasm'\n"
         "[[families]]\nname='f'\n[[families.perturb]]\nkind='push'\nat=1\n",
         "families[0].perturb[0].force: missing"),
        ("[campaign]\nrobot='r'\nduration_s=1\n[[controllers]]\nname='a'\nwasm='a.wasm'\n"
         "[[families]]\nname='f'\n[[families.perturb]]\nkind='push'\nat=1\n"
         "force={uniform=[5,1]}\n", "must not exceed"),
        ("[campaign]\nrobot='r'\nduration_s=1\n[[controllers]]\nname='a'\nwasm='a.wasm'\n"
         "[[families]]\nname='f'\nverdict={stands=1}\n", "families[0].verdict.stands"),
        ("[campaign]\nrobot='r'\nduration_s=1\n[[controllers]]\nname='a'\nwasm='a.wasm'\n"
         "[[families]]\nname='f'\ncontrollers=['b']\n", "families[0].controllers"),
        ("[campaign\n", "Expected ']'"),
    ]
    for text, words in cases:
        path = tmp_path / "c.toml"
        path.write_text(text)
        with pytest.raises(campaign.CampaignError) as e:
            campaign.load(str(path))
        assert str(e.value).startswith(f"{path}: ") and words in str(e.value), (text, e.value)


def test_samples_drawn_from_the_seed_and_paired(tiny):
    c = campaign.load(tiny(samples=3))
    c["rate_hz"] = 500
    a, b = campaign.samples(c), campaign.samples(c)
    assert a == b and len(a) == 2 * 3 * 2
    by = {(s["family"], s["index"], s["controller"]): s for s in a}
    for fam in ("push", "payload"):
        for i in range(3):
            # the builds are compared on the same runs: the same values, seed, arguments
            sa, sb = by[(fam, i, "stand")], by[(fam, i, "pd")]
            assert (sa["values"], sa["seed"], sa["args"]) == (sb["values"], sb["seed"], sb["args"])
    assert [by[("push", i, "pd")]["values"]["push.force"] for i in range(3)] == [50, 775, 1500]
    assert len({by[("payload", i, "pd")]["seed"] for i in range(3)}) == 3
    cmd = by[("push", 2, "pd")]["args"]
    assert "push=1500,0,0@pelvis@50:100" in cmd and f"noise_seed={by[('push', 2, 'pd')]['seed']}" in cmd
    assert any(x.startswith("payload=") and x.endswith("@torso_link")
               for x in by[("payload", 0, "pd")]["args"])
    # another seed, other values
    c2 = dict(c, seed=8)
    assert campaign.samples(c2)[-1]["values"] != a[-1]["values"]


def test_results_exactly_once_and_cut_lines(tmp_path):
    path = str(tmp_path / "results.jsonl")
    r = campaign.Results(path)
    assert r.add({"id": "a/0/x", "v": 1}) and not r.add({"id": "a/0/x", "v": 2})
    r.close()
    with open(path, "ab") as f:
        f.write(b'{"id": "a/1/x", "v"')  # a crash mid-line
    r = campaign.Results(path)
    assert set(r.rows) == {"a/0/x"} and r.rows["a/0/x"]["v"] == 1
    assert r.add({"id": "a/1/x", "v": 3})
    r.close()
    assert set(campaign.read_results(path)) == {"a/0/x", "a/1/x"}


def test_run_report_and_reproduce(tiny, tmp_path):
    out = str(tmp_path / "out")
    p = run("run", tiny(), "--out", out, "--workers", "2")
    assert p.returncode == 0, p.stderr + p.stdout
    got = rows(out)
    ids = [r["id"] for r in got]
    assert len(ids) == len(set(ids)) == 8
    by = {r["id"]: r for r in got}
    # the 1500 N shove fells both; every row judged, its figures kept
    for ct in ("stand", "pd"):
        r = by[f"push/1/{ct}"]
        assert not r["passed"] and r["reasons"][0].startswith("fell"), r["reasons"]
        assert r["summary"]["truth"]["base_height_min"] < 0.6
    assert by["push/0/stand"]["passed"], by["push/0/stand"]["reasons"]

    # the CSV, every sample
    with open(os.path.join(out, "results.csv"), newline="") as f:
        table = list(csv.DictReader(f))
    assert sorted(t["id"] for t in table) == sorted(ids)
    row = next(t for t in table if t["id"] == "push/1/pd")
    assert row["passed"] == "0" and float(row["value:push.force"]) == 1500
    assert float(row["base_height_min"]) == by["push/1/pd"]["summary"]["truth"]["base_height_min"]
    # the peak joint speed, as rozrun's summary has it
    speed = by["push/1/pd"]["summary"]["joint_speed_max"]
    assert float(row["joint_speed_max"]) == speed["value"] > 1.0  # felled
    assert row["joint_speed_max_joint"] == speed["joint"]
    # the page: pass rates, boundary, the builds compared, the worst cases
    page = open(os.path.join(out, "index.html")).read()
    for words in ('id="pass-rate"', 'id="boundaries"', 'id="compare"', "push.force",
                  "Peak joint speed: ",
                  "1/2 (50 %)", "case-1", campaign.shell(by["push/1/stand"]["command"])
                  .replace("'", "&#39;").split(" ")[0]):
        assert words in page, words
    for png in os.listdir(os.path.join(out, "plots")):
        img = matplotlib.image.imread(os.path.join(out, "plots", png))
        assert img.shape[0] > 100 and img.shape[1] > 100 and img.std() > 0.01, png

    # the failing sample's command runs it again: the same run, bit for bit
    bad = by["push/1/stand"]
    cmd = bad["command"]
    runs = []
    for k in range(2):
        trace, summ = str(tmp_path / f"t{k}.csv"), str(tmp_path / f"s{k}.json")
        q = subprocess.run(cmd + ["--trace", trace, "--summary-json", summ],
                           capture_output=True, text=True)
        assert q.returncode == bad["status"], q.stderr
        with open(summ) as f:
            runs.append(json.load(f))
    assert filecmp.cmp(tmp_path / "t0.csv", tmp_path / "t1.csv", shallow=False)
    for s in runs:  # what the campaign measured is what the command gives
        for k in ("truth", "faults", "counters", "port_counters", "wire_violations", "fuel"):
            assert s[k] == bad["summary"][k], k


def _children(pid):
    out = []
    for t in os.listdir(f"/proc/{pid}/task"):
        try:
            with open(f"/proc/{pid}/task/{t}/children") as f:
                out += [int(x) for x in f.read().split()]
        except OSError:
            pass
    return out


def test_interrupted_resumes_and_killed_rozrun_retried(tiny, tmp_path):
    out = str(tmp_path / "out")
    # samples long enough that a quiet machine's rozrun is still running
    # when the loop below looks (0.6 s of simulation ended between looks)
    path = tiny(duration=4.0, samples=3)
    log = str(tmp_path / "tasks.log")
    env = dict(os.environ, ROZ_CAMPAIGN_TASK_LOG=log)
    # first: one rozrun killed under the driver, then the driver interrupted
    d = subprocess.Popen(CAMPAIGN + ["run", path, "--out", out, "--workers", "2", "--no-report"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    killed = None
    deadline = time.monotonic() + 300
    while killed is None and time.monotonic() < deadline and d.poll() is None:
        for c in _children(d.pid):
            try:
                with open(f"/proc/{c}/cmdline", "rb") as f:
                    argv = f.read().split(b"\0")
            except OSError:
                continue
            # a sample's rozrun (not the first one-tick run that asks the rate)
            seeds = [x for x in argv if x.startswith(b"noise_seed=")]
            if argv and argv[0].endswith(b"rozrun") and seeds:
                os.kill(c, signal.SIGKILL)
                killed = int(seeds[0].split(b"=")[1])  # the sample's seed
                break
        time.sleep(0.01)
    assert killed is not None
    # interrupted once the killed sample is in (run again) and a few more
    while d.poll() is None and time.monotonic() < deadline:
        if os.path.exists(os.path.join(out, "results.jsonl")):
            got = rows(out)
            if len(got) >= 3 and any(r["seed"] == killed and r["attempts"] == 2 for r in got):
                d.send_signal(signal.SIGINT)
                break
        time.sleep(0.1)
    d.communicate(timeout=300)
    first = {r["id"]: r for r in rows(out)}
    assert 0 < len(first) < 12 or d.returncode == 0
    # a crash cut the last line short
    with open(os.path.join(out, "results.jsonl"), "ab") as f:
        f.write(b'{"id": "payload/2/pd", "stat')
    p = run("run", path, "--out", out, "--workers", "2", "--no-report", env=env)
    assert p.returncode == 0, p.stderr
    final = list(campaign.read_results(os.path.join(out, "results.jsonl")).values())
    with open(os.path.join(out, "results.jsonl"), "rb") as f:
        lines = [x for x in f.read().split(b"\n") if x.strip()]
    assert len(lines) == 13  # twelve samples and the cut line, which counts for none
    ids = [r["id"] for r in final if "summary" in r]
    assert sorted(ids) == sorted(set(ids)) and len(ids) == 12
    for r in final:  # what was there stays as it was
        if r["id"] in first:
            assert r == first[r["id"]]
    # the killed sample was run again, and counted once
    assert [r["attempts"] for r in final if r.get("seed") == killed] in ([1, 2], [2, 1])
    # another campaign in the same folder is refused
    other = tiny(samples=2, name="other.toml")
    p = run("run", other, "--out", out)
    assert p.returncode == 2 and "another campaign" in p.stderr


def test_operator_script_reaches_every_sample(tmp_path):
    """[campaign] operator = "FILE.csv": every sample's rozrun runs with
    --operator (the file shipped to the worker with the controller), the
    probe checks the script against the robot, and the printed command
    carries it: its trace shows the inputs the controller read, the
    script's. (The controller here, deploy_mujoco's shape, compiles its
    command in; it runs all the same.)"""
    from conftest import need_mujoco, BUILD
    need_mujoco()
    ctl = os.path.join(BUILD, "examples", "controllers", "g1_12dof_deployed.wasm")
    if not os.path.exists(ctl):
        pytest.skip("the deployed 12-joint G1 policy is not built")
    (tmp_path / "walk.csv").write_text(
        "time_s,operator/velocity.x,operator/velocity.y,operator/yaw_rate\n"
        "0,0,0,0\n0.2,0.4,0,0\n")
    path = tmp_path / "walk.toml"
    path.write_text(f"""
[campaign]
robot = "unitree_g1_12dof"
duration_s = 0.6
operator = "walk.csv"

[[controllers]]
name = "policy"
wasm = "{ctl}"

[verdict]
min_base_height = 0.5

[[families]]
name = "nominal"
samples = 1
""")
    c = campaign.load(str(path))
    assert c["operator"] == str(tmp_path / "walk.csv")
    out = str(tmp_path / "out")
    p = run("run", str(path), "--out", out, "--workers", "1", "--no-report")
    assert p.returncode == 0, p.stderr + p.stdout
    (r,) = rows(out)
    assert r["status"] == 0, r["stderr"]
    cmd = r["command"]
    assert cmd[cmd.index("--operator") + 1] == str(tmp_path / "walk.csv")
    trace = str(tmp_path / "t.csv")
    q = subprocess.run(cmd + ["--trace", trace, "--summary-json", str(tmp_path / "s.json")],
                       capture_output=True, text=True)
    assert q.returncode == 0, q.stderr
    with open(trace, newline="") as f:
        got = [(float(t["time_s"]), float(t["input:operator/velocity.x"]))
               for t in csv.DictReader(f)]
    assert all(v == 0.0 for t, v in got if t < 0.19) and got[-1][1] > 0.0
    with open(tmp_path / "s.json") as f:
        assert json.load(f)["truth"] == r["summary"]["truth"]  # the campaign's run, again
    # a script the robot refuses is said at the start, naming the file
    (tmp_path / "walk.csv").write_text("time_s,operator/nothing\n0,1\n")
    p = run("run", str(path), "--out", str(tmp_path / "out2"), "--workers", "1", "--no-report")
    assert p.returncode != 0 and "walk.csv" in p.stderr, p.stderr


def test_sample_rozrun_refuses_stops_the_campaign(tiny, tmp_path):
    """The first one-tick run opens the loopback port, not MuJoCo (the
    model's load costs as much as a short sample): what only a sample's run
    refuses (a push at a body the model lacks) stops the campaign at that
    sample, saying rozrun's words and the command, and writes no row."""
    from conftest import ROZRUN
    path = tiny()
    with open(path) as f:
        text = f.read()
    with open(path, "w") as f:
        f.write(text.replace('at = 0.1\n', 'at = 0.1\nbody = "nobody"\n', 1))
    out = str(tmp_path / "out")
    p = run("run", path, "--out", out, "--workers", "1", "--no-report", "--rozrun", ROZRUN)
    assert p.returncode == 2, p.stderr + p.stdout
    assert "rozrun refuses sample push/" in p.stderr and "nobody" in p.stderr, p.stderr
    assert rows(out) == []
