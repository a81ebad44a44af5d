# SPDX-License-Identifier: Apache-2.0
"""rozgen.nn_export on files that real torch and onnx wrote
(data/nn/make_torch_files.py, which says which versions): the numpy
reference against torch's own outputs over several steps (the recurrent
state carried), every ONNX file against onnx.reference, the metadata
Isaac Lab and mjlab write, and the C header compiled natively against
both. Nothing here imports torch."""
import hashlib
import os
import shutil
import subprocess

import numpy as np
import pytest

from conftest import DATA, REPO
from rozgen import nn, nn_export

NN = DATA / "nn"
SDK = REPO / "sdk" / "include"
MATH = REPO / "lib" / "math"  # roz_math.h, the core's, which the SDK gives controllers
MLP_SPEC = "dense:7:16:elu,dense:16:8:relu,dense:8:4"
# the layers of each network torch wrote, by its reference's name
LAYERS = {
    "lstm_exporter": [("lstm", 6, 12, "linear"), ("dense", 12, 8, "elu"), ("dense", 8, 4, "linear")],
    "gru_exporter": [("gru", 5, 10, "linear"), ("dense", 10, 8, "tanh"), ("dense", 8, 3, "linear")],
    "mlp": [("dense", 7, 16, "elu"), ("dense", 16, 8, "relu"), ("dense", 8, 4, "linear")],
}
# file, its torch reference (<name>.io.npz), spec, the layers it holds
FILES = [(name, io, spec, LAYERS[io]) for name, io, spec in [
    ("lstm_exporter.pt", "lstm_exporter", None),
    ("gru_exporter.pt", "gru_exporter", None),
    ("mlp.pt", "mlp", None),
    ("mlp_state.pt", "mlp", MLP_SPEC),
    ("lstm_exporter.pt", "lstm_exporter", "lstm:6:12,dense:12:8:elu,dense:8:4"),
    ("mlp.onnx", "mlp", None),
    ("lstm.onnx", "lstm_exporter", None),
    ("gru.onnx", "gru_exporter", None),
    ("lstm_dynamo.onnx", "lstm_exporter", None),
    ("gru_dynamo.onnx", "gru_exporter", None),
]]
IDS = [f"{f}{'+spec' if s else ''}" for f, _, s, _ in FILES]


@pytest.mark.parametrize("name,io,spec,shape", FILES, ids=IDS)
def test_matches_torch(name, io, spec, shape):
    """rozgen's numpy forward pass equals torch's within float32 rounding,
    step by step from a zero state."""
    p = nn_export.read_policy(str(NN / name), spec)
    assert [(l.kind, l.n_in, l.n_out, l.act) for l in p.layers] == shape
    assert p.source_sha256 == hashlib.sha256((NN / name).read_bytes()).hexdigest()
    ref = np.load(NN / f"{io}.io.npz")
    got = nn.forward(p.layers, ref["x"])
    assert np.allclose(got, ref["y"], rtol=1e-5, atol=2e-6), np.abs(got - ref["y"]).max()


def test_state_dict_needs_a_spec():
    with pytest.raises(ValueError, match="mlp_state.pt: no code/ folder .* --spec"):
        nn_export.read_policy(str(NN / "mlp_state.pt"))
    with pytest.raises(ValueError, match="expected a 'weight_ih_l0'"):
        nn_export.read_policy(str(NN / "mlp_state.pt"), "lstm:7:16," + MLP_SPEC)


def test_dispatch_on_content_not_suffix(tmp_path):
    for src, dst in (("mlp.onnx", "policy.pt"), ("mlp.pt", "policy.onnx")):
        shutil.copy(NN / src, tmp_path / dst)
        got = nn_export.read_policy(str(tmp_path / dst))
        assert [l.n_out for l in got.layers] == [16, 8, 4]
    (tmp_path / "bare.pt").write_bytes(b"\x80\x02}q\x00.")
    with pytest.raises(ValueError, match="bare.pt: a bare pickle"):
        nn_export.read_policy(str(tmp_path / "bare.pt"))
    (tmp_path / "junk.onnx").write_bytes(b"\x08\x07\xff\xff\xff")
    with pytest.raises(ValueError, match="junk.onnx: not an ONNX model"):
        nn_export.read_policy(str(tmp_path / "junk.onnx"))


def test_onnx_metadata():
    """mjlab's attach_metadata_to_onnx keys and comma-separated values,
    normalised."""
    m = nn_export.read_policy(str(NN / "lstm.onnx")).metadata
    assert m == {"joint_names": ["left_hip_pitch_joint", "left_knee_joint",
                                 "right_hip_pitch_joint", "right_knee_joint"],
                 "default_joint_pos": [-0.1, 0.3, -0.1, 0.3],
                 "stiffness": [100.0, 150.0, 100.0, 150.0], "damping": [2.0, 4.0, 2.0, 4.0],
                 "action_scale": 0.25, "observation_names": ["base_ang_vel", "projected_gravity"],
                 "observation_scales": [0.25, 1.0]}
    assert nn_export.read_policy(str(NN / "mlp.pt")).metadata == {}


