# SPDX-License-Identifier: Apache-2.0
"""The footprint of a roz firmware image, per component, from its GNU ld map.

    python tools/fw_footprint.py IMAGE.map [--run QEMU_OUTPUT] [--aim-flash KB]
                                 [--aim-ram KB] [--title TEXT]

Flash is what the image stores (code, read-only data, the initial values of
.data); static RAM is .data and .bss. The heap and the main stack are
regions the linker script reserves (sections .heap and .stack): what they
are sized to is not what the run needed, so with --run (the image's output
under QEMU) the table adds the high-water marks the run measured (the most
the heap's break ever reached, the deepest the painted stack was used), and
"RAM all told" is static RAM plus the heap and stack regions as reserved
(what the board must have), with the high-water figure beside it.

Components, by the archive or object each input section came from:
roz core (libroz_core.a), hal (libroz_hal.a), port (libroz_port_*.a),
manifest table (rozgen's <id>_manifest.c), controller (the embedded .wasm),
wasm3 (libroz_wasm3.a), libc/libm (newlib), libgcc (soft-float and
division helpers), app (the rest: the board's start-up, semihosting and
C library hooks, the application). The application's static objects of
roz's types count to the component whose storage they are: the runtime
(rt) and the validator's scratch to roz core, the loopback port (sim,
port) to port. KB is 1024 bytes.
"""
import argparse
import re
import sys

FLASH_SECTIONS = {".vectors", ".text", ".ARM.extab", ".ARM.exidx"}
DATA_SECTION = ".data"
BSS_SECTION = ".bss"
COMPONENTS = ["roz core", "hal", "port", "manifest table", "controller", "wasm3",
              "libc/libm", "libgcc", "app"]

INPUT = re.compile(r"^ (?P<name>[.\w*$]\S*)\s+0x(?P<addr>[0-9a-f]+)\s+0x(?P<size>[0-9a-f]+)\s+(?P<file>\S.*)$")
INPUT_NAME_ONLY = re.compile(r"^ (?P<name>[.\w*$]\S*)\s*$")
INPUT_REST = re.compile(r"^\s+0x(?P<addr>[0-9a-f]+)\s+0x(?P<size>[0-9a-f]+)\s+(?P<file>\S.*)$")
FILL = re.compile(r"^ \*fill\*\s+0x(?P<addr>[0-9a-f]+)\s+0x(?P<size>[0-9a-f]+)")
OUTPUT = re.compile(r"^(?P<name>\.[\w.]+)(\s+0x(?P<addr>[0-9a-f]+)\s+0x(?P<size>[0-9a-f]+))?")


# the images' static objects of roz's types (examples/firmware/app/fw_app.c,
# cortex_m/main.c), by input section
APP_OBJECTS = {".bss.rt": "roz core", ".bss.scratch": "roz core", ".bss.sim": "port",
               ".bss.port": "port"}


def component(path: str, section: str = "") -> str:
    """The component an input file (and section) belongs to."""
    if section in APP_OBJECTS:
        return APP_OBJECTS[section]
    base = path.replace("\\", "/")
    if "libroz_core.a" in base:
        return "roz core"
    if "libroz_hal.a" in base:
        return "hal"
    if re.search(r"libroz_port_\w+\.a", base):
        return "port"
    if "libroz_wasm3.a" in base:
        return "wasm3"
    if re.search(r"_manifest\.c\.(obj|o)$", base):
        return "manifest table"
    if re.search(r"_wasm\.c\.(obj|o)$", base):
        return "controller"
    if "libgcc.a" in base:
        return "libgcc"
    if re.search(r"lib(c|c_nano|m|g|g_nano|nosys)\.a", base):
        return "libc/libm"
    return "app"


