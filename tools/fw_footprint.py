# SPDX-License-Identifier: Apache-2.0
"""The footprint of a roz firmware image, per component, from its GNU ld map.

    python tools/fw_footprint.py IMAGE.map [--elf IMAGE.elf] [--run QEMU_OUTPUT]
                                 [--aim-flash KB] [--aim-ram KB] [--title TEXT]

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
manifest table (rozgen's <id>_manifest.c), controller (the embedded .wasm,
or the controller compiled ahead of time: libroz_aot_<name>.a),
wasm3 (libroz_wasm3.a), libc/libm (newlib), libgcc (soft-float and
division helpers), app (the rest: the board's start-up, semihosting and
C library hooks, the application); roz core includes the ahead-of-time
engine's glue (libroz_aot.a). The application's static objects of
roz's types count to the component whose storage they are: the runtime
(rt) and the validator's scratch to roz core, the loopback port (sim,
port) to port. KB is 1024 bytes.

A link-time-optimised image (-flto) has its code in the link's own
objects (*.ltrans.o), one input section per function or object: each is
counted to the component of the source file that defines it, from the
image's debug information (--elf: the symbols' files as `nm -l` reads
them; $NM, default arm-none-eabi-nm), else of the archive member that
defined the symbol before the optimisation (the map's cross reference
table, -Wl,--cref); a function's string literals count to the function.
What none of these names is "unattributed" (static data the debug
information gives no file, e.g. a table of the loopback port's). The map
lists string literals before the link merges their duplicates: "merged
strings" (negative) is what that merging saved, so that the total is the
image's size.
"""
import argparse
import os
import re
import subprocess
import sys

FLASH_SECTIONS = {".vectors", ".text", ".ARM.extab", ".ARM.exidx"}
DATA_SECTION = ".data"
BSS_SECTION = ".bss"
COMPONENTS = ["roz core", "hal", "port", "manifest table", "controller", "wasm3",
              "libc/libm", "libgcc", "app", "unattributed", "merged strings"]

INPUT = re.compile(r"^ (?P<name>[.\w*$]\S*)\s+0x(?P<addr>[0-9a-f]+)\s+0x(?P<size>[0-9a-f]+)\s+(?P<file>\S.*)$")
INPUT_NAME_ONLY = re.compile(r"^ (?P<name>[.\w*$]\S*)\s*$")
INPUT_REST = re.compile(r"^\s+0x(?P<addr>[0-9a-f]+)\s+0x(?P<size>[0-9a-f]+)\s+(?P<file>\S.*)$")
FILL = re.compile(r"^ \*fill\*\s+0x(?P<addr>[0-9a-f]+)\s+0x(?P<size>[0-9a-f]+)")
OUTPUT = re.compile(r"^(?P<name>\.[\w.]+)(\s+0x(?P<addr>[0-9a-f]+)\s+0x(?P<size>[0-9a-f]+))?")


# the images' static objects of roz's types (examples/firmware/app/fw_app.c,
# cortex_m/main.c), by input section
APP_OBJECTS = {".bss.rt": "roz core", ".bss.scratch": "roz core", ".bss.sim": "port",
               ".bss.port": "port"}


def first_component(rules, path: str) -> str:
    """The component of the first (pattern, component) of @p rules whose
    pattern is in @p path (with / for \\), else "app"."""
    path = path.replace("\\", "/")
    for pattern, comp in rules:
        if pattern.search(path):
            return comp
    return "app"


# an input file's component, by its archive or object's name
FILE_COMPONENTS = [
    (re.compile(r"libroz_core\.a|libroz_aot\.a"), "roz core"),
    (re.compile(r"libroz_aot_\w+\.a"), "controller"),
    (re.compile(r"libroz_hal\.a"), "hal"),
    (re.compile(r"libroz_port_\w+\.a"), "port"),
    (re.compile(r"libroz_wasm3\.a"), "wasm3"),
    (re.compile(r"_manifest\.c\.(obj|o)$"), "manifest table"),
    (re.compile(r"_wasm\.c\.(obj|o)$"), "controller"),
    (re.compile(r"libgcc\.a"), "libgcc"),
    (re.compile(r"lib(c|c_nano|m|g|g_nano|nosys)\.a"), "libc/libm"),
]


