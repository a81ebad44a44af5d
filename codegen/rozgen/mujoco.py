# SPDX-License-Identifier: Apache-2.0
"""The mujoco port's own open, asked by ``rozgen --check``. Every rule of a
mujoco robot.toml is the port's, in C, run by rozgen's checker
(``rozgen.checker``): the [hardware] keys (``ports/mujoco/src/mj_params.c``)
and the rules on the model the file names, read without MuJoCo
(``ports/mujoco/src/mj_rules.c``: every joint bound to a joint of the model
and an actuator, the IMU's sensors, the effort limits its actuators can
give). What only MuJoCo's compiler can say is the open's.

``check_open(manifest, toml_path)`` (``rozgen --check`` only) asks the port
itself: ``rozrun --robot FILE --port mujoco --check`` opens it as a run
would (MuJoCo compiles the model; a built-in robot's model is the port's
build's) and reports what it refuses, in its words: an effort channel wider
than its motor's ``ctrlrange`` times gear and gain, a built-in robot's
effort past what its model gives. rozrun is ``$ROZ_ROZRUN``, else the one
beside the command that runs rozgen (an installed roz's ``bin/``), else on
PATH; without one the port checks at open, as before.
"""

import os
import shutil
import subprocess
import sys
from pathlib import Path

from rozgen.model import Manifest

PORT = "mujoco"

ROZRUN_ENV = "ROZ_ROZRUN"


def _rozrun() -> str | None:
    """rozrun, whose --check opens a port (see the module's text), or None."""
    given = os.environ.get(ROZRUN_ENV)
    if given:
        return given
    beside = Path(os.path.realpath(sys.argv[0])).parent / "rozrun"
    if beside.is_file() and os.access(beside, os.X_OK):
        return str(beside)
    return shutil.which("rozrun")


def check_open(m: Manifest, toml_path: str) -> list[tuple[str, str]]:
    """What the mujoco port's own open refuses of the robot.toml at
    ``toml_path`` (rozrun --check), as (rule, message); [] when it opens, or
    when no rozrun is found."""
    hw = m.hardware
    if hw is None or hw.port != PORT:
        return []
    exe = _rozrun()
    if exe is None:
        return []
    path = os.path.abspath(toml_path)
    try:
        done = subprocess.run([exe, "--robot", path, "--port", PORT, "--check"],
                              capture_output=True, text=True, errors="backslashreplace")
    except OSError as e:
        return [("mujoco-model", f": the port's own check (rozrun --check) cannot run: {exe}: "
                 f"{e.strerror or e}")]
    if done.returncode == 0:
        return []
    said = [line for line in done.stderr.splitlines() if line.startswith(f"rozrun: port {PORT}: ")]
    text = said[-1][len(f"rozrun: port {PORT}: "):] if said else \
        f"rozrun --check exit {done.returncode}: {done.stderr.strip()[-400:]}"
    for head in (f"{PORT}: {path}", PORT):  # the port's words name the file: it is the problem's
        if text.startswith(head + ": "):
            text = text[len(head):]
            break
    else:
        text = ": " + text
    rule = "mujoco-effort" if "ctrlrange" in text or "effort" in text else "mujoco-model"
    return [(rule, text)]
