# SPDX-License-Identifier: Apache-2.0
"""The ``rozgen`` command.

    rozgen [-o DIR] [--check | --json | --identity] [--registry] [--source-root DIR]
           [--max-commands N] [--max-states N] [--max-name-len N] [--checker PATH]
           [--strict] [--error-ids] [--list-rules] [--version] FILE...

Every FILE is loaded and validated first; nothing is written unless all of
them are valid. Problems go to stderr, one per line, as ``<file>: ...``
(see ``rozgen.validate``); so do warnings about valid files
(``<file>: warning: ...``, ``rozgen.lint``), which ``--strict`` makes
errors. Exit status: 0 when all is well (warnings or not), 2 on any
problem, warning under --strict, usage error or I/O error, or when roz's
C implementation of the rules (``rozgen.checker``) cannot be found or run.
"""

import argparse
import os
import sys

from rozgen import __version__, identity
from rozgen import checker as _checker
from rozgen.lint import lint
from rozgen.load import load, source_label
from rozgen.model import Manifest, Maxima
from rozgen.output import write_if_changed
from rozgen import mujoco
from rozgen import problems as _problems
from rozgen.problems import Problem, rules
from rozgen.render import REGISTRY_FILE, Source, render_registry, render_robot
from rozgen.validate import validate

EXIT_OK = 0
EXIT_ERROR = 2


def _positive_int(text: str) -> int:
    try:
        value = int(text, 10)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1: {text!r}")
    return value


def _parser() -> argparse.ArgumentParser:
    defaults = Maxima()
    p = argparse.ArgumentParser(
        prog="rozgen",
        description="Validate robot.toml manifests and generate roz's static C tables.",
    )
    p.add_argument("files", nargs="*", metavar="FILE", help="robot.toml files")
    p.add_argument("-o", "--output-dir", default=".", metavar="DIR",
                   help="where to write <id>_manifest.h/.c, <id>_channels.h and the "
                        "Rust module <id>_channels.rs (created if missing; default: .)")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true",
                      help="validate only; write nothing")
    mode.add_argument("--json", action="store_true",
                      help="print the canonical JSON of one FILE; write nothing")
    mode.add_argument("--identity", action="store_true",
                      help="print each FILE's robot_id and interface hash (the identity a "
                           "controller built for it carries); write nothing")
    p.add_argument("--registry", action="store_true",
                   help=f"also write {REGISTRY_FILE} (roz/builtin.h) over all FILEs")
    p.add_argument("--source-root", metavar="DIR",
                   help="name sources in banners relative to DIR (default: the "
                        "current directory, else the base name)")
    p.add_argument("--max-commands", type=_positive_int, default=defaults.commands,
                   metavar="N", help="ROZ_CFG_MAX_COMMANDS of the target build "
                                     f"(default {defaults.commands})")
    p.add_argument("--max-states", type=_positive_int, default=defaults.states,
                   metavar="N", help=f"ROZ_CFG_MAX_STATES (default {defaults.states})")
    p.add_argument("--max-name-len", type=_positive_int, default=defaults.name_len,
                   metavar="N", help=f"ROZ_CFG_MAX_NAME_LEN (default {defaults.name_len})")
    p.add_argument("--strict", action="store_true",
                   help="treat warnings (a command paired with another joint's position "
                        "state, ...) as errors: exit 2, write nothing")
    p.add_argument("--checker", metavar="PATH",
                   help="roz_manifest_json, roz's C implementation of the rules (default: "
                        f"${_checker.ENV}, else beside rozgen, else built from the roz source "
                        "tree rozgen is in, else on PATH)")
    p.add_argument("--error-ids", action="store_true",
                   help="prefix every problem with its rule id: [limits-order] ...")
    p.add_argument("--list-rules", action="store_true",
                   help="print the rule ids and what they refuse, then exit")
    p.add_argument("--version", action="version", version=f"rozgen {__version__}")
    return p


class _Reporter:
    def __init__(self, with_ids: bool, strict: bool = False) -> None:
        self.with_ids = with_ids
        self.strict = strict
        self.count = 0

    def __call__(self, file: str, problems: list[Problem]) -> None:
        for problem in problems:
            print(problem.render(file, self.with_ids), file=sys.stderr)
        self.count += len(problems)

    def warn(self, file: str, warnings: list) -> None:
        """Warnings (rozgen.lint): errors only under --strict."""
        for warning in warnings:
            print(warning.render(file, self.with_ids, self.strict), file=sys.stderr)
        if self.strict:
            self.count += len(warnings)