def test_metadata_refusals():
    norm = nn_export.normalise_metadata
    assert norm({"joint_names": '["a", "b"]', "action_scale": "[0.5, 0.25]",
                 "observation_scales": '{"a": 2}'}, "f") == {
        "joint_names": ["a", "b"], "action_scale": [0.5, 0.25], "observation_scales": {"a": 2.0}}
    for props, why in (({"joint_names": "a,b", "joint_stiffness": "1,2,3"}, "stiffness: 3 values"),
                       ({"action_scale": "x"}, "'x' is not a number"),
                       ({"joint_damping": "1,nan"}, "not finite"),
                       ({"kps": "1", "joint_stiffness": "1"}, "stiffness twice"),
                       ({"joint_names": "[1, 2]"}, "not a list of names"),
                       ({"joint_names": "[[[" * 5}, "neither JSON")):
        with pytest.raises(ValueError, match=why):
            norm(props, "f.onnx")


onnx = pytest.importorskip("onnx")


@pytest.mark.parametrize("name,io", [("mlp.onnx", "mlp"), ("gru.onnx", "gru_exporter"),
                                     ("lstm.onnx", "lstm_exporter"),
                                     ("gru_dynamo.onnx", "gru_exporter"),
                                     ("lstm_dynamo.onnx", "lstm_exporter")])
def test_onnx_files_against_onnx_reference(name, io):
    """Every ONNX file torch exported: onnx.reference's outputs (the state
    carried through h_in -> h_out) equal rozgen's numpy forward pass. An
    LSTM's c_out is not in onnx.reference, so lstm.onnx is checked on its
    first step there (and on every step against torch above)."""
    from test_nn_export import run_reference
    ref = np.load(NN / f"{io}.io.npz")
    layers = nn_export.read_policy(str(NN / name)).layers
    if name.startswith("lstm"):
        from onnx.reference import ReferenceEvaluator
        x = ref["x"][:1]
        z = np.zeros((1, 1, 12), np.float32)
        want = ReferenceEvaluator(str(NN / name)).run(["actions"], {"obs": x, "h_in": z,
                                                                    "c_in": z})[0]
    else:
        x = ref["x"]
        want = run_reference(NN / name, x)
    assert np.allclose(nn.forward(layers, x), want, rtol=1e-5, atol=2e-6)


def _cc():
    return next((c for c in ("cc", "gcc", "clang") if shutil.which(c)), None)


_MAIN = """#include <stdio.h>
#include "net_net.h"
int main(void)
{
    static const float xs[%(steps)d][%(n_in)d] = { %(xs)s };
    float y[%(n_out)d];
    net_reset();
    for (int t = 0; t < %(steps)d; t++) {
        if (net_forward(xs[t], y) != 0)
            return 1;
        for (int i = 0; i < %(n_out)d; i++)
            printf("%%a\\n", (double)y[i]);
    }
    return 0;
}
"""


@pytest.mark.skipif(_cc() is None, reason="no C compiler")
@pytest.mark.parametrize("name,io,spec,shape", FILES[:3], ids=IDS[:3])
def test_native_header_matches(tmp_path, name, io, spec, shape):
    """The header rozgen writes from a torch-written file, compiled
    natively (roz_nn.h's plain C loops, the bits the wasm build gives:
    test/nn), equals the numpy reference within 2^-14 of max(1, |y|) and
    torch within float32 rounding; built twice (-O0, -O2), the same bits."""
    layers = nn_export.read_policy(str(NN / name), spec).layers
    (tmp_path / "net_net.h").write_text(nn.header(layers, "net", name))
    ref = np.load(NN / f"{io}.io.npz")
    x = ref["x"]
    (tmp_path / "main.c").write_text(_MAIN % {
        "steps": len(x), "n_in": x.shape[1], "n_out": layers[-1].n_out,
        "xs": ", ".join("{" + ", ".join(float(v).hex() + "f" for v in row) + "}" for row in x)})
    outs = []
    for opt in ("-O0", "-O2"):
        exe = tmp_path / f"net{opt}"
        subprocess.run([_cc(), "-std=c11", opt, "-ffp-contract=off", "-I", str(SDK), "-I", str(MATH), "-I",
                        str(tmp_path), str(tmp_path / "main.c"), "-o", str(exe), "-lm"],
                       check=True)
        run = subprocess.run([str(exe)], capture_output=True, text=True, check=True)
        outs.append(run.stdout)
    assert outs[0] == outs[1]
    got = np.array([float.fromhex(v) for v in outs[0].split()]).reshape(len(x), -1)
    want = nn.forward(layers, x)
    assert np.all(np.abs(got - want) <= np.ldexp(np.maximum(1.0, np.abs(want)), -14))
    assert np.allclose(got, ref["y"], rtol=1e-5, atol=2e-6)


def test_script_header_names_the_versions():
    text = (NN / "make_torch_files.py").read_text()
    assert "torch 2.15.0" in text and "onnx 1.19.1" in text
    for f, *_ in FILES:
        assert os.path.getsize(NN / f) < 32 << 10  # small files only