def component(path: str, section: str = "") -> str:
    """The component an input file (and section) belongs to."""
    section = LTO_SUFFIX.sub("", section)
    if section in APP_OBJECTS:
        return APP_OBJECTS[section]
    return first_component(FILE_COMPONENTS, path)


LTRANS = re.compile(r"\.ltrans\d*\.ltrans\.o$|\.ltrans\.o$")
MEMBER = re.compile(r"^(?P<archive>\S+\.a)\((?P<member>[^)]+)\)")
CREF_HEAD = re.compile(r"^(?P<sym>\S+)\s+(?P<file>\S.*?)(?: \(symbol from plugin\))?$")
# what link-time optimisation appends to a function's name
LTO_SUFFIX = re.compile(r"(\.(lto_priv|constprop|part|isra|cold)(\.\d+)?)+$")
# a source file's component, by where it sits in roz's tree (the end of its
# path only, so that where the tree is cloned does not matter)
SOURCE_COMPONENTS = [
    (re.compile(r"/wasm3/[^/]+$"), "wasm3"),
    (re.compile(r"_manifest\.c$"), "manifest table"),
    (re.compile(r"_wasm\.c$"), "controller"),
    (re.compile(r"/roz_aot/[^/]+/[^/]+_(aot|glue)\.c$"), "controller"),
    (re.compile(r"/(lib/(src|aot|math|include/roz)|sdk/include)/[^/]+$"), "roz core"),
    (re.compile(r"/hal/(src|include/roz/hal)/[^/]+$"), "hal"),
    (re.compile(r"/ports/[^/]+/(src|include/roz/port)/[^/]+$"), "port"),
    (re.compile(r"/libgcc/"), "libgcc"),
    (re.compile(r"/newlib/"), "libc/libm"),
]


def source_component(path: str) -> str:
    return first_component(SOURCE_COMPONENTS, path)


class LtoOwners:
    """Who an input section of a link-time-optimised image belongs to: by
    the debug information's file of the symbol at its address, else by the
    archive member that defined its symbol before the optimisation."""

    def __init__(self, map_path: str, elf: str):
        self.by_addr = {}
        self.file_of = {}
        self.defined_in = {}
        members = {}
        lines = open(map_path, encoding="utf-8", errors="replace").read().splitlines()
        for line in lines:  # "Archive member included ...": member -> its archive
            m = MEMBER.match(line)
            if m:
                members[os.path.basename(m.group("member"))] = line[:m.end()]
            if line.startswith("Linker script and memory map"):
                break
        try:
            start = lines.index("Cross Reference Table")
        except ValueError:
            start = len(lines)
        sym = None
        for line in lines[start + 1:]:  # a symbol's first file is where it is defined
            if line[:1].strip():  # a symbol, and its file unless the name is long
                m = CREF_HEAD.match(line)
                sym, f = (m.group("sym"), m.group("file")) if m else (line.strip(), None)
            elif sym is not None and line.strip():  # the long name's file
                f = CREF_HEAD.match("x " + line.strip()).group("file")
            else:
                continue
            if f is not None:
                if sym != "Symbol" and not LTRANS.search(f):
                    self.defined_in[sym] = members.get(os.path.basename(f), f)
                sym = None
        nm = os.environ.get("NM", "arm-none-eabi-nm")
        out = subprocess.run([nm, "-S", "-l", "--defined-only", elf], check=True,
                             capture_output=True, text=True).stdout
        for line in out.splitlines():
            head, _, where = line.partition("\t")
            f = head.split()
            if len(f) != 4:
                continue
            addr, where = int(f[0], 16), where.rsplit(":", 1)[0]
            if where or addr not in self.by_addr:
                self.by_addr[addr] = (f[3], where)
            if where:
                self.file_of[f[3]] = where

    def component(self, addr: int, section: str) -> str:
        name, where = self.by_addr.get(addr, ("", ""))
        if where:
            return source_component(where)
        # a function's string literals: .rodata.<function>.str1.<align>
        owner = re.sub(r"^\.(text|rodata|data|bss)\.", "", section)
        owner = re.sub(r"\.str\d+\.\d+$", "", owner)
        for n in (name, owner, LTO_SUFFIX.sub("", owner)):
            if n in self.file_of:
                return source_component(self.file_of[n])
        defined = self.defined_in.get(LTO_SUFFIX.sub("", name or owner))
        if defined:
            return component(defined)
        return "unattributed"


