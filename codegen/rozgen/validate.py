# SPDX-License-Identifier: Apache-2.0
"""Rules of robot.toml: file bytes -> model.

``validate(data, maxima)`` returns the ``rozgen.model.Manifest`` of a
robot.toml's bytes or every problem found. The rules themselves, from the
TOML reader's refusals to the ports' [hardware] keys, are roz's C loader's
and the ports' registered checks (``rozgen.checker``: their one
implementation, the mujoco port's rules on its model among them). It never
stops at the first problem, and it never guesses: unknown keys are refused,
because a typo such as ``max_rate = 0.5`` must not silently drop a safety
limit.

Message format (after the file name)::

    : <where>: <key> <value>: <what is wrong>

``<where>`` is ``manifest``, ``manifest.commands[<i>] "<name>"``,
``manifest.states[<i>] "<name>"``, ``hardware`` or ``hardware.params``, and
is left out (with its ``": "``) for top-level keys (examples: every
``manifests/invalid/*.expected``).

Order: by place in the file's schema -- top level, then ``[manifest]``,
then each command in order, then each state, then ``[hardware]``, then a
port's keys. The rule ids and what each refuses: ``rozgen --list-rules``
(``rozgen.problems``); every message, verbatim: ``manifests/invalid/*.expected``.

Command-line misuse is reported by argparse (``usage: rozgen ...``, exit 2)
and has no rule id.
"""

from rozgen import checker as _checker
from rozgen.model import Manifest, Maxima
from rozgen.problems import Problem


def validate(data: bytes | str, maxima: Maxima = Maxima(), checker: str | None = None,
             origin: str | None = None) -> tuple[Manifest | None, list[Problem]]:
    """Check a robot.toml's bytes (or text); the model, or None and the problems.

    ``checker`` is roz_manifest_json's path (default: ``rozgen.checker.find()``);
    raises ``rozgen.checker.CheckerError`` when it cannot run. ``origin``
    is the file's path as given (the files its keys name are read relative
    to its folder; None: the working directory).
    """
    if isinstance(data, str):
        data = data.encode("utf-8")
    return _checker.check(data, maxima, checker or _checker.find(), origin)
