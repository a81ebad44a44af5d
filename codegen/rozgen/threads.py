# SPDX-License-Identifier: Apache-2.0
"""A thread's scheduling keys, as roz_thread_params() (hal/src/thread.c)
reads them: <prefix>_sched, _priority, _cpus, _stack_kib. The same words as
the C side, which checks them again when the port opens (test_port_vectors,
toml_vectors)."""
from __future__ import annotations

MAX_CPUS = 64  # ROZ_THREAD_MAX_CPUS
_BLANK = " \t"  # is_blank() of hal/src/params.c
SCHEDS = ("other", "fifo", "rr")


def _u32(text: str, lo: int, hi: int) -> int | None:
    """roz_params_parse_u32 with no flags: decimal digits, within lo..hi."""
    if not text or not text.isascii() or not text.isdigit():
        return None
    value = int(text)
    return value if lo <= value <= hi else None


def _cpus(text: str) -> bool:
    """parse_cpus(): a comma list of CPUs and ranges lo-hi, none empty."""
    mask = 0
    for entry in text.split(","):
        entry = entry.strip(_BLANK)
        lo_text, dash, hi_text = entry.partition("-")
        lo = _u32(lo_text, 0, MAX_CPUS - 1)
        if lo is None:
            return False
        hi = lo
        if dash:
            hi = _u32(hi_text, lo, MAX_CPUS - 1)
            if hi is None:
                return False
        for c in range(lo, hi + 1):
            mask |= 1 << c
    return mask != 0


def problem(params: dict[str, str], prefix: str) -> str | None:
    """The first problem roz_thread_params() finds with @p prefix's keys in
    @p params, in its words; None when there is none."""
    key = f"{prefix}_sched"
    sched = "other"
    if key in params:
        sched = params[key].strip(_BLANK)
        if sched not in SCHEDS:
            return f'parameter {key} = "{params[key]}": expected other, fifo or rr'
    key = f"{prefix}_priority"
    priority = 0
    if key in params:
        priority = _u32(params[key], 1, 99)
        if priority is None:
            return f'parameter {key} = "{params[key]}": expected an integer in 1..99'
    if sched == "other" and key in params:
        return f"parameter {key}: only with {prefix}_sched = fifo or rr"
    if sched != "other" and priority == 0:
        return f"parameter {prefix}_sched = {sched}: needs {key} (1..99)"
    key = f"{prefix}_cpus"
    if key in params and not _cpus(params[key]):
        return (f'parameter {key} = "{params[key]}": expected CPUs 0..{MAX_CPUS - 1} as a list '
                "such as 0,2-3")
    key = f"{prefix}_stack_kib"
    if key in params and _u32(params[key], 64, 65536) is None:
        return f'parameter {key} = "{params[key]}": expected an integer in 64..65536'
    return None


def cyclone_problem(params: dict[str, str]) -> str | None:
    """roz_dds_params_parse()'s: dds_threads_*, which Cyclone runs in no
    round-robin class."""
    found = problem(params, "dds_threads")
    if found is None and params.get("dds_threads_sched", "").strip(_BLANK) == "rr":
        found = ('parameter dds_threads_sched = "rr": expected other or fifo (Cyclone DDS has '
                 "no round-robin class)")
    return found
