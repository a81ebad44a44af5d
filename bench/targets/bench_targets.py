# SPDX-License-Identifier: Apache-2.0
"""bench/targets/bench_targets.py: the tick's cost on every target, in
instructions.

    bench_targets.py --build BUILD --aarch64 TREE --json OUT [--skip N] [--ticks N]

One program on every target: the firmware images' application
(examples/firmware/app/fw_app.c: roz_runtime_tick() on the loopback
simulator, the same controllers' same bytes), built for x86-64 Linux
(BUILD/examples/firmware/host/roz_fw_host), for aarch64 Linux (TREE: the
cross tree test/aarch64 builds) and for the Cortex-M boards (the images of
make firmware, BUILD-fw-<tree>/). Each runs under QEMU (qemu-x86_64 -cpu max
and qemu-aarch64 in user mode, qemu-system-arm with -icount shift=0) and
qemu_count.py counts the instructions each part of a tick executed: the
controller (roz_controller_process_from: wasm3 and the imports), the safety
filter (roz_filter_apply), the port (the loopback's read and write), the
board's clock reads (fw_clock_ns: the Cortex-M images that run with a
clock), and the runtime's own work (the rest of roz_runtime_tick). A
combination with no build (no cross compiler, no firmware tree) is written
as skipped, with the reason. JSON lines, one per target and controller.
"""

import argparse
import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import qemu_count  # noqa: E402

# the parts: function -> part (qemu_count --track)
TRACK = {
    "roz_controller_process_from": "process",
    "roz_filter_apply": "filter",
    "lb_read": "port",
    "lb_write": "port",
    "fw_clock_ns": "clock",
}
TICK = "roz_runtime_tick"
HOST_FN = "fw_app_run"  # the tick's caller (examples/firmware/app/fw_app.c)
PARTS = ["process", "filter", "port", "clock"]

# (name, robot, controller file, the firmware tree and image that run it)
CONTROLLERS = [
    ("ur5_sine", "ur5", "sine_wat.wasm",
     {"m4f": "ur5_sine", "m7": "ur5_sine@m7u", "m33": "ur5_sine"}),
    ("g1_pd", "unitree_g1", "g1_pd.wasm",
     {"m4f": "g1_pd@m4fg", "m7": "g1_pd", "m33": "g1_pd@m33g"}),
    ("g1_policy", "unitree_g1", "g1_policy.wasm",
     {"m4f": "g1_policy@m4fp", "m7": "g1_policy@m7p", "m33": "g1_policy@m33p"}),
]
# target -> QEMU's machine (Cortex-M), or the Linux program's QEMU
BOARDS = {"m4f": "mps2-an386", "m7": "mps2-an500", "m33": "mps2-an505"}
TARGETS = ["x86-64", "aarch64", "m4f", "m7", "m33"]


def command(target, robot, wasm, image, a):
    """QEMU's command for one run, or a reason it cannot run."""
    ticks = str(a.skip + a.ticks)
    if target == "x86-64":
        exe = Path(a.build) / "examples/firmware/host/roz_fw_host"
        if not exe.exists():
            return None, f"{exe.name} is not built"
        return ["qemu-x86_64", "-cpu", "max", str(exe), robot, wasm, ticks], None
    if target == "aarch64":
        if not a.aarch64:
            return None, "no aarch64 tree"
        exe = Path(a.aarch64) / "examples/firmware/host/roz_fw_host"
        if not exe.exists():
            return None, "roz_fw_host is not built for aarch64"
        return ["qemu-aarch64", "-L", "/", str(exe), robot, wasm, ticks], None
    if image is None:
        return None, "no image of this controller for this board (examples/firmware)"
    name, _, tree = image.partition("@")
    elf = Path(f"{a.build}-fw-{tree or target}") / f"roz_fw_{name}.elf"
    if not elf.exists():
        return None, f"{elf.parent.name}/{elf.name} is not built"
    return ["qemu-system-arm", "-M", BOARDS[target], "-nographic", "-monitor", "none",
            "-serial", "none", "-semihosting-config", "enable=on,target=native",
            "-icount", "shift=0", "-kernel", str(elf)], None


def tick_inlined(elf):
    """(the function, its addresses) where an image's link-time optimisation
    inlined roz_runtime_tick (into the application's fw_app_run, its one
    caller); None when the image has it as a function of its own."""
    syms = subprocess.run(["arm-none-eabi-nm", elf], check=True, capture_output=True,
                          text=True).stdout.split()
    if TICK in syms:
        return None
    return (HOST_FN, qemu_count.inlined_addresses(elf, TICK, HOST_FN, "arm-none-eabi-"))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", required=True, help="the host build (and BUILD-fw-* beside it)")
    ap.add_argument("--aarch64", help="the aarch64 Linux tree (roz_fw_host built)")
    ap.add_argument("--json", required=True)
    ap.add_argument("--skip", type=int, default=20, help="ticks left out first")
    ap.add_argument("--ticks", type=int, default=100,
                    help="ticks measured (a multiple of the policy's decimation)")
    ap.add_argument("--only", action="append", default=[], help="TARGET or CONTROLLER to run")
    a = ap.parse_args(argv)
    ctl_dir = Path(a.build) / "examples/controllers"
    rows = []
    with open(a.json, "w", encoding="utf-8") as out:
        for name, robot, wasm_file, images in CONTROLLERS:
            wasm = str(ctl_dir / wasm_file)
            for target in TARGETS:
                if a.only and target not in a.only and name not in a.only:
                    continue
                row = {"controller": name, "target": target}
                cmd, why = command(target, robot, wasm, images.get(target), a)
                if cmd is None:
                    row["skipped"] = why
                else:
                    inlined = None
                    if cmd[0] == "qemu-system-arm":
                        inlined = tick_inlined(cmd[-1])
                        if inlined is not None:
                            row["tick_inlined_in"] = inlined[0]
                    c, output = qemu_count.count(
                        [cmd[0], "-d", "in_asm,exec,nochain"] + cmd[1:],
                        {**TRACK, TICK: "runtime"}, TICK, a.skip, a.ticks, inlined)
                    res = qemu_count.summarise(c, a.skip, a.ticks, PARTS + ["runtime"])
                    row.update(res)
                    row["command"] = " ".join([os.path.basename(cmd[0])] + [
                        os.path.basename(x) if "/" in x else x for x in cmd[1:]])
                    print(f"{name} on {target}: tick {res['parts']['tick']['mean']:,.0f} "
                          f"instructions (process {res['parts']['process']['mean']:,.0f}, "
                          f"max {res['parts']['process']['max']:,})", flush=True)
                out.write(json.dumps(row, sort_keys=True) + "\n")
                out.flush()
                rows.append(row)
    # the table BENCHMARKS.md shows (bench/report.py)
    spec = importlib.util.spec_from_file_location("roz_bench_report", HERE.parent / "report.py")
    report = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(report)
    print("\n" + report.targets_table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
