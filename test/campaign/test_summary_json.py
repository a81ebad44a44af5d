# SPDX-License-Identifier: Apache-2.0
"""rozrun --summary-json, and the mujoco port's perturbations: each one
changes the run, the same parameters give the same run bit for bit, and a
bad one is refused naming the key."""
import filecmp
import json
import math
import os
import subprocess

import pytest

from conftest import G1_STAND, ROZRUN, SOURCE, need_mujoco

TICKS = "300"


def rozrun(tmp_path, *params, ticks=TICKS, trace=None, extra=(), name="s.json", robot="unitree_g1",
           port="mujoco", controller=G1_STAND):
    out = tmp_path / name
    cmd = [ROZRUN, "--robot", robot, "--port", port, "--controller", controller, "--ticks",
           ticks, "--summary-json", str(out)] + list(extra)
    for p in params:
        cmd += ["--param", p]
    if trace:
        cmd += ["--trace", str(tmp_path / trace)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p, (json.loads(out.read_text()) if out.exists() else None)


def test_summary_json_fields(tmp_path):
    need_mujoco()
    p, s = rozrun(tmp_path, "push=80,0,0@pelvis@100:150")
    assert p.returncode == 0, p.stderr
    assert s["format"] == "rozrun-summary/1"
    assert (s["robot"], s["port"], s["rate_hz"], s["ticks"]) == ("unitree_g1", "mujoco", 500, 300)
    assert s["params"] == [["push", "80,0,0@pelvis@100:150"]]
    assert s["faults"] == {"latched": [], "bits": 0, "first": "", "times_latched": {}}
    assert s["exit_status"] == 0 and s["wire_violations"] == 0
    assert s["port_counters"]["violations"] == 0 and s["port_counters"]["frames"] == 300
    t = s["truth"]
    assert 0.7 < t["base_height_min"] <= t["base_height_start"]
    assert t["base_height_min"] <= t["base_height_final"]
    assert len(t["base_height_series"]["values"]) == 300
    assert t["base_height_series"]["values"][0] == pytest.approx(t["base_height_start"], abs=1e-5)
    # what the summary a person reads says, the same
    assert f"lowest {t['base_height_min']:.3f}" in p.stdout
    # no tmp file is left beside it
    assert os.listdir(tmp_path) == ["s.json"]


def _trace_peak(path):
    """The largest |"<joint>/velocity" state| of a --trace file, and its joint."""
    import csv
    with open(path) as f:
        rows = list(csv.DictReader(f))
    cols = [c for c in rows[0] if c.startswith("state:") and c.endswith("/velocity")]
    return max((abs(float(r[c])), c[len("state:"):-len("/velocity")]) for r in rows
               for c in cols)


def test_summary_json_peak_joint_speed(tmp_path):
    """The fastest any joint's velocity state read over the run, which joint
    and when, as the trace's states say: a standing G1 barely moves; shoved
    over, its joints go fast."""
    need_mujoco()
    p, s = rozrun(tmp_path, ticks="400", trace="still.csv")
    assert p.returncode == 0, p.stderr
    still = s["joint_speed_max"]
    assert set(still) == {"value", "joint", "time_s"} and 0.0 <= still["time_s"] < 0.8
    assert (still["value"], still["joint"]) == pytest.approx(_trace_peak(tmp_path / "still.csv"),
                                                             rel=1e-6)
    # the stand's first moves set its knees: about 1.6 rad/s in the first 0.3 s
    p, s = rozrun(tmp_path, "push=2000,0,0@pelvis@20:40", ticks="400", name="fell.json",
                  trace="fell.csv")
    fell = s["joint_speed_max"]
    assert (fell["value"], fell["joint"]) == pytest.approx(_trace_peak(tmp_path / "fell.csv"),
                                                           rel=1e-6)
    assert fell["value"] > 3.0 * still["value"], (still, fell)


def test_summary_json_fault_and_fall(tmp_path):
    need_mujoco()
    # a stream dropped for 100 ticks latches the stale fault; a 2 kN shove fells the robot,
    # which the manifest's fall rule latches once fresh states show it down
    p, s = rozrun(tmp_path, "drop=50:150", "push=2000,0,0@pelvis@20:40", ticks="600")
    assert p.returncode == 1
    assert s["exit_status"] == 1 and s["faults"]["latched"] == ["stale state", "fall"]
    assert s["faults"]["times_latched"] == {"stale state": 1, "fall": 1}
    assert "no fresh state" in s["faults"]["first"]
    assert s["truth"]["base_height_min"] < 0.4
    assert s["counters"]["stale_reads"] >= 100


def test_summary_json_without_truth(tmp_path):
    p, s = rozrun(tmp_path, robot="ur5", port="loopback", ticks="50",
                  controller=os.path.join(SOURCE, "examples", "controllers", "sine.wat"))
    if p.returncode == 2 and "wat2wasm" in p.stderr:
        pytest.skip("no wat2wasm")
    assert p.returncode == 0, p.stderr
    assert s["truth"] is None and s["port_counters"] is None and s["wire_violations"] == 0
    # the loopback's UR5 follows the sine's velocities: its velocity states
    speed = s["joint_speed_max"]
    assert speed["value"] > 0.0 and speed["joint"].endswith("_joint")


def test_summary_json_unwritable(tmp_path):
    need_mujoco()
    p, _ = rozrun(tmp_path, name="no/such/dir.json", ticks="5")
    assert p.returncode == 3 and "--summary-json" in p.stderr


PERTURBATIONS = [
    "payload=6@torso_link", "payload=6@torso_link@0.2,0,0.1", "mass_scale=1.3",
    "friction_scale=0.02", "strength_scale=0.05@left_knee_joint", "strength_scale=0.05",
    "gains_scale=0.6", "joint_damping=5", "joint_armature=0.3", "command_latency_ticks=8",
    "bias_position=0.02", "bias_gyro=0.05", "bias_accelerometer=0.5", "bias_orientation=0.05",
]


def test_perturbations_change_the_run_and_repeat_bit_for_bit(tmp_path):
    need_mujoco()
    # friction only shows when something slides: a sideways shove
    shove = "push=0,60,0@pelvis@50:80"
    _, nominal = rozrun(tmp_path, shove, trace="nominal.csv", name="n.json", ticks="200")
    for i, p in enumerate(PERTURBATIONS):
        a, sa = rozrun(tmp_path, shove, p, trace=f"a{i}.csv", name=f"a{i}.json", ticks="200")
        assert a.returncode == 0, (p, a.stderr)
        assert not filecmp.cmp(tmp_path / "nominal.csv", tmp_path / f"a{i}.csv",
                               shallow=False), f"{p} changed nothing"
    # the same parameters, the same run: those drawn from the seed and those
    # that change the model
    for i in (0, 6, 9, 13):
        b, sb = rozrun(tmp_path, shove, PERTURBATIONS[i], trace=f"b{i}.csv", name=f"b{i}.json",
                       ticks="200")
        assert filecmp.cmp(tmp_path / f"a{i}.csv", tmp_path / f"b{i}.csv", shallow=False)


def test_bias_is_drawn_from_the_seed(tmp_path):
    need_mujoco()
    _, a = rozrun(tmp_path, "bias_orientation=0.05", "noise_seed=1", name="a.json", trace="a.csv")
    _, b = rozrun(tmp_path, "bias_orientation=0.05", "noise_seed=2", name="b.json", trace="b.csv")
    assert a["truth"] != b["truth"]
    # without a bias asked for, nothing is drawn: the noise is as it was
    _, c = rozrun(tmp_path, "noise_gyro=0.01", "bias_gyro=0", name="c.json", trace="c.csv")
    _, d = rozrun(tmp_path, "noise_gyro=0.01", name="d.json", trace="d.csv")
    assert filecmp.cmp(tmp_path / "c.csv", tmp_path / "d.csv", shallow=False)


def test_payload_and_gains_fell_the_stand(tmp_path):
    need_mujoco()
    _, s = rozrun(tmp_path, "payload=20@torso_link", ticks="1000")
    assert s["truth"]["base_height_min"] < 0.4
    _, s = rozrun(tmp_path, "strength_scale=0.01", ticks="1000")
    assert s["truth"]["base_height_min"] < 0.4 and s["port_counters"]["saturated"] > 0


@pytest.mark.parametrize("param,words", [
    ("payload=2@nobody", 'no body "nobody"'),
    ("payload=x@torso_link", "expected KG@BODY"),
    ("payload=2000@torso_link", "expected KG@BODY"),
    ("strength_scale=1.5", "expected S[@JOINT]"),
    ("strength_scale=0.5@no_joint", 'no bound joint "no_joint"'),
    ("mass_scale=0", "parameter mass_scale = \"0\": expected a number in 0.1..10"),
    ("command_latency_ticks=16", "expected an integer in 0..15"),
    ("bias_orientation=1", "expected a number in 0..0.5"),
])
def test_bad_perturbations_refused(tmp_path, param, words):
    need_mujoco()
    p, s = rozrun(tmp_path, param, ticks="5")
    assert p.returncode == 2 and s is None
    assert words in p.stderr, p.stderr
