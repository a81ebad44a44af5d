# SPDX-License-Identifier: Apache-2.0
"""The Rust module rozgen writes beside the C channel header
(<id>_channels.rs, docs/rust.md): the same constants with the same names and
values as <id>_channels.h, and the same identity record, in the source and,
where a rustc with the wasm32 target is found, in a built controller."""

import os
import re
import subprocess
from pathlib import Path

import pytest

from conftest import REPO, builtin_manifests, run_rozgen
from rozgen import identity
from rozgen.validate import Maxima, validate
from test_identity import _custom_sections

C_DEFINE = re.compile(r"^#define (ROZ_[A-Z0-9_]+) +(\S+)", re.M)
RS_CONST = re.compile(r"^    pub const (ROZ_[A-Z0-9_]+): +(\S+) = (\S+);$", re.M)
RS_RECORD = re.compile(r"static IDENTITY: \[u8; (\d+)\] = \[\n(.*?)\n    \];", re.S)


def _manifest(toml: Path):
    with open(toml, "rb") as f:
        return validate(f.read(), Maxima())[0]


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    out = tmp_path_factory.mktemp("rs")
    result = run_rozgen("-o", out, *builtin_manifests())
    assert result.returncode == 0, result.stderr
    return out


@pytest.mark.parametrize("toml", builtin_manifests(), ids=lambda p: p.name)
def test_same_constants_as_the_header(generated, toml):
    m = _manifest(toml)
    header = (generated / f"{m.robot_id}_channels.h").read_text()
    module = (generated / f"{m.robot_id}_channels.rs").read_text()
    c = {name: value for name, value in C_DEFINE.findall(header)
         if not name.endswith("_CHANNELS_H")}
    rs = {name: (ty, value) for name, ty, value in RS_CONST.findall(module)}
    assert set(rs) == set(c)
    for name, (ty, value) in rs.items():
        assert value == c[name], name
        if "_CMD_" in name or "_STATE_" in name:
            assert ty == "i32", name
    assert rs[f"{m.prefix}_N_COMMANDS"] == ("usize", str(len(m.commands)))
    assert rs[f"{m.prefix}_N_STATES"] == ("usize", str(len(m.states)))
    assert rs[f"{m.prefix}_INTERFACE_HASH"] == ("u64", f"0x{identity.interface_hash(m):016x}")
    assert f"pub mod {m.robot_id}_channels {{" in module


@pytest.mark.parametrize("toml", builtin_manifests(), ids=lambda p: p.name)
def test_same_identity_record(generated, toml):
    m = _manifest(toml)
    module = (generated / f"{m.robot_id}_channels.rs").read_text()
    (length, body), = RS_RECORD.findall(module)
    record = bytes(int(b) for b in re.findall(r"\d+", body))
    assert record == identity.record(m) and int(length) == len(record)
    assert '#[link_section = "roz.manifest"]' in module
    assert "#[cfg(all(target_arch = \"wasm32\", not(roz_no_robot_identity)))]" in module


def _rustc_wasm32():
    """The first rustc on PATH with the wasm32-unknown-unknown core library,
    as cmake/RozRust.cmake probes."""
    for d in os.environ.get("PATH", "").split(os.pathsep):
        exe = Path(d) / "rustc"
        if not exe.is_file():
            continue
        got = subprocess.run([exe, "--print", "target-libdir", "--target",
                              "wasm32-unknown-unknown"], capture_output=True, text=True)
        libdir = Path(got.stdout.strip())
        if got.returncode == 0 and libdir.is_dir() and any(libdir.glob("libcore-*.rlib")):
            return exe
    return None


@pytest.fixture(scope="module")
def rustc():
    exe = _rustc_wasm32()
    if exe is None:
        pytest.skip("no rustc with the wasm32-unknown-unknown target")
    return exe


def _build(rustc, tmp_path, gen, source: str, *flags: str) -> bytes:
    """A controller crate of one file against sdk/rust, as RozRust.cmake builds it."""
    common = ["--edition", "2018", "--target", "wasm32-unknown-unknown", "-C", "opt-level=2",
              "-C", "panic=abort", "-D", "warnings"]
    sdk = tmp_path / "libroz_controller.rlib"
    if not sdk.exists():
        result = subprocess.run([rustc, *common, "--crate-type", "rlib", "--crate-name",
                                 "roz_controller", "-o", sdk,
                                 REPO / "sdk" / "rust" / "src" / "lib.rs"],
                                capture_output=True, text=True)
        assert result.returncode == 0, result.stderr
    (tmp_path / "ctl.rs").write_text(source)
    wasm = tmp_path / "ctl.wasm"
    result = subprocess.run([rustc, *common, "--crate-type", "cdylib", "--crate-name", "ctl",
                             "--extern", f"roz_controller={sdk}",
                             "-C", "link-arg=-zstack-size=16384", "-C", "link-arg=--strip-all",
                             *flags, "-o", wasm, tmp_path / "ctl.rs"],
                            capture_output=True, text=True, env={**os.environ, "OUT_DIR": str(gen)})
    assert result.returncode == 0, result.stderr
    return wasm.read_bytes()


CONTROLLER = """#![no_std]
#![deny(unsafe_code)]
use roz_controller as roz;
include!(concat!(env!("OUT_DIR"), "/ur5_channels.rs"));
use ur5_channels::*;
fn step(tick: i64) {
    roz::command_set(ROZ_UR5_CMD_ELBOW_JOINT_VELOCITY, 0.01 * tick as f64);
}
roz::process!(step);
"""


def test_rust_controller_carries_the_identity(rustc, generated, tmp_path):
    wasm = _build(rustc, tmp_path, generated, CONTROLLER)
    assert _custom_sections(wasm) == [("roz.manifest",
                                       identity.record(_manifest(REPO / "manifests" / "ur5.toml")))]


def test_rust_controller_for_any_robot(rustc, generated, tmp_path):
    wasm = _build(rustc, tmp_path, generated, CONTROLLER, "--cfg", "roz_no_robot_identity")
    assert _custom_sections(wasm) == []


def test_rust_fuel_declaration(rustc, generated, tmp_path):
    """roz_controller::fuel_per_tick! writes what ROZ_FUEL_PER_TICK does."""
    wasm = _build(rustc, tmp_path, generated,
                  CONTROLLER + "roz::fuel_per_tick!(60000);\n", "--cfg", "roz_no_robot_identity")
    assert _custom_sections(wasm) == [("roz.fuel", b"\x01" + (60000).to_bytes(8, "little"))]