def main(argv: list[str] | None = None) -> int:
    """Run rozgen; returns the exit status."""
    parser = _parser()
    args = parser.parse_args(argv)
    if args.list_rules:  # the ports' come from their rules (roz_manifest_json --list-rules)
        try:
            _problems.used_checker = _checker.find(args.checker)
            every = rules()
        except _checker.CheckerError as e:
            print(f"rozgen: {e}", file=sys.stderr)
            return EXIT_ERROR
        for rule, what in every.items():
            print(f"{rule:20} {what}")
        return EXIT_OK
    if not args.files:
        parser.error("the following arguments are required: FILE")
    if args.json and len(args.files) != 1:
        parser.error("--json takes exactly one FILE")
    if (args.json or args.identity) and args.registry:
        parser.error(f"--{'json' if args.json else 'identity'} and --registry do not go together")

    report = _Reporter(args.error_ids, args.strict)
    try:
        checker = _checker.find(args.checker)
        robots = _load_all(args.files, Maxima(args.max_commands, args.max_states,
                                              args.max_name_len), report, checker, args.check)
        if report.count:
            return EXIT_ERROR
        if args.json:
            sys.stdout.write(_checker.canonical_json(robots[0][3], checker))
            return EXIT_OK
    except _checker.CheckerError as e:
        print(f"rozgen: {e}", file=sys.stderr)
        return EXIT_ERROR
    if args.identity:
        for _, manifest, _, _ in robots:
            print(f"{manifest.robot_id} {identity.interface_hash(manifest):016x}")
        return EXIT_OK
    if args.check:
        for path, manifest, _, _ in robots:
            print(f"{path}: ok: {manifest.robot_id}, {len(manifest.commands)} commands, "
                  f"{len(manifest.states)} states")
        return EXIT_OK

    outputs = _render_all(robots, args.source_root, args.registry, report)
    if report.count:
        return EXIT_ERROR
    return _write_all(args.output_dir, outputs, report)


def _load_all(files: list[str], maxima: Maxima, report: _Reporter,
              checker: str, check: bool = False) -> list[tuple]:
    """Load and validate every file: [(path, manifest, sha256, bytes)] of valid ones."""
    robots = []
    for path in files:
        loaded = load(path)
        manifest, problems = None, loaded.problems
        if loaded.data is not None:
            manifest, problems = validate(loaded.data, maxima, checker, str(path))
        if manifest is not None and check:  # the port's own open (rozrun --check)
            problems = [Problem(rule, message)
                        for rule, message in mujoco.check_open(manifest, path)]
            if problems:
                manifest = None
        report(path, problems)
        if not problems:
            report.warn(path, lint(manifest))
            robots.append((path, manifest, loaded.sha256, loaded.data))
    first_with_id: dict[str, int] = {}
    for i, (path, manifest, _, _) in enumerate(robots):
        first = first_with_id.setdefault(manifest.robot_id, i)
        if first != i:
            report(path, [Problem(
                "duplicate-robot-id",
                f': manifest: robot_id "{manifest.robot_id}": also the robot_id of {robots[first][0]}')])
    return robots


def _render_all(robots: list[tuple], source_root: str | None, registry: bool,
                report: _Reporter) -> dict[str, str]:
    """File name -> content of everything to write."""
    outputs: dict[str, str] = {}
    sourced: list[tuple[Manifest, Source]] = []
    for path, manifest, sha256, _ in robots:
        label = source_label(path, source_root)
        if label is None:
            report(path, [Problem("source-root", f": not under --source-root {source_root}")])
            continue
        source = Source(label, sha256)
        sourced.append((manifest, source))
        outputs.update(render_robot(manifest, source))
    if registry and not report.count:
        outputs[REGISTRY_FILE] = render_registry(sourced)
    return outputs


def _write_all(out_dir: str, outputs: dict[str, str], report: _Reporter) -> int:
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as e:
        report(out_dir, [Problem("io-error", f": cannot write: {e.strerror or e}")])
        return EXIT_ERROR
    for name in sorted(outputs):
        path = os.path.join(out_dir, name)
        try:
            write_if_changed(path, outputs[name])
        except OSError as e:
            report(path, [Problem("io-error", f": cannot write: {e.strerror or e}")])
            return EXIT_ERROR
    return EXIT_OK
