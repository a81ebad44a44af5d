# SPDX-License-Identifier: Apache-2.0
"""Every rule has a fixture in manifests/invalid/, with its exact message.

``manifests/invalid/<rule-id>.toml`` (and variants ``<rule-id>--<what>.toml``)
breaks exactly that rule; ``<same name>.expected`` is the exact stderr of
``rozgen --check manifests/invalid/<file>`` run from the repository root. Any
other reader of robot.toml can run the same files and compare.
"""

import pytest

from conftest import BUILD_STACK_RANGE, INVALID, REPO, STACK_RANGE, run_rozgen
from rozgen.cli import main
from rozgen.problems import RULES, RULES_WITHOUT_FIXTURE

FIXTURES = sorted(INVALID.glob("*.toml"))


def _rule_of(fixture) -> str:
    return fixture.stem.split("--")[0]


def _expected(fixture) -> str:
    """The fixture's words on this machine: a thread stack's range is its
    C library's (test/ports/common/test_port_vectors.c does the same)."""
    text = fixture.with_suffix(".expected").read_text(encoding="utf-8")
    return text.replace(BUILD_STACK_RANGE, STACK_RANGE)


def test_every_rule_has_a_fixture():
    covered = {_rule_of(f) for f in FIXTURES}
    missing = set(RULES) - RULES_WITHOUT_FIXTURE - covered
    assert not missing, f"rules without a fixture in {INVALID}: {sorted(missing)}"


def test_every_fixture_names_a_rule_and_has_expected_output():
    for fixture in FIXTURES:
        assert _rule_of(fixture) in RULES, fixture.name
        assert fixture.with_suffix(".expected").is_file(), fixture.name
    for expected in INVALID.glob("*.expected"):
        assert expected.with_suffix(".toml").is_file(), expected.name


@pytest.mark.parametrize("fixture", FIXTURES, ids=lambda f: f.stem)
def test_check_reports_exactly(fixture):
    relative = fixture.relative_to(REPO).as_posix()
    result = run_rozgen("--check", relative)
    assert "Traceback" not in result.stderr
    assert result.stdout == ""
    assert result.stderr == _expected(fixture)
    assert result.returncode == 2


@pytest.mark.parametrize("fixture", FIXTURES, ids=lambda f: f.stem)
def test_error_ids_name_the_fixture_rule(fixture, capsys, monkeypatch):
    monkeypatch.chdir(REPO)
    relative = fixture.relative_to(REPO).as_posix()
    assert main(["--check", "--error-ids", relative]) == 2
    lines = capsys.readouterr().err.splitlines()
    prefix = f"[{_rule_of(fixture)}] "
    assert lines and all(line.startswith(prefix) for line in lines)
    assert [line[len(prefix):] for line in lines] == _expected(fixture).splitlines()
