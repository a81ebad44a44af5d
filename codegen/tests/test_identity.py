# SPDX-License-Identifier: Apache-2.0
"""The manifest identity: the interface hash, `rozgen --identity`, and the
record the generated channel header puts into a wasm32 controller.

The byte string and the hash of ``ARM`` are the worked example of
codegen/README.md ("Manifest identity"); test/identity/test_identity.c
checks the C side against the same numbers.
"""

import shutil
import struct
import subprocess

import pytest

from conftest import REPO, builtin_manifests, channel, robot_toml, run_rozgen
from rozgen import identity
from rozgen.model import Maxima
from rozgen.validate import validate

ARM = robot_toml(
    "arm",
    channel("commands", "j1/velocity", "velocity", "rad/s", "[-2, 2]", "0"),
    channel("states", "j1/position", "position", "rad", "[-4, 4]", "0.0"))

#: interface_bytes(ARM), written out by hand from the definition.
ARM_BYTES = (
    b"roz-interface-v1"
    + b"\x01\x00\x00\x00" + b"\x01\x00\x00\x00"
    + b"\x0b\x00\x00\x00j1/velocity" + b"\x08\x00\x00\x00velocity" + b"\x05\x00\x00\x00rad/s"
    + bytes.fromhex("00000000000000c0") + bytes.fromhex("0000000000000040")
    + b"\x0b\x00\x00\x00j1/position" + b"\x08\x00\x00\x00position" + b"\x03\x00\x00\x00rad"
    + bytes.fromhex("00000000000010c0") + bytes.fromhex("0000000000001040")
)
ARM_HASH = 0x22B82593F3D5E024


def manifest(text: str):
    m, problems = validate(text, Maxima())
    assert problems == [], problems
    return m


def test_fnv1a64_known_answers():
    # the published FNV-1a 64 test values
    assert identity.fnv1a64(b"") == 0xCBF29CE484222325
    assert identity.fnv1a64(b"a") == 0xAF63DC4C8601EC8C
    assert identity.fnv1a64(b"foobar") == 0x85944171F73967E8


def test_worked_example():
    m = manifest(ARM)
    assert identity.interface_bytes(m) == ARM_BYTES
    assert identity.interface_hash(m) == ARM_HASH
    assert identity.record(m) == b"\x01\x03arm" + struct.pack("<Q", ARM_HASH)


SAME = [  # (what, old, new): not part of the interface
    ("robot_id", 'robot_id = "arm"', 'robot_id = "arm2"'),
    ("robot_class", 'robot_id = "arm"', 'robot_id = "arm"\nrobot_class = "cobot"'),
    ("control rate", 'robot_id = "arm"', 'robot_id = "arm"\ncontrol_rate_hz = 500'),
    ("default", "limits = [-2, 2]\ndefault = 0", "limits = [-2, 2]\ndefault = 1.5"),
    ("max rate", "default = 0\n", "default = 0\nmax_rate_of_change = 0.1\n"),
    ("pairing", "default = 0\n", "default = 0\nposition_state_index = 0\n"),
    ("limit margin", "limits = [-4, 4]\n", "limits = [-4, 4]\nlimit_margin = 0.5\n"),
    ("integer or float", "limits = [-2, 2]", "limits = [-2.0, 2.0]"),
    ("hardware", "default = 0.0\n", 'default = 0.0\n[hardware]\nport = "loopback"\n'),
]
DIFFER = [  # (what, old, new): what an index means
    ("command name", '"j1/velocity"', '"j2/velocity"'),
    ("interface type", 'interface_type = "velocity"', 'interface_type = "effort"'),
    ("unit", 'unit = "rad"\n', 'unit = "deg"\n'),
    ("min", "limits = [-4, 4]", "limits = [-3, 4]"),
    ("max", "limits = [-4, 4]", "limits = [-4, 4.000000000000001]"),
    ("a state more", "", channel("states", "j2/position", "position", "rad", "[-4, 4]", "0.0")),
]


@pytest.mark.parametrize("what,old,new", SAME, ids=[s[0] for s in SAME])
def test_hash_ignores(what, old, new):
    assert old in ARM
    assert identity.interface_hash(manifest(ARM.replace(old, new, 1))) == ARM_HASH


