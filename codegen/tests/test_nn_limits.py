# SPDX-License-Identifier: Apache-2.0
"""rozgen's network readers bounded by rules, not by the allocator: each
hostile file is made here, small, and refused before the work it would
cause, with a message naming the file and the limit; never a traceback.
Also: ONNX tensors with external data are never read, and an ONNX graph
is followed along its edges (an operator that changes values is refused
by name, whatever it sits between)."""
import pickle
import struct
import zipfile

import numpy as np
import pytest

from rozgen import nn, nn_export, nn_torch
from test_nn_export import _HEAD, _MODULES, SPEC, _archive, write_pt

CODE_MOD = "__torch__"


def test_stride0_tensor_refused_before_expanding(tmp_path):
    """A one-value storage seen as 20000 x 20000 (stride 0): 1.6 GB if made."""
    ref = nn.random_network(SPEC, 4)
    p = tmp_path / "stride0.pt"
    write_pt(p, ref, tamper=lambda n, s, st: ([20000, 20000], [0, 0]) if n == "bias" else (s, st))
    with pytest.raises(ValueError, match=r"stride0.pt: a tensor of size \(20000, 20000\) and "
                                         r"stride \(0, 0\) has 400000000 values, more than"):
        nn_export.read_torchscript(str(p))


def test_shared_dict_paths_bounded(tmp_path):
    """Thirty dicts, each holding the next twice: 2^30 paths from 1 KB."""
    d: dict = {"w": None}
    for _ in range(30):
        d = {"a": d, "b": d}
    p = _archive(tmp_path, pickle.dumps(d, protocol=2))
    with pytest.raises(ValueError, match="evil.pt: data.pkl: more than 65536 module paths: "
                                         "over the limit"):
        nn_export.read_torchscript(p)
    deep: dict = {}
    for _ in range(100):
        deep = {"a": deep}
    with pytest.raises(ValueError, match="modules nested deeper than 32"):
        nn_export.read_torchscript(_archive(tmp_path, pickle.dumps(deep, protocol=2)))


def test_torch_classes_bounded(tmp_path):
    pkl = (b"\x80\x02" + b"".join(b"c__torch__\nC%d\n0" % i for i in range(3000)) + b"N.")
    with pytest.raises(ValueError, match=r"evil.pt: more than 1024 torch classes: over the "
                                         r"limit of 1024 torch classes"):
        nn_export.read_torchscript(_archive(tmp_path, pkl))


def _fanout(leaf: str, levels: int = 6, calls: int = 10) -> dict:
    """code/ where each module calls the next one's forward ten times."""
    text = ""
    for k in range(levels):
        sub = f"{CODE_MOD}.M{k + 1}" if k + 1 < levels else leaf
        body = "".join(f"    x{i + 1} = (self.m).forward(x{i}, )\n" for i in range(calls))
        text += (_HEAD.format(name=f"M{k}") + f"  m : {sub}\n"
                 f"  def forward(self: {CODE_MOD}.M{k},\n    x0: Tensor) -> Tensor:\n"
                 f"{body}    return x{calls}\n")
    policy = (_HEAD.format(name="Policy") + f"  m : {CODE_MOD}.M0\n"
              f"  def forward(self: {CODE_MOD}.Policy,\n    obs: Tensor) -> Tensor:\n"
              "    return (self.m).forward(obs, )\n")
    return {"__torch__.py": text + policy}


def test_code_fanout_bounded(tmp_path):
    """10^6 calls from a few KB of code: calls counted, layers capped."""
    ref = nn.random_network(SPEC, 4)
    p = tmp_path / "fan.pt"
    write_pt(p, ref, code=_fanout(f"{_MODULES}.linear.Linear"))
    assert p.stat().st_size < 8 << 10
    with pytest.raises(ValueError, match="fan.pt: .*more than 256 layers: over the limit"):
        nn_export.read_torchscript_layers(str(p))
    write_pt(p, ref, code=_fanout(f"{_MODULES}.linear.Identity"))
    with pytest.raises(ValueError, match="fan.pt: .*more than 10000 calls: over the limit"):
        nn_export.read_torchscript_layers(str(p))


def _policy_returning(expr: str) -> dict:
    return {"__torch__.py": _HEAD.format(name="Policy")
            + f"  def forward(self: {CODE_MOD}.Policy,\n    obs: Tensor) -> Tensor:\n"
            + f"    return {expr}\n"}


