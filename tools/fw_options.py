# SPDX-License-Identifier: Apache-2.0
"""The firmware images' flash per build option: what each part they leave
out would cost them.

    python tools/fw_options.py --build DIR [--jobs N] [CMAKE_ARGS...]

Builds the G1 PD image (Cortex-M7, mps2-an500) and the UR5 images
(Cortex-M4F, mps2-an386) of examples/firmware as shipped, then once per
option they use with that one part put back: each ROZ_CFG_* switch their
configuration header (examples/firmware/config/) sets to leave something
out, through a header of DIR's that includes it and sets the option back
to roz's default (FW_CONFIG), and link-time optimisation off. Prints a
Markdown table of the images' flash (tools/fw_footprint.py's total) and
what leaving each part out saves. CMAKE_ARGS go to every configure (the
Makefile's: ROZ_SOURCE_DIR, ROZGEN_EXECUTABLE, ROZ_WASM3_SDIST, -G Ninja).
Long: one build of roz per row and board (`make firmware-options`).
"""
import argparse
import pathlib
import re
import subprocess
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import fw_footprint  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
FIRMWARE = ROOT / "examples" / "firmware"

# board: (its configuration header, its images and their titles)
BOARDS = {
    "mps2-an500": ("g1_m7.h", [("g1_pd", "G1 PD, Cortex-M7")]),
    "mps2-an386": ("ur5_m4f.h", [("ur5_sine", "UR5 sine, Cortex-M4F"),
                                 ("ur5_regs", "UR5 regs (no simulator), Cortex-M4F")]),
}
# option: (roz's default, what it leaves out when the image's value differs)
OPTIONS = {
    "ROZ_CFG_NN_IMPORTS": ("1", "the nn imports (nn.matvec, nn.act)"),
    "ROZ_CFG_MATH_IMPORTS": ("1", "the math imports (math.sin, math.cos)"),
    "ROZ_CFG_BULK_IMPORTS": ("1", "the bulk imports (state.get_all, command.set_all)"),
    "ROZ_CFG_FORMAT_DOUBLE": ("1", "%g's decimal conversion"),
    "ROZ_CFG_MAX_INPUTS": ("32", "the operator inputs"),
    "ROZ_CFG_CRC32_SLICES": ("4", "the CRC's large tables (slicing by four: 4 KiB)"),
    "ROZ_CFG_FALL": ("1", "the fall rule (roz/fall.h)"),
}
LTO = "link-time optimisation"


def config_values(header: pathlib.Path) -> dict:
    """The options a configuration header defines, and their values."""
    text = header.read_text(encoding="utf-8")
    return dict(re.findall(r"^#define (ROZ_CFG_\w+)\s+(\S+)", text, re.M))


def build(tree: pathlib.Path, board: str, images, cmake_args, jobs: int, extra) -> dict:
    """Configures and builds a tree's images; {image: flash bytes}."""
    if not (tree / "CMakeCache.txt").exists():
        subprocess.run(["cmake", "-S", str(FIRMWARE), "-B", str(tree), f"-DFW_BOARD={board}",
                        *cmake_args, *extra], check=True, stdout=subprocess.DEVNULL)
    targets = [f"roz_fw_{name}" for name, _ in images]
    subprocess.run(["cmake", "--build", str(tree), "-j", str(jobs), "--target", *targets],
                   check=True, stdout=subprocess.DEVNULL)
    flash = {}
    for name, _ in images:
        sizes = fw_footprint.parse_map(str(tree / f"roz_fw_{name}.map"),
                                       str(tree / f"roz_fw_{name}.elf"))
        flash[name] = sum(v["flash"] for v in sizes.values())
    return flash


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", required=True, type=pathlib.Path, help="a folder for the trees")
    ap.add_argument("--jobs", type=int, default=2)
    args, cmake_args = ap.parse_known_args(argv)
    args.build.mkdir(parents=True, exist_ok=True)

    rows = {}  # row -> {image: flash}
    titles = []
    for board, (header, images) in BOARDS.items():
        titles += images
        shipped = config_values(FIRMWARE / "config" / header)
        rows.setdefault("as shipped", {}).update(
            build(args.build / f"{board}-shipped", board, images, cmake_args, args.jobs, []))
        for option, (default, _) in OPTIONS.items():
            if option not in shipped or shipped[option] == default:
                continue
            variant = args.build / f"{board}-{option.lower()}"
            variant.mkdir(exist_ok=True)
            guard = f"FW_OPTIONS_{option}_H"
            (variant / f"with_{header}").write_text(
                f"/* {header} with {option} back at roz's default (tools/fw_options.py) */\n"
                f"#ifndef {guard}\n#define {guard}\n#include \"{header}\"\n#undef {option}\n"
                f"#define {option} {default}\n#endif\n", encoding="utf-8")
            rows.setdefault(option, {}).update(
                build(variant / "tree", board, images, cmake_args, args.jobs,
                      [f"-DFW_CONFIG={variant / f'with_{header}'}"]))
        rows.setdefault(LTO, {}).update(
            build(args.build / f"{board}-no-lto", board, images, cmake_args, args.jobs,
                  ["-DCMAKE_INTERPROCEDURAL_OPTIMIZATION=OFF"]))

    base = rows["as shipped"]
    print("Flash of each image as shipped, and with one part put back: the bytes "
          "leaving it out saves (tools/fw_options.py; KB = 1024 bytes).\n")
    print("| left out | " + " | ".join(t for _, t in titles) + " |")
    print("|---|" + "---:|" * len(titles))
    for row, flash in rows.items():
        if row == "as shipped":
            cells = [f"{base[n]:,} ({base[n] / 1024:.1f} KB)" for n, _ in titles]
            label = "**as shipped**"
        else:
            cells = [f"{flash[n] - base[n]:,}" if n in flash else "(kept)" for n, _ in titles]
            label = row if row == LTO else f"{OPTIONS[row][1]} (`{row}`)"
        print(f"| {label} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