def test_minus_zero_is_zero():
    plus = ARM.replace("limits = [-2, 2]", "limits = [0, 2]")
    minus = ARM.replace("limits = [-2, 2]", "limits = [-0.0, 2]")
    assert manifest(minus).commands[0].min == 0.0
    assert identity.interface_hash(manifest(minus)) == identity.interface_hash(manifest(plus))


@pytest.mark.parametrize("what,old,new", DIFFER, ids=[d[0] for d in DIFFER])
def test_hash_covers(what, old, new):
    assert old in ARM or old == ""
    changed = ARM.replace(old, new, 1) if old else ARM + new
    assert identity.interface_hash(manifest(changed)) != ARM_HASH


def test_hash_covers_order_and_lists():
    two = ARM.replace("\n[[manifest.states]]",
                      channel("commands", "j2/velocity", "velocity", "rad/s", "[-2, 2]", "0")
                      + "\n[[manifest.states]]")
    swapped = two.replace('"j1/velocity"', '"tmp"').replace('"j2/velocity"', '"j1/velocity"') \
        .replace('"tmp"', '"j2/velocity"')
    assert identity.interface_hash(manifest(two)) != identity.interface_hash(manifest(swapped))
    # the same channel as a command or as a state
    as_state = ARM.replace("[[manifest.states]]", "[[manifest.commands]]", 1) \
        .replace("[[manifest.commands]]", "[[manifest.states]]", 1)
    moved = manifest(as_state)
    assert [c.name for c in moved.commands] == ["j1/position"]
    assert identity.interface_hash(moved) != ARM_HASH


def test_identity_option(tmp_path):
    result = run_rozgen("--identity", *builtin_manifests())
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert len(lines) == len(builtin_manifests())
    for line, path in zip(lines, builtin_manifests()):
        with open(path, "rb") as f:
            m, _ = validate(f.read(), Maxima())
        assert line == f"{m.robot_id} {identity.interface_hash(m):016x}"
    arm = tmp_path / "arm.toml"
    arm.write_text(ARM)
    assert run_rozgen("--identity", arm).stdout == f"arm {ARM_HASH:016x}\n"
    bad = run_rozgen("--identity", "--registry", arm)
    assert bad.returncode == 2 and "--identity and --registry" in bad.stderr
    assert run_rozgen("--identity", "--json", arm).returncode == 2
    assert run_rozgen("--identity", REPO / "manifests" / "invalid" / "limits-order.toml") \
        .returncode == 2


def _asm_record(header: str) -> bytes:
    """The bytes the header's __asm__ statement puts into roz.manifest."""
    body = header[header.index('__asm__(".section .custom_section.roz.manifest'):]
    body = body[:body.index(".text")]
    out = b""
    for directive, value in (line.split(" ", 1) for line in
                             (part.strip('" \n') for part in body.split("\\n")[1:]) if line):
        if directive == ".int8":
            out += bytes([int(value, 0)])
        elif directive == ".ascii":
            out += value.strip('\\"').encode("ascii")
        elif directive == ".int64":
            out += struct.pack("<Q", int(value, 0))
        else:
            raise AssertionError(f"unexpected directive {directive}")
    return out


def test_header_carries_the_identity(tmp_path):
    for toml in builtin_manifests():
        assert run_rozgen("-o", tmp_path, toml).returncode == 0
        with open(toml, "rb") as f:
            m, _ = validate(f.read(), Maxima())
        header = (tmp_path / f"{m.robot_id}_channels.h").read_text()
        h = identity.interface_hash(m)
        assert f'{m.prefix}_ROBOT_ID' in header and f'"{m.robot_id}"\n' in header
        assert f"{m.prefix}_INTERFACE_HASH" in header and f" 0x{h:016x}\n" in header
        assert _asm_record(header) == identity.record(m)
        assert "#if defined(__wasm__) && !defined(ROZ_NO_ROBOT_IDENTITY)" in header