def parse_map(path: str):
    """{component: {"flash": n, "ram": n}} from the map's memory map part."""
    sizes = {c: {"flash": 0, "ram": 0} for c in COMPONENTS}
    in_map = False
    out = None
    pending = None
    last_comp = "app"
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            line = line.rstrip("\n")
            if not in_map:
                in_map = line.startswith("Linker script and memory map")
                continue
            m = OUTPUT.match(line)
            if m:
                out = m.group("name")
                pending = None
                continue
            if out is None:
                continue
            if pending is not None:
                m = INPUT_REST.match(line)
                name, pending = pending, None
                if m:
                    last_comp = add(sizes, out, m.group("addr"), m.group("size"), m.group("file"),
                                    name)
                continue
            m = INPUT.match(line)
            if m:
                last_comp = add(sizes, out, m.group("addr"), m.group("size"), m.group("file"),
                                m.group("name"))
                continue
            m = FILL.match(line)
            if m:  # alignment padding: the component before it
                add_bytes(sizes, out, int(m.group("size"), 16), last_comp)
                continue
            m = INPUT_NAME_ONLY.match(line)
            if m:
                pending = m.group("name")
    return sizes


def add(sizes, out, addr, size, path, section):
    comp = component(path.strip(), section)
    if int(addr, 16) == 0 and out not in FLASH_SECTIONS:
        return comp  # discarded, or not in the image
    add_bytes(sizes, out, int(size, 16), comp)
    return comp


def add_bytes(sizes, out, n, comp):
    if out in FLASH_SECTIONS:
        sizes[comp]["flash"] += n
    elif out == DATA_SECTION:
        sizes[comp]["flash"] += n  # its initial values
        sizes[comp]["ram"] += n
    elif out == BSS_SECTION:
        sizes[comp]["ram"] += n


def parse_run(path: str):
    """Heap and stack high-water marks (and their reserved sizes) from the run."""
    text = open(path, encoding="utf-8", errors="replace").read()
    m = re.search(r"memory: heap high-water (\d+) of (\d+) bytes, stack high-water (\d+) of (\d+)",
                  text)
    if not m:
        return None
    return {"heap": int(m.group(1)), "heap_size": int(m.group(2)),
            "stack": int(m.group(3)), "stack_size": int(m.group(4))}


def kb(n: int) -> str:
    return f"{n / 1024:.1f}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("map")
    ap.add_argument("--run", help="the image's output under QEMU (for the high-water marks)")
    ap.add_argument("--aim-flash", type=float, help="flash aim, KB")
    ap.add_argument("--aim-ram", type=float, help="RAM aim (static + heap + stack), KB")
    ap.add_argument("--title", default=None)
    args = ap.parse_args(argv)

    try:
        sizes = parse_map(args.map)
    except OSError as e:
        print(f"fw_footprint: {args.map}: {e.strerror}", file=sys.stderr)
        return 2
    total_flash = sum(v["flash"] for v in sizes.values())
    total_ram = sum(v["ram"] for v in sizes.values())
    if total_flash == 0:
        print(f"fw_footprint: {args.map}: no memory map found (a GNU ld -Map file?)",
              file=sys.stderr)
        return 2

    print(args.title or args.map)
    print(f"  {'component':<16} {'flash KB':>9} {'static RAM KB':>14}")
    for c in COMPONENTS:
        v = sizes[c]
        if v["flash"] or v["ram"]:
            print(f"  {c:<16} {kb(v['flash']):>9} {kb(v['ram']):>14}")
    print(f"  {'total':<16} {kb(total_flash):>9} {kb(total_ram):>14}")
    status = 0
    run = parse_run(args.run) if args.run else None
    if args.run and run is None:
        print(f"fw_footprint: {args.run}: no 'memory:' line", file=sys.stderr)
        return 2
    if run:
        used = total_ram + run["heap"] + run["stack"]
        all_ram = total_ram + run["heap_size"] + run["stack_size"]
        print(f"  heap             {kb(run['heap_size']):>9} KB reserved, {kb(run['heap'])} KB used "
              "at most")
        print(f"  main stack       {kb(run['stack_size']):>9} KB reserved, {kb(run['stack'])} KB used "
              "at most")
        print(f"  RAM all told     {kb(all_ram):>9} KB (static + reserved heap and stack; "
              f"{kb(used)} KB used at most)")
    if args.aim_flash is not None:
        verdict = "met" if total_flash <= args.aim_flash * 1024 else "NOT met"
        print(f"  aim: flash <= {args.aim_flash:g} KB: {verdict}")
    if args.aim_ram is not None and run:
        verdict = "met" if all_ram <= args.aim_ram * 1024 else "NOT met"
        print(f"  aim: RAM <= {args.aim_ram:g} KB: {verdict}")
    return status


if __name__ == "__main__":
    sys.exit(main())
