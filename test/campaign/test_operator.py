# SPDX-License-Identifier: Apache-2.0
"""The operator in a campaign: a family's operator steps make each sample's
own script (rozrun --operator), written where the printed command names it;
and "follows the operator" (verdict.tracking), judged from the run's trace
with tools/tracking.py's measures: a stand told to stay tracks, the same
stand told to walk does not."""
import csv
import json
import os
import subprocess
import sys

import pytest

import campaign
import tracking
from conftest import BUILD, ROZRUN, TOOLS, need_mujoco, rows, run

#: a stand on the 12-joint G1, the robot with operator inputs (its
#: operator/velocity.x and friends); it stands, it does not walk
STAND = os.path.join(BUILD, "test", "ports", "mujoco", "g1_12dof_stand.wasm")

FILE = """
[campaign]
name = "walk"
robot = "unitree_g1_12dof"
duration_s = {duration}
seed = 5

[[controllers]]
name = "stand"
wasm = "{wasm}"

[verdict]
min_base_height = 0.5
tracking = {{ settle = 0.5, max_speed_error = 0.2, max_yaw_rate_error = 0.2, max_stop_drift = 0.1 }}

[[families]]
name = "stay"
samples = 1
[[families.perturb]]
kind = "operator"
value = 0

[[families]]
name = "walk"
samples = {walk}
boundary = {{ value = "operator.value", worse = "higher" }}
[[families.perturb]]
kind = "operator"
input = "operator/velocity.x"
value = {{ linspace = [0.4, 0.6] }}
at = {{ uniform = [0.3, 0.5] }}
[[families.perturb]]
kind = "operator"
input = "operator/yaw_rate"
value = 0.3
at = 1.4
duration = 0.3
"""


def write(tmp_path, duration=2.0, walk=2, wasm=STAND):
    path = tmp_path / "walk.toml"
    path.write_text(FILE.format(duration=duration, walk=walk, wasm=wasm))
    return str(path)


def test_operator_steps_make_each_samples_script(tmp_path):
    c = campaign.load(write(tmp_path, duration=3.0, walk=3))
    c["rate_hz"] = 500
    c["out"] = str(tmp_path / "out")
    got = {s["id"]: s for s in campaign.samples(c)}
    assert campaign.samples(c) == list(got.values())  # drawn from the seed: the same again
    stay = got["stay/0/stand"]
    assert stay["script"] == "time_s,operator/velocity.x\n0,0\n"
    assert stay["operator_file"] == str(tmp_path / "out" / "operators" / "stay-0.csv")
    scripts = [got[f"walk/{i}/stand"] for i in range(3)]
    for i, s in enumerate(scripts):
        v = s["values"]
        assert v["operator.value"] == pytest.approx(0.4 + 0.1 * i)
        assert 0.3 <= v["operator.at"] <= 0.5 and v["operator2.at"] == 1.4
        at, vx = campaign._g(v["operator.at"]), campaign._g(v["operator.value"])
        # every input held from its row on; the yaw step ends, the walk does not
        assert s["script"] == ("time_s,operator/velocity.x,operator/yaw_rate\n0,0,0\n"
                               f"{at},{vx},0\n1.4,{vx},0.3\n1.7,{vx},0\n")
        # tools/tracking.py reads it as the command it is
        path = tmp_path / f"s{i}.csv"
        path.write_text(s["script"])
        assert tracking.commands(tracking.read_operator(str(path)))[1] == \
            (float(at), (float(vx), 0.0, 0.0))
        cmd = campaign.command(c, s, "rozrun")
        assert cmd[cmd.index("--operator") + 1] == s["operator_file"]
    assert len({s["values"]["operator.at"] for s in scripts}) == 3