def parse_map(path: str, elf: str = None):
    """{component: {"flash": n, "ram": n}} from the map's memory map part
    (and, for a link-time-optimised image, the ELF's symbols)."""
    sizes = {c: {"flash": 0, "ram": 0} for c in COMPONENTS}
    out_sizes = {}
    lto = None
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
                if m.group("size") and out not in out_sizes:
                    out_sizes[out] = int(m.group("size"), 16)
                pending = None
                continue
            if out is None:
                continue
            m = None
            if pending is not None:
                m = INPUT_REST.match(line)
                name, pending = pending, None
                if not m:
                    continue
            else:
                m = INPUT.match(line)
                name = m.group("name") if m else None
            if m:
                comp = None
                if LTRANS.search(m.group("file")) and LTO_SUFFIX.sub("", name) not in APP_OBJECTS:
                    if lto is None:
                        if elf is None:
                            raise LtoWithoutElf()
                        lto = LtoOwners(path, elf)
                    comp = lto.component(int(m.group("addr"), 16), name)
                last_comp = add(sizes, out, m.group("addr"), m.group("size"), m.group("file"),
                                name, comp)
                continue
            m = FILL.match(line)
            if m:  # alignment padding: the component before it
                add_bytes(sizes, out, int(m.group("size"), 16), last_comp)
                continue
            m = INPUT_NAME_ONLY.match(line)
            if m:
                pending = m.group("name")
    # the image as the link wrote it: input sections of strings (SEC_MERGE)
    # are listed at their size before the link merged their duplicates
    image = sum(n for o, n in out_sizes.items() if o in FLASH_SECTIONS or o == DATA_SECTION)
    listed = sum(v["flash"] for v in sizes.values())
    if out_sizes and image != listed:
        sizes["merged strings"]["flash"] += image - listed
    return sizes


class LtoWithoutElf(Exception):
    """A link-time-optimised image's map, without its ELF."""


def add(sizes, out, addr, size, path, section, comp=None):
    comp = comp or component(path.strip(), section)
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
    ap.add_argument("--elf", help="the image (a link-time-optimised one needs it)")
    ap.add_argument("--run", help="the image's output under QEMU (for the high-water marks)")
    ap.add_argument("--aim-flash", type=float, help="flash aim, KB")
    ap.add_argument("--aim-ram", type=float, help="RAM aim (static + heap + stack), KB")
    ap.add_argument("--title", default=None)
    args = ap.parse_args(argv)

    try:
        sizes = parse_map(args.map, args.elf)
    except OSError as e:
        print(f"fw_footprint: {e.filename}: {e.strerror}", file=sys.stderr)
        return 2
    except LtoWithoutElf:
        print(f"fw_footprint: {args.map}: a link-time-optimised image: give its ELF (--elf) "
              "for the components", file=sys.stderr)
        return 2
    except subprocess.CalledProcessError as e:
        print(f"fw_footprint: {args.elf}: {e.cmd[0]} failed: {e.stderr.strip()}", file=sys.stderr)
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
    print(f"  flash: {total_flash} bytes")
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
