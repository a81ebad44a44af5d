# SPDX-License-Identifier: Apache-2.0
"""codegen/requirements.txt (what an installed rozgen runs on) pins exactly
what tools/requirements.txt pins for the same packages, and covers rozgen's
dependencies and theirs."""

import re
import tomllib

from conftest import CODEGEN, REPO


def pins(path):
    """{name: (version, hashes, vias)} of a pip-compile style requirements file."""
    out = {}
    name = None
    for line in path.read_text().splitlines():
        if m := re.match(r"^([A-Za-z0-9_.-]+)==(\S+)", line):
            name = m.group(1).lower()
            out[name] = (m.group(2), set(), set())
        elif name and (m := re.match(r"^\s+--hash=(\S+)", line)):
            out[name][1].add(m.group(1))
        elif name and (m := re.match(r"^\s+#\s+(?:via\s+)?([A-Za-z0-9_.-]+)\s*$", line)):
            out[name][2].add(m.group(1).lower())
    return out


def test_requirements_match_the_tools_pins():
    rozgen = pins(CODEGEN / "requirements.txt")
    tools = pins(REPO / "tools" / "requirements.txt")
    assert rozgen, "codegen/requirements.txt pins nothing"
    for name, (version, hashes, _) in rozgen.items():
        assert name in tools, f"{name} is not in tools/requirements.txt"
        assert (version, hashes) == tools[name][:2], f"{name}: pins differ"
        assert hashes, f"{name} has no hashes"


def test_requirements_cover_rozgen_and_what_it_pulls_in():
    rozgen = pins(CODEGEN / "requirements.txt")
    tools = pins(REPO / "tools" / "requirements.txt")
    project = tomllib.loads((CODEGEN / "pyproject.toml").read_text())["project"]
    for dep in project["dependencies"]:
        name = re.match(r"[A-Za-z0-9_.-]+", dep).group(0).lower()
        assert name in rozgen, f"rozgen depends on {name}; codegen/requirements.txt lacks it"
    for name, (_, _, vias) in tools.items():
        assert not (vias & rozgen.keys()) or name in rozgen, \
            f"{name} is pulled in by {sorted(vias & rozgen.keys())}; codegen/requirements.txt lacks it"


def test_tools_run_requirements_match_and_cover_the_tools():
    """tools/requirements-run.txt (what the installed roz-plot,
    roz-recording and roz-live run on) pins what tools/requirements.txt
    pins, and holds everything matplotlib, mcap, mcap-ros2-support and
    foxglove-sdk pull in."""
    run = pins(REPO / "tools" / "requirements-run.txt")
    tools = pins(REPO / "tools" / "requirements.txt")
    for name, (version, hashes, _) in run.items():
        assert name in tools, f"{name} is not in tools/requirements.txt"
        assert (version, hashes) == tools[name][:2], f"{name}: pins differ"
        assert hashes, f"{name} has no hashes"
    for root in ("matplotlib", "mcap", "mcap-ros2-support", "foxglove-sdk"):
        assert root in run, f"the tools import {root}; tools/requirements-run.txt lacks it"
    for name, (_, _, vias) in tools.items():
        assert not (vias & run.keys()) or name in run, \
            f"{name} is pulled in by {sorted(vias & run.keys())}; tools/requirements-run.txt lacks it"


def test_nn_requirements_match_and_cover_rozgen_nn():
    """codegen/requirements-nn.txt (what the installed rozgen-nn runs on)
    pins what tools/requirements.txt pins, and holds rozgen's `nn` extra
    and everything onnx pulls in."""
    nn = pins(CODEGEN / "requirements-nn.txt")
    tools = pins(REPO / "tools" / "requirements.txt")
    for name, (version, hashes, _) in nn.items():
        assert name in tools, f"{name} is not in tools/requirements.txt"
        assert (version, hashes) == tools[name][:2], f"{name}: pins differ"
        assert hashes, f"{name} has no hashes"
    extra = tomllib.loads((CODEGEN / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]["nn"]
    for dep in extra:
        assert re.match(r"[A-Za-z0-9_.-]+", dep).group(0).lower() in nn, dep
    for name, (_, _, vias) in tools.items():
        assert not (vias & {"onnx", "ml-dtypes"}) or name in nn, \
            f"{name} is pulled in by {sorted(vias & nn.keys())}; requirements-nn.txt lacks it"