def test_operator_and_tracking_file_errors(tmp_path):
    (tmp_path / "w.csv").write_text("time_s,operator/velocity.x\n0,0\n")
    head = ("[campaign]\nrobot='r'\nduration_s=1\n{op}\n[[controllers]]\nname='a'\n"
            "wasm='a.wasm'\n")
    step = "[[families.perturb]]\nkind='operator'\nvalue=1\n"
    cases = [
        (head.format(op="operator='w.csv'") + "[[families]]\nname='f'\n" + step,
         "families[0].perturb[0]: an operator step"),
        (head.format(op="") + "[verdict]\ntracking={max_speed_error=0.1}\n"
         "[[families]]\nname='f'\n", "families[0].verdict.tracking: follows the operator"),
        (head.format(op="") + "[verdict]\ntracking={max_speed=0.1}\n[[families]]\nname='f'\n"
         + step, "verdict.tracking.max_speed: unknown bound"),
        (head.format(op="") + "[verdict]\ntracking={settle=1}\n[[families]]\nname='f'\n" + step,
         "verdict.tracking: no bound"),
        (head.format(op="") + "[verdict]\ntracking={heading_ratio=[2,1]}\n[[families]]\n"
         "name='f'\n" + step, "verdict.tracking.heading_ratio: expected [lo, hi]"),
        (head.format(op="") + "[[families]]\nname='f'\n[[families.perturb]]\nkind='operator'\n",
         "families[0].perturb[0].value: missing"),
    ]
    for text, words in cases:
        path = tmp_path / "c.toml"
        path.write_text(text)
        with pytest.raises(campaign.CampaignError) as e:
            campaign.load(str(path))
        assert words in str(e.value), (text, e.value)


def test_tracking_invariant_passes_a_stay_fails_a_walk(tmp_path):
    """The stand told to stay tracks (no drift); told to walk, it does not,
    and the verdict says which segment and by how much. The failing
    sample's printed command, with its own script, runs it again: the same
    truth, and tools/tracking.py on its trace finds the same errors."""
    need_mujoco()
    if not os.path.exists(STAND):
        pytest.skip("the 12-joint G1 stand is not built")
    path = write(tmp_path)
    out = str(tmp_path / "out")
    p = run("run", path, "--out", out, "--workers", "2", "--rozrun", ROZRUN)
    assert p.returncode == 0, p.stderr + p.stdout
    got = {r["id"]: r for r in rows(out)}
    # the report's table: each sample's worst tracking figures
    with open(os.path.join(out, "results.csv"), newline="") as f:
        table = {t["id"]: t for t in csv.DictReader(f)}
    assert float(table["walk/1/stand"]["speed_error_max"]) > 0.2
    assert float(table["stay/0/stand"]["stop_drift_max"]) < 0.1
    assert table["stay/0/stand"]["speed_error_max"] == ""
    assert set(got) == {"stay/0/stand", "walk/0/stand", "walk/1/stand"}
    stay = got["stay/0/stand"]
    assert stay["status"] == 0, stay["stderr"]
    assert stay["passed"], stay["reasons"]
    (seg,) = stay["tracking"]
    assert seg["kind"] == "stop" and seg["drift_m"] < 0.1
    for i in range(2):
        walk = got[f"walk/{i}/stand"]
        assert walk["status"] == 0, walk["stderr"]
        assert not walk["passed"]
        assert any("does not follow the operator" in w and "vx_error" in w
                   for w in walk["reasons"]), walk["reasons"]
        # standing: the base still up, the only complaint the tracking
        assert all("does not follow the operator" in w for w in walk["reasons"])
        moving = [s for s in walk["tracking"] if s["kind"] != "stop"]
        assert moving and all(s["vx_error"] > 0.2 for s in moving if s["command"][0] > 0)
    # the failing sample, again, from its printed command and its own script
    walk = got["walk/1/stand"]
    cmd = walk["command"]
    script = cmd[cmd.index("--operator") + 1]
    assert os.path.dirname(script) == os.path.join(out, "operators")
    trace, summary = str(tmp_path / "t.csv"), str(tmp_path / "s.json")
    q = subprocess.run(cmd + ["--trace", trace, "--summary-json", summary],
                       capture_output=True, text=True)
    assert q.returncode == 0, q.stderr
    with open(summary) as f:
        assert json.load(f)["truth"] == walk["summary"]["truth"]
    t = subprocess.run([sys.executable, os.path.join(TOOLS, "tracking.py"), trace,
                        "--operator", script, "--settle", "0.5", "--max-speed-error", "0.2"],
                       capture_output=True, text=True)
    assert t.returncode == 1 and "vx_error" in t.stderr, t.stdout + t.stderr
    # an operator step naming an input the robot lacks is refused at the start
    bad = tmp_path / "bad.toml"
    bad.write_text(open(path).read().replace('input = "operator/yaw_rate"',
                                             'input = "operator/jump"'))
    p = run("run", str(bad), "--out", str(tmp_path / "out2"), "--workers", "1", "--no-report",
            "--rozrun", ROZRUN)
    assert p.returncode != 0 and "operator/jump" in p.stderr, p.stderr
