# SPDX-License-Identifier: Apache-2.0
"""The campaigns the project runs on itself (tools/campaigns/): each loads
against the build (every controller it names is built), and the stop
tables of the PM01 and the X2 (SAFETY.md section 8) run from their files,
every row (a few seconds each: one sample a row)."""
import glob
import os

import pytest

import campaign
from conftest import BUILD, ROZRUN, SOURCE, need_mujoco, rows, run

FILES = sorted(glob.glob(os.path.join(SOURCE, "tools", "campaigns", "*.toml")))


@pytest.mark.parametrize("path", FILES, ids=os.path.basename)
def test_shipped_campaign_loads_against_the_build(path):
    need_mujoco()
    c = campaign.load(path, BUILD)
    assert c["families"] and c["controllers"]
    for ct in c["controllers"]:
        assert os.path.exists(ct["wasm"]), f"{path}: {ct['name']}: {ct['wasm']} not built"
    c["build"] = BUILD
    for fam in c["families"]:
        for pt in fam["perturb"]:
            if pt["kind"] == "swap":
                assert os.path.exists(campaign._swap_path(c, pt["fields"]["controller"]))


@pytest.mark.parametrize("name,n", [("stops_pm01", 8), ("stops_x2", 12)])
def test_stop_tables_run_from_the_shipped_files(tmp_path, name, n):
    """Every row: the stop's fault latched (none where the row has none),
    the robot still up 2 s later, nothing outside the manifest."""
    need_mujoco()
    path = os.path.join(SOURCE, "tools", "campaigns", f"{name}.toml")
    out = str(tmp_path / "out")
    p = run("run", path, "--build", BUILD, "--out", out, "--workers", "2", "--no-report",
            "--rozrun", ROZRUN)
    assert p.returncode == 0, p.stderr + p.stdout
    got = rows(out)
    assert len(got) == n
    fams = {f["name"]: f for f in campaign.load(path, BUILD)["families"]}
    for r in got:
        want = fams[r["family"]]["verdict"]["faults"]
        assert r["status"] == (1 if want else 0), r["stderr"]  # rozrun's 1: a fault latched
        assert r["passed"], (r["id"], r["reasons"])
        assert r["summary"]["faults"]["latched"] == want
    assert {r["family"] for r in got} == set(fams)


def test_family_option_runs_a_subset(tmp_path):
    need_mujoco()
    path = os.path.join(SOURCE, "tools", "campaigns", "stops_pm01.toml")
    out = str(tmp_path / "out")
    p = run("run", path, "--build", BUILD, "--out", out, "--family", "estop", "--family",
            "trap", "--no-report", "--rozrun", ROZRUN)
    assert p.returncode == 0, p.stderr + p.stdout
    assert sorted(r["id"] for r in rows(out)) == ["estop/0/pm01_stand", "trap/0/stops_pm01_trap"]
    p = run("run", path, "--out", str(tmp_path / "o2"), "--family", "jump")
    assert p.returncode == 2 and "--family jump: no such family" in p.stderr, p.stderr