@pytest.mark.parametrize("expr,why", [
    ("torch.relu(" * 200 + "obs" + ")" * 200, "nested deeper than 64 .expression depth limit"),
    ("self" + ".a" * 500, "nested deeper than 64 .expression depth limit"),
    ("self" + ".a" * 50000, "nested deeper than the parser takes .expression depth limit"),
    ("torch.relu(" * 60000 + "obs" + ")" * 60000, "nested|not TorchScript's code"),
])
def test_deep_expressions_refused_not_recursion(tmp_path, expr, why):
    ref = nn.random_network(SPEC, 4)
    p = tmp_path / "deep.pt"
    write_pt(p, ref, code=_policy_returning(expr))
    with pytest.raises(ValueError, match=why):
        nn_export.read_torchscript_layers(str(p))
    assert nn.main(["pt", "--weights", str(p), "-o", str(tmp_path / "x.h")]) == 2


# ---- .npz ------------------------------------------------------------------------

def _patch_sizes(raw: bytes, size: int) -> bytes:
    """@p raw (a one-member zip) with its member's uncompressed size set to
    @p size in both the local and the central header."""
    b = bytearray(raw)
    loc, cen = b.find(b"PK\x03\x04"), b.find(b"PK\x01\x02")
    struct.pack_into("<I", b, loc + 22, size)
    struct.pack_into("<I", b, cen + 24, size)
    return bytes(b)


