# SPDX-License-Identifier: Apache-2.0
"""A thread's keys as rozgen reports them: roz_thread_params()
(hal/src/thread.c), their one implementation, run through the checker on a
robot of a port that reads them (unitree/G1: its command writer, and
Cyclone's threads, which have no round-robin class); the shared vectors
(manifests/invalid/*thread*) hold the same words."""
import pytest

from conftest import STACK_LEAST_KIB as LEAST
from conftest import STACK_RANGE as RANGE
from conftest import knee_toml
from rozgen.validate import validate

def _full(text: str, prefix: str) -> str:
    """The table's "w_" keys as the thread @p prefix's."""
    return text.replace("w_", prefix + "_")


def _said(params: dict, prefix: str = "command_writer") -> list[str]:
    lines = "".join(f'{_full(k, prefix)} = "{v}"\n' for k, v in params.items())
    _, problems = validate(knee_toml() + "[hardware.params]\n" + lines)
    return [p.message for p in problems]


OK = [
    {},
    {"w_sched": "other"},
    {"w_sched": " fifo ", "w_priority": "80"},
    {"w_sched": "rr", "w_priority": "1"},
    {"w_sched": "fifo", "w_priority": "99", "w_cpus": "0,2-3, 63", "w_stack_kib": str(LEAST)},
    {"w_cpus": "5-5"},
    {"w_stack_kib": "65536"},
]

BAD = [
    ({"w_sched": "realtime"}, 'parameter w_sched = "realtime": expected other, fifo or rr'),
    ({"w_sched": "FIFO", "w_priority": "3"}, 'parameter w_sched = "FIFO": expected other, fifo or rr'),
    ({"w_sched": "fifo", "w_priority": "0"}, 'parameter w_priority = "0": expected an integer in 1..99'),
    ({"w_sched": "fifo", "w_priority": " 5"}, 'parameter w_priority = " 5": expected an integer in 1..99'),
    ({"w_sched": "fifo", "w_priority": "100"}, 'parameter w_priority = "100": expected an integer in 1..99'),
    ({"w_priority": "5"}, "parameter w_priority: only with w_sched = fifo or rr"),
    ({"w_sched": "other", "w_priority": "5"}, "parameter w_priority: only with w_sched = fifo or rr"),
    ({"w_sched": "rr"}, "parameter w_sched = rr: needs w_priority (1..99)"),
    ({"w_cpus": ""}, 'parameter w_cpus = "": expected CPUs 0..63 as a list such as 0,2-3'),
    ({"w_cpus": "3-1"}, 'parameter w_cpus = "3-1": expected CPUs 0..63 as a list such as 0,2-3'),
    ({"w_cpus": "64"}, 'parameter w_cpus = "64": expected CPUs 0..63 as a list such as 0,2-3'),
    ({"w_cpus": "0,"}, 'parameter w_cpus = "0,": expected CPUs 0..63 as a list such as 0,2-3'),
    ({"w_stack_kib": str(LEAST - 1)},
     f'parameter w_stack_kib = "{LEAST - 1}": expected an integer in {RANGE}'),
    ({"w_stack_kib": "1e3"}, f'parameter w_stack_kib = "1e3": expected an integer in {RANGE}'),
]


@pytest.mark.parametrize("params", OK)
def test_threads_accepts(params):
    assert _said(params) == []


@pytest.mark.parametrize("params,said", BAD)
def test_threads_refuses_in_the_c_words(params, said):
    assert _said(params) == [": " + _full(said, "command_writer")]


def test_threads_cyclone_has_no_round_robin():
    said = _said({"w_sched": "rr", "w_priority": "4"}, "dds_threads")
    assert said == [': parameter dds_threads_sched = "rr": expected other or fifo (Cyclone DDS '
                    "has no round-robin class)"]
    assert _said({"w_sched": "fifo", "w_priority": "4"}, "dds_threads") == []
    # the priority's problem first, as the port finds it
    assert _said({"w_sched": "rr"}, "dds_threads") == \
        [": parameter dds_threads_sched = rr: needs dds_threads_priority (1..99)"]