def _custom_sections(wasm: bytes) -> list[tuple[str, bytes]]:
    """(name, content) of every custom section of a module."""

    def leb(at):
        value = shift = 0
        while True:
            byte = wasm[at]
            at += 1
            value |= (byte & 0x7F) << shift
            shift += 7
            if byte < 0x80:
                return value, at

    assert wasm[:8] == b"\0asm\1\0\0\0"
    found, at = [], 8
    while at < len(wasm):
        section = wasm[at]
        size, at = leb(at + 1)
        if section == 0:
            name_len, start = leb(at)
            found.append((wasm[start:start + name_len].decode(), wasm[start + name_len:at + size]))
        at += size
    return found


@pytest.fixture(scope="module")
def wasm_clang():
    clang = shutil.which("clang")
    if clang is None or "wasm32" not in subprocess.run(
            [clang, "--print-targets"], capture_output=True, text=True).stdout:
        pytest.skip("no clang with the wasm32 target")
    return clang


def _controller(clang, tmp_path, sources: dict[str, str]) -> bytes:
    out = tmp_path / "gen"
    result = run_rozgen("-o", out, REPO / "manifests" / "ur5.toml",
                        REPO / "manifests" / "quadcopter.toml")
    assert result.returncode == 0, result.stderr
    paths = []
    for name, text in sources.items():
        (tmp_path / name).write_text(text)
        paths.append(str(tmp_path / name))
    wasm = tmp_path / "ctl.wasm"
    # as cmake/RozWasm.cmake builds a controller (--strip-all keeps it)
    result = subprocess.run(
        [clang, "--target=wasm32", "-O2", "-nostdlib", "-std=c11", "-Wall", "-Wextra",
         "-Werror", "-pedantic", f"-I{REPO / 'sdk' / 'include'}",
         f"-I{out}", "-Wl,--no-entry", "-Wl,--strip-all", "-o", str(wasm), *paths],
        capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return wasm.read_bytes()


PROCESS = ('#include "roz_controller.h"\n#include "ur5_channels.h"\n'
           "ROZ_PROCESS(tick) { roz_command_set(ROZ_UR5_CMD_ELBOW_JOINT_VELOCITY, "
           "0.01 * (double)tick); }\n")
HELPER = '#include "ur5_channels.h"\nint helper(void) { return ROZ_UR5_N_COMMANDS; }\n'


def _ur5_record():
    with open(REPO / "manifests" / "ur5.toml", "rb") as f:
        return identity.record(validate(f.read(), Maxima())[0])


def test_controller_carries_the_identity(wasm_clang, tmp_path):
    wasm = _controller(wasm_clang, tmp_path, {"ctl.c": PROCESS})
    assert _custom_sections(wasm) == [("roz.manifest", _ur5_record())]
    objdump = shutil.which("wasm-objdump")
    if objdump:
        listed = subprocess.run([objdump, "-x", tmp_path / "ctl.wasm"], capture_output=True,
                                text=True).stdout
        assert 'Custom:\n - name: "roz.manifest"' in listed


def test_controller_of_two_files(wasm_clang, tmp_path):
    """wasm-ld joins the sections: one copy of the record per object file."""
    wasm = _controller(wasm_clang, tmp_path, {"ctl.c": PROCESS, "helper.c": HELPER})
    assert _custom_sections(wasm) == [("roz.manifest", _ur5_record() * 2)]


def test_controller_for_two_robots(wasm_clang, tmp_path):
    """Two robots' headers: two different records, which roz refuses."""
    both = PROCESS + '#include "quadcopter_channels.h"\n'
    wasm = _controller(wasm_clang, tmp_path, {"ctl.c": both})
    (name, content), = _custom_sections(wasm)
    assert name == "roz.manifest" and content.startswith(_ur5_record())
    assert content[len(_ur5_record()):].startswith(b"\x01\x0aquadcopter")


def test_controller_for_any_robot(wasm_clang, tmp_path):
    wasm = _controller(wasm_clang, tmp_path,
                       {"ctl.c": "#define ROZ_NO_ROBOT_IDENTITY\n" + PROCESS})
    assert _custom_sections(wasm) == []