def _deflated_npz(path, array_bytes: int, declared: int | None = None):
    """An .npz of one float32 array of @p array_bytes zeros, deflated;
    @p declared: the size its headers claim instead."""
    hdr = {"descr": "<f4", "fortran_order": False, "shape": (array_bytes // 4,)}
    import io
    b = io.BytesIO()
    np.lib.format.write_array_header_1_0(b, hdr)
    body = b.getvalue() + bytes(array_bytes)
    info = zipfile.ZipInfo("l0.weight.npy")
    info.compress_type = zipfile.ZIP_DEFLATED
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as z:
        z.writestr(info, body)
    raw = out.getvalue()
    path.write_bytes(raw if declared is None else _patch_sizes(raw, declared))
    return str(path)


def test_npz_bombs_refused_before_inflating(tmp_path):
    # declared honestly: 2 GiB in the header, refused without inflating a byte
    p = _deflated_npz(tmp_path / "big.npz", 1 << 20, declared=(2 << 30) - 1)
    with pytest.raises(ValueError, match=r"big.npz: 'l0.weight.npy' declares 2147483647 bytes: "
                                         r"over the limit of 67108864 array bytes"):
        nn.read_npz("dense:4:4", p)
    # a lie: declares 4 KiB, inflates to 8 MiB: the inflate stops at 4 KiB + 1
    p = _deflated_npz(tmp_path / "lie.npz", 8 << 20, declared=4096)
    assert (tmp_path / "lie.npz").stat().st_size < 64 << 10
    with pytest.raises(ValueError,
                       match="lie.npz: 'l0.weight.npy' (inflates to more or less|is corrupt)"):
        nn.read_npz("dense:4:4", p)
    # a header whose shape claims more than the bytes stored
    p = _deflated_npz(tmp_path / "shape.npz", 64)
    raw = (tmp_path / "shape.npz").read_bytes()
    with zipfile.ZipFile(tmp_path / "shape.npz") as z:
        body = z.read("l0.weight.npy").replace(b"(16,)", b"(9999999,)".ljust(5))
    with zipfile.ZipFile(tmp_path / "shape.npz", "w") as z:
        z.writestr("l0.weight.npy", body)
    with pytest.raises(ValueError, match="shape.npz: 'l0.weight': shape .* is not the"):
        nn.read_npz("dense:4:4", str(tmp_path / "shape.npz"))
    del raw
    assert nn.main(["npz", "--spec", "dense:4:4", "--weights", p, "-o",
                    str(tmp_path / "x.h")]) == 2


def test_limits_are_named_in_one_table():
    for key in ("tensor bytes", "torch classes", "module paths", "calls", "layers",
                "expression depth"):
        assert key in nn_torch.LIMITS


# ---- ONNX ------------------------------------------------------------------------

onnx = pytest.importorskip("onnx")
from onnx import TensorProto, helper, numpy_helper  # noqa: E402


def _graph(nodes, inits, path, n_in=4):
    g = helper.make_graph(nodes, "g", [helper.make_tensor_value_info("x", TensorProto.FLOAT,
                                                                     [1, n_in])],
                          [helper.make_tensor_value_info("y", TensorProto.FLOAT, None)],
                          [numpy_helper.from_array(np.asarray(a), n) for n, a in inits.items()])
    onnx.save(helper.make_model(g, opset_imports=[helper.make_opsetid("", 17)]), path)
    return str(path)


@pytest.mark.parametrize("location", ["/etc/passwd", "../../../../etc/passwd", "link/passwd",
                                      "passwd"])
def test_onnx_constant_external_data_never_read(tmp_path, location):
    """A Constant whose tensor lives in another file: refused by rule,
    whatever the path (absolute, .., through a symlinked folder)."""
    (tmp_path / "link").symlink_to("/etc")
    (tmp_path / "passwd").write_bytes(np.ones(4, np.float32).tobytes())
    t = numpy_helper.from_array(np.ones(4, np.float32), "c")
    t.ClearField("raw_data")
    t.data_location = TensorProto.EXTERNAL
    t.external_data.add(key="location", value=location)
    w = np.ones((4, 4), np.float32)
    p = _graph([helper.make_node("Constant", [], ["b"], value=t),
                helper.make_node("Gemm", ["x", "w", "b"], ["y"], transB=1)],
               {"w": w}, tmp_path / "ext.onnx")
    with pytest.raises(ValueError, match=r"ext.onnx: Constant '' attribute value has external "
                                         r"data .*refused, never read"):
        nn_export.read_policy(p)
    with pytest.raises(ValueError, match="external data"):
        nn_export.read_onnx(p)


def _ref(path, x):
    from onnx.reference import ReferenceEvaluator
    return ReferenceEvaluator(path).run(None, {"x": x})[0]


def test_onnx_value_changing_operators_refused(tmp_path):
    """MatMul + Add -> Gather(permutation) -> Relu -> MatMul: onnx.reference
    says the Gather matters; the reader refuses it by name rather than
    skip it (and so for Cast, Concat, Slice, Transpose on the data)."""
    rng = np.random.default_rng(5)
    w1, b1, w2 = (rng.normal(size=s).astype(np.float32) for s in ((4, 6), (6,), (6, 3)))
    perm = np.array([5, 4, 3, 2, 1, 0], np.int64)
    inits = {"w1": w1, "b1": b1, "w2": w2, "perm": perm}
    p = _graph([helper.make_node("MatMul", ["x", "w1"], ["m"]),
                helper.make_node("Add", ["m", "b1"], ["a"]),
                helper.make_node("Gather", ["a", "perm"], ["g"], axis=1),
                helper.make_node("Relu", ["g"], ["r"]),
                helper.make_node("MatMul", ["r", "w2"], ["y"])], inits, tmp_path / "gather.onnx")
    x = rng.normal(size=(1, 4)).astype(np.float32)
    skipped = np.maximum(x @ w1 + b1, 0) @ w2  # what skipping the Gather would compute
    assert np.abs(_ref(p, x) - skipped).max() > 1e-2
    with pytest.raises(ValueError, match=r"gather.onnx: Gather '': operator Gather is not one "
                                         r"roz_nn.h runs"):
        nn_export.read_policy(p)
    for op, extra, kw in (("Cast", [], {"to": TensorProto.FLOAT16}),
                          ("Transpose", [], {"perm": [1, 0]}),  # on a 2 x 3 view below
                          ("Concat", ["a"], {"axis": 1}),
                          ("Slice", ["st", "en", "ax1"], {})):
        view = op == "Transpose"  # a real transpose: of a 2 x 3 view, back to 1 x 6
        q = _graph([helper.make_node("MatMul", ["x", "w1"], ["m"]),
                    helper.make_node("Add", ["m", "b1"], ["a0"]),
                    helper.make_node("Reshape", ["a0", "s23" if view else "s16"], ["a"]),
                    helper.make_node(op, ["a"] + extra, ["g0"], **kw),
                    helper.make_node("Reshape", ["g0", "s16"], ["g"]),
                    helper.make_node("MatMul", ["g", "w2"], ["y"])],
                   {**inits, "st": np.array([0], np.int64), "en": np.array([3], np.int64),
                    "ax1": np.array([1], np.int64),
                    "s23": np.array([2, 3], np.int64), "s16": np.array([1, 6], np.int64)},
                   tmp_path / f"{op}.onnx")
        with pytest.raises(ValueError, match=f"{op} '': (operator {op} is not one|the data)"):
            nn_export.read_onnx(q)
    # a Transpose or a Slice that keeps every value where it was is no operator at all
    for op, extra, kw in (("Transpose", [], {"perm": [1, 0]}), ("Slice", ["st", "en6"], {})):
        q = _graph([helper.make_node("MatMul", ["x", "w1"], ["m"]),
                    helper.make_node("Add", ["m", "b1"], ["a"]),
                    helper.make_node(op, ["a"] + extra, ["g0"], **kw),
                    helper.make_node("Reshape", ["g0", "s16"], ["g"]),
                    helper.make_node("MatMul", ["g", "w2"], ["y"])],
                   {**inits, "st": np.array([0, 0], np.int64), "en6": np.array([1, 6], np.int64),
                    "s16": np.array([1, 6], np.int64)}, tmp_path / f"keep_{op}.onnx")
        layers = nn_export.read_onnx(q)
        assert np.allclose(nn.forward(layers, x), _ref(q, x), rtol=1e-5, atol=1e-6)


def test_onnx_graph_followed_not_listed(tmp_path):
    """Shape arithmetic beside the data path is allowed (torch's flatten),
    and the result equals onnx.reference; a branch (two layers on one
    input) and an output that is not the last layer's are refused."""
    rng = np.random.default_rng(6)
    w1, b1, w2, b2 = (rng.normal(size=s).astype(np.float32) for s in
                      ((6, 4), (6,), (3, 6), (3,)))
    inits = {"w1": w1, "b1": b1, "w2": w2, "b2": b2, "zero": np.array([0], np.int64),
             "m1": np.array([-1], np.int64)}
    p = _graph([helper.make_node("Gemm", ["x", "w1", "b1"], ["h"], transB=1),
                helper.make_node("Tanh", ["h"], ["t"]),
                helper.make_node("Shape", ["t"], ["s"]),
                helper.make_node("Gather", ["s", "zero"], ["n"], axis=0),
                helper.make_node("Concat", ["n", "m1"], ["shape"], axis=0),
                helper.make_node("Reshape", ["t", "shape"], ["f"]),
                helper.make_node("Gemm", ["f", "w2", "b2"], ["y"], transB=1)],
               inits, tmp_path / "flat.onnx")
    layers = nn_export.read_onnx(p)
    assert [(l.kind, l.act) for l in layers] == [("dense", "tanh"), ("dense", "linear")]
    x = rng.normal(size=(1, 4)).astype(np.float32)
    assert np.allclose(nn.forward(layers, x), _ref(p, x), rtol=1e-5, atol=1e-6)
    branch = _graph([helper.make_node("Gemm", ["x", "w1", "b1"], ["h"], transB=1),
                     helper.make_node("Gemm", ["x", "w1", "b1"], ["y"], transB=1)],
                    inits, tmp_path / "branch.onnx")
    with pytest.raises(ValueError, match="an earlier value: roz_nn.h runs a straight line"):
        nn_export.read_onnx(branch)
    early = _graph([helper.make_node("Gemm", ["x", "w1", "b1"], ["y"], transB=1),
                    helper.make_node("Tanh", ["y"], ["t"])], inits, tmp_path / "early.onnx")
    with pytest.raises(ValueError, match="output 'y' is not the last layer's output"):
        nn_export.read_onnx(early)


def test_onnx_counts_bounded(tmp_path):
    w = np.ones((4, 4), np.float32)
    nodes = [helper.make_node("Identity", ["x" if i == 0 else f"i{i}"], [f"i{i + 1}"])
             for i in range(5000)]
    nodes.append(helper.make_node("Gemm", ["i5000", "w"], ["y"], transB=1))
    p = _graph(nodes, {"w": w}, tmp_path / "many.onnx")
    with pytest.raises(ValueError, match="many.onnx: 5001 nodes: over the limit of 4096 nodes"):
        nn_export.read_onnx(p)
    (tmp_path / "junk.onnx").write_bytes(b"\x0a\xff\xff\xff\xff\x0f")
    with pytest.raises(ValueError, match="junk.onnx: not an ONNX model"):
        nn_export.read_onnx(str(tmp_path / "junk.onnx"))


@pytest.mark.parametrize("name", ["lstm_exporter.pt", "mlp_state.pt", "gru.onnx", "mlp.onnx"])
def test_mutated_files_refused_cleanly(tmp_path, name):
    """Files torch wrote, with bytes flipped at random: each read either
    succeeds or ends in a ValueError naming the file, never another
    exception."""
    from conftest import DATA
    raw = (DATA / "nn" / name).read_bytes()
    rng = np.random.default_rng(11)
    p = tmp_path / name
    spec = "dense:7:16:elu,dense:16:8:relu,dense:8:4" if name == "mlp_state.pt" else None
    for _ in range(60):
        b = bytearray(raw)
        for at in rng.integers(0, len(b), size=int(rng.integers(1, 8))):
            b[at] = int(rng.integers(0, 256))
        p.write_bytes(bytes(b))
        try:
            nn_export.read_policy(str(p), spec)
        except ValueError as e:
            assert str(p) in str(e)
