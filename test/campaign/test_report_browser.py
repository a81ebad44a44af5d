# SPDX-License-Identifier: Apache-2.0
"""The campaign report in a real browser: Debian's Chromium, headless, with no
network and a fresh profile, screenshots index.html; the picture must show
the page (its size, and more than one colour), and the page's own files are
read back. The results are made here (no rozrun needed): two builds, two
families, one failing sample each."""
import json
import os
import shutil
import subprocess

import matplotlib.image
import pytest

import campaign
import campaign_report


def _row(fam, i, ct, force, z, passed):
    series = [0.79 - (0.79 - z) * min(1.0, max(0.0, (k - 50) / 50)) for k in range(200)]
    return {"id": f"{fam}/{i}/{ct}", "family": fam, "index": i, "controller": ct, "seed": 7 + i,
            "values": {"push.force": force, "push.at": 1.0, "push.duration": 0.1},
            "command": ["rozrun", "--robot", "unitree_g1", "--param", f"push={force},0,0@pelvis"],
            "status": 0, "attempts": 1, "node": "n", "wall_s": 1.0, "stderr": "",
            "passed": passed, "reasons": [] if passed else [f"fell: base down to {z} m"],
            "summary": {"ticks": 1000, "faults": {"latched": []}, "counters": {}, "fuel": {},
                        "wire_violations": 0,
                        "truth": {"base_height_min": z, "base_height_min_time_s": 1.5,
                                  "base_height_final": z, "tilt_max_deg": 3.0,
                                  "base_height_series": {"every_s": 0.01, "values": series}}}}


def make_report(out):
    os.makedirs(out)
    fams = [{"name": f, "samples": 2, "controllers": ["a", "b"], "perturb": [],
             "verdict": {"min_base_height": 0.6},
             "boundary": {"value": "push.force", "worse": "higher"}} for f in ("fwd", "side")]
    meta = {"format": campaign.FORMAT, "fingerprint": "x", "rozrun": "rozrun",
            "campaign": {"name": "browser", "file": "b.toml", "robot": "unitree_g1",
                         "port": "mujoco", "duration_s": 2.0, "seed": 1, "rate_hz": 500,
                         "controllers": [{"name": "a", "wasm": "a.wasm"},
                                         {"name": "b", "wasm": "b.wasm"}],
                         "families": fams}}
    with open(os.path.join(out, "campaign.json"), "w") as f:
        json.dump(meta, f)
    r = campaign.Results(os.path.join(out, "results.jsonl"))
    for fam in ("fwd", "side"):
        r.add(_row(fam, 0, "a", 60.0, 0.77, True))
        r.add(_row(fam, 0, "b", 60.0, 0.76, True))
        r.add(_row(fam, 1, "a", 200.0, 0.08, False))
        r.add(_row(fam, 1, "b", 200.0, 0.70, True))
    r.close()
    return campaign_report.write(out)


def test_report_read_back(tmp_path):
    page = make_report(str(tmp_path / "out"))
    text = open(page).read()
    assert "1/2 (50 %)" in text and "2/2 (100 %)" in text and "2/4 (50 %)" in text and "4/4 (100 %)" in text
    assert "fwd/1: a fail, b pass" in text  # the builds compared, sample by sample
    assert text.count('class="case"') == 6 and "plots/worst-1.png" in text
    assert "Values: push.at = 1, push.duration = 0.1, push.force = 200" in text
    # the boundary: the largest push survived, the least that failed
    assert "<td>60</td><td>200</td>" in text


def test_report_in_headless_chromium(tmp_path):
    browser = shutil.which("chromium")
    if browser is None:
        pytest.skip("no chromium (tools/setup.sh installs Debian's)")
    page = make_report(str(tmp_path / "out"))
    shot = str(tmp_path / "shot.png")
    p = subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run",
         f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1200,1600",
         f"--screenshot={shot}", "file://" + os.path.abspath(page)],
        capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and os.path.exists(shot), p.stderr[-2000:]
    img = matplotlib.image.imread(shot)
    assert img.shape[:2] == (1600, 1200)
    # the page was drawn: its tables' colours and the plots, not a blank page
    colours = {tuple(round(float(c), 2) for c in px[:3]) for px in img[::20, ::20].reshape(-1, 4)}
    assert len(colours) > 20
