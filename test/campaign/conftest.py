# SPDX-License-Identifier: Apache-2.0
"""What the campaign tests share: rozrun, the controllers, the tool, and a
tiny G1 campaign file written into a test's folder. ROZRUN and BUILD come
from ctest (test/CMakeLists.txt); ROZ_SOURCE is the source tree."""
import json
import os
import subprocess
import sys

import pytest

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = os.path.join(SOURCE, "tools")
sys.path.insert(0, TOOLS)
BUILD = os.environ.get("BUILD", os.path.join(SOURCE, "build"))
ROZRUN = os.environ.get("ROZRUN", os.path.join(BUILD, "tools", "rozrun", "rozrun"))
G1_STAND = os.path.join(BUILD, "examples", "controllers", "g1_stand.wasm")
G1_STAND_PD = os.path.join(BUILD, "examples", "controllers", "g1_stand_pd.wasm")
CAMPAIGN = [sys.executable, os.path.join(TOOLS, "campaign.py")]

#: a campaign of a few short samples: two builds, a push family whose
#: strongest push fells the stand (and a PD that falls anyway)
TINY = """
[campaign]
name = "tiny"
robot = "unitree_g1"
duration_s = {duration}
seed = 7
samples = {samples}

[[controllers]]
name = "stand"
wasm = "{stand}"

[[controllers]]
name = "pd"
wasm = "{pd}"

[verdict]
min_base_height = 0.6

[[families]]
name = "push"
boundary = {{ value = "push.force", worse = "higher" }}
[[families.perturb]]
kind = "push"
force = {{ linspace = [50, 1500] }}
at = 0.1
duration = 0.1

[[families]]
name = "payload"
[[families.perturb]]
kind = "payload"
mass = {{ uniform = [0, 3] }}
body = "torso_link"
[[families.perturb]]
kind = "sensors"
noise_gyro = 0.01
bias_orientation = {{ uniform = [0, 0.02] }}
"""


def need_mujoco():
    if not os.path.exists(ROZRUN) or not os.path.exists(G1_STAND):
        pytest.skip("rozrun or the G1 controllers are not built")
    p = subprocess.run([ROZRUN, "--port", "mujoco", "--help"], capture_output=True, text=True)
    if "Port mujoco" not in p.stdout:
        pytest.skip("this build has no mujoco port")


@pytest.fixture
def tiny(tmp_path):
    """Writes the tiny campaign; returns its path. tiny(duration, samples)."""
    need_mujoco()

    def make(duration=0.6, samples=2, name="tiny.toml"):
        path = tmp_path / name
        path.write_text(TINY.format(duration=duration, samples=samples, stand=G1_STAND,
                                    pd=G1_STAND_PD))
        return str(path)
    return make


def run(*args, **kw):
    return subprocess.run(CAMPAIGN + list(args), capture_output=True, text=True, **kw)


def rows(out):
    with open(os.path.join(out, "results.jsonl")) as f:
        return [json.loads(line) for line in f if line.strip()]
