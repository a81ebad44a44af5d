# SPDX-License-Identifier: Apache-2.0
"""rozgen.nn_export on networks made here: TorchScript-style archives
written without torch (the pickle torch.jit.save writes: __torch__ module
objects, tensors through torch._utils._rebuild_tensor_v2 and persistent
storages) and ONNX graphs built with onnx.helper; each read back against
the arrays it was made from, or run against ONNX's own equations; hostile
files refused, never run."""
import collections
import io
import os
import pickle
import sys
import types
import zipfile

import numpy as np
import pytest

from rozgen import nn, nn_export

SPEC = "lstm:5:4,dense:4:3:elu,dense:3:2"


# ---- writing a TorchScript-style archive without torch ---------------------------

class _Fake:
    """Modules for the pickler to name: torch, torch._utils, __torch__..."""

    def __enter__(self):
        self.mods = {}
        for name in ("torch", "torch._utils", "__torch__", "__torch__.torch.nn.modules.rnn",
                     "__torch__.torch.nn.modules.linear",
                     "__torch__.torch.nn.modules.container"):
            self.mods[name] = sys.modules.get(name)
            sys.modules[name] = types.ModuleType(name)

        def _rebuild_tensor_v2(*a):
            raise AssertionError("never called while writing")
        _rebuild_tensor_v2.__module__ = "torch._utils"
        _rebuild_tensor_v2.__qualname__ = "_rebuild_tensor_v2"
        sys.modules["torch._utils"]._rebuild_tensor_v2 = _rebuild_tensor_v2
        self.rebuild = _rebuild_tensor_v2
        self.FloatStorage = type("FloatStorage", (), {"__module__": "torch"})
        sys.modules["torch"].FloatStorage = self.FloatStorage

        def cls(mod, name):
            c = type(name, (), {"__module__": mod})
            setattr(sys.modules[mod], name, c)
            return c
        self.Policy = cls("__torch__", "Policy")
        self.LSTM = cls("__torch__.torch.nn.modules.rnn", "LSTM")
        self.Linear = cls("__torch__.torch.nn.modules.linear", "Linear")
        self.Sequential = cls("__torch__.torch.nn.modules.container", "Sequential")
        return self

    def __exit__(self, *exc):
        for name, m in self.mods.items():
            if m is None:
                sys.modules.pop(name, None)
            else:
                sys.modules[name] = m


class _Storage:
    def __init__(self, key, array):
        self.key, self.array = key, array


def write_pt(path, ref, *, tamper=None, key=str, code=None):
    """A TorchScript-style archive of the random network `ref` (SPEC);
    tamper(name, shape, stride, numel) may lie about a tensor; code: the
    files of its code/ folder ({'__torch__.py': text}), none by default."""
    storages = []
    with _Fake() as f:
        class Tensor:
            def __init__(self, name, a):
                self.name, self.a = name, np.ascontiguousarray(a, dtype=np.float32)

            def __reduce__(self):
                st = _Storage(key(len(storages)), self.a.ravel())
                storages.append(st)
                shape, stride = list(self.a.shape), [int(s // 4) for s in self.a.strides]
                if tamper:
                    shape, stride = tamper(self.name, shape, stride)
                return (f.rebuild, (st, 0, tuple(shape), tuple(stride), False,
                                    collections.OrderedDict()))

        class P(pickle.Pickler):
            def persistent_id(self, obj):
                if isinstance(obj, _Storage):
                    return ("storage", f.FloatStorage, obj.key, "cpu", obj.array.size)
                return None

        pol, mem, seq = f.Policy(), f.LSTM(), f.Sequential()
        if code:  # the state buffers of legged_gym's exporter (its code names them)
            pol.hidden_state = Tensor("hidden_state", np.zeros((1, 1, 4), np.float32))
            pol.cell_state = Tensor("cell_state", np.zeros((1, 1, 4), np.float32))
        for ours, theirs in (("w_ih", "weight_ih_l0"), ("w_hh", "weight_hh_l0"),
                             ("b_ih", "bias_ih_l0"), ("b_hh", "bias_hh_l0")):
            setattr(mem, theirs, Tensor(theirs, ref[0].arrays[ours]))
        mem.hidden_size = 4
        for k, idx in ((1, "0"), (2, "2")):
            lin = f.Linear()
            lin.weight = Tensor("weight", ref[k].arrays["w"])
            lin.bias = Tensor("bias", ref[k].arrays["b"])
            setattr(seq, idx, lin)
        pol.memory, pol.actor, pol.training = mem, seq, False
        buf = io.BytesIO()
        P(buf, protocol=2).dump(pol)
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("policy/data.pkl", buf.getvalue())
        z.writestr("policy/version", "3\n")
        for i, st in enumerate(storages):  # files by index; key() may lie in the pickle
            z.writestr(f"policy/data/{i}", st.array.astype("<f4").tobytes())
        for name, text in (code or {}).items():
            z.writestr(f"policy/code/{name}", text)


def test_torchscript_round_trip(tmp_path):
    ref = nn.random_network(SPEC, 4)
    p = tmp_path / "policy.pt"
    write_pt(p, ref)
    t = nn_export.read_torchscript(str(p))
    assert list(t)[:2] == ["memory.weight_ih_l0", "memory.weight_hh_l0"]
    assert "actor.2.bias" in t
    got = nn_export.layers_from_tensors(t, SPEC, str(p))
    assert nn.header(got, "p", "x") == nn.header(ref, "p", "x")
    out = tmp_path / "policy_net.h"
    assert nn.main(["pt", "--spec", SPEC, "--weights", str(p), "-o", str(out)]) == 0
    assert "ROZ_NN_LSTM_DEFINE(policy_l0, 5, 4" in out.read_text()


def _archive(tmp_path, pkl: bytes, files=None):
    p = tmp_path / "evil.pt"
    with zipfile.ZipFile(p, "w") as z:
        z.writestr("evil/data.pkl", pkl)
        for n, b in (files or {}).items():
            z.writestr(f"evil/data/{n}", b)
    return str(p)


def test_torchscript_hostile(tmp_path):
    marker = tmp_path / "ran"
    for pkl in (b"cos\nsystem\n(S'touch " + str(marker).encode() + b"'\ntR.",
                b"cbuiltins\neval\n(S'1+1'\ntR.",
                b"\x80\x04\x95\x10\x00\x00\x00\x00\x00\x00\x00\x8c\x02os\x8c\x06getpid\x93)R.",
                b"csubprocess\nPopen\n(S'true'\ntR."):
        with pytest.raises(ValueError, match="refused"):
            nn_export.read_torchscript(_archive(tmp_path, pkl))
    assert not marker.exists()
    (tmp_path / "nope.pt").write_bytes(b"PK junk")
    with pytest.raises(ValueError, match="not a zip"):
        nn_export.read_torchscript(str(tmp_path / "nope.pt"))
    with pytest.raises(ValueError, match="malformed data.pkl"):
        nn_export.read_torchscript(_archive(tmp_path, b"\x80\x02}q\x00(X"))
    # a storage that is not there, or outside the archive's folder
    ref = nn.random_network(SPEC, 4)
    for key in (lambda i: f"{i}x" if i == 3 else str(i), lambda i: "../../etc/passwd"):
        write_pt(tmp_path / "k.pt", ref, key=key)
        with pytest.raises(ValueError, match="no storage"):
            nn_export.read_torchscript(str(tmp_path / "k.pt"))


def test_torchscript_lying_shapes(tmp_path):
    ref = nn.random_network(SPEC, 4)
    p = tmp_path / "lie.pt"
    write_pt(p, ref, tamper=lambda n, s, st: ([1000, 1000], st) if n == "weight" else (s, st))
    with pytest.raises(ValueError, match="more than its storage's 12"):
        nn_export.read_torchscript(str(p))
    write_pt(p, ref, tamper=lambda n, s, st: ([2, 2], [5, 9]) if n == "weight" else (s, st))
    with pytest.raises(ValueError, match="reaches past its storage"):
        nn_export.read_torchscript(str(p))
    write_pt(p, ref, tamper=lambda n, s, st: (s, [0 - 1] + st[1:]) if n == "bias_ih_l0" else (s, st))
    with pytest.raises(ValueError, match="a tensor of size"):
        nn_export.read_torchscript(str(p))
    # a storage shorter than the pickle claims
    write_pt(p, ref)
    q = tmp_path / "short.pt"
    with zipfile.ZipFile(p) as zi, zipfile.ZipFile(q, "w") as zo:
        for n in zi.namelist():
            b = zi.read(n)
            zo.writestr(n, b[:-4] if n.endswith("/data/0") else b)
    with pytest.raises(ValueError, match="the pickle says"):
        nn_export.read_torchscript(str(q))


def test_torchscript_unmappable(tmp_path):
    ref = nn.random_network(SPEC, 4)
    p = tmp_path / "policy.pt"
    write_pt(p, ref)
    t = nn_export.read_torchscript(str(p))
    with pytest.raises(ValueError, match="expected a 'weight_ih_l0'"):
        nn_export.layers_from_tensors(t, "gru:5:4," + SPEC, str(p))
    with pytest.raises(ValueError, match="no place for"):
        nn_export.layers_from_tensors(t, "lstm:5:4,dense:4:3:elu", str(p))
    t2 = dict(t)
    t2["memory.weight_ih_l1"] = t2.pop("actor.2.bias")
    with pytest.raises(ValueError):
        nn_export.layers_from_tensors(t2, SPEC, str(p))


# ---- the activations from the archive's code/ folder ------------------------------
# The serialized forward as torch.jit.save writes it (Python syntax: classes
# per module, submodules as annotations, forward unrolled), written here.

_HEAD = """class {name}(Module):
  __parameters__ = []
  __buffers__ = []
  training : bool
  _is_full_backward_hook : Optional[bool]
"""
_MODULES = "__torch__.torch.nn.modules"
_POLICY = _HEAD.format(name="Policy").replace(
    "__buffers__ = []", '__buffers__ = ["hidden_state", "cell_state", ]') + f"""\
  hidden_state : Tensor
  cell_state : Tensor
  memory : {_MODULES}.rnn.LSTM
  actor : {_MODULES}.container.Sequential
  def forward(self: __torch__.Policy,
    obs: Tensor) -> Tensor:
    memory = self.memory
    hidden_state = self.hidden_state
    cell_state = self.cell_state
    _0 = (memory).forward__0(torch.unsqueeze(obs, 0), (hidden_state, cell_state), )
    out, _1, = _0
    h, c, = _1
    _2 = torch.copy_(torch.slice(self.hidden_state), h)
    _3 = torch.copy_(torch.slice(self.cell_state), c)
    actor = self.actor
    return (actor).forward(torch.squeeze(out, 0), )
"""


def _sequential(act_class):
    return {"__torch__/torch/nn/modules/container.py": _HEAD.format(name="Sequential") + f"""\
  __annotations__["0"] = {_MODULES}.linear.Linear
  __annotations__["1"] = {_MODULES}.activation.{act_class}
  __annotations__["2"] = {_MODULES}.linear.Linear
  def forward(self: {_MODULES}.container.Sequential,
    input: Tensor) -> Tensor:
    _0 = getattr(self, "0")
    _1 = getattr(self, "1")
    _2 = getattr(self, "2")
    input0 = (_0).forward(input, )
    input1 = (_1).forward(input0, )
    return (_2).forward(input1, )
"""}


_ELU = {"__torch__/torch/nn/modules/activation.py": _HEAD.format(name="ELU") + f"""\
  alpha : Final[float] = {{alpha}}
  inplace : Final[bool] = False
  def forward(self: {_MODULES}.activation.ELU,
    input: Tensor) -> Tensor:
    return torch.elu(input, {{alpha}}, 1, 1)
"""}


def _code(policy=_POLICY, act_class="ELU", alpha="1."):
    code = {"__torch__.py": policy}
    code.update(_sequential(act_class))
    code.update({k: v.format(alpha=alpha) for k, v in _ELU.items()})
    return code


def test_torchscript_layers_from_code(tmp_path):
    ref = nn.random_network(SPEC, 4)  # lstm:5:4, dense:4:3:elu, dense:3:2
    p = tmp_path / "policy.pt"
    write_pt(p, ref, code=_code())
    got = nn_export.read_torchscript_layers(str(p))
    assert [(l.kind, l.n_in, l.n_out, l.act) for l in got] == \
        [("lstm", 5, 4, "linear"), ("dense", 4, 3, "elu"), ("dense", 3, 2, "linear")]
    assert nn.header(got, "p", "x") == nn.header(ref, "p", "x")
    out = tmp_path / "policy_net.h"
    assert nn.main(["pt", "--weights", str(p), "-o", str(out)]) == 0  # no --spec
    assert "ROZ_NN_ELU" in out.read_text() and "(its code/)" in out.read_text()
    # an activation module of another kind, and one written as an operator
    write_pt(p, ref, code=_code(act_class="Tanh"))
    assert [l.act for l in nn_export.read_torchscript_layers(str(p))] == \
        ["linear", "tanh", "linear"]
    functional = _POLICY.replace(
        "return (actor).forward(torch.squeeze(out, 0), )",
        '_2 = getattr(actor, "0")\n    h = torch.sigmoid((_2).forward(out, ))\n'
        '    return (getattr(actor, "2")).forward(h, )')
    write_pt(p, ref, code=_code(policy=functional))
    assert [l.act for l in nn_export.read_torchscript_layers(str(p))] == \
        ["linear", "sigmoid", "linear"]
    method = functional.replace("h = torch.sigmoid((_2).forward(out, ))",
                                "h = torch.relu((_2).forward(out, )).view([-1])")
    write_pt(p, ref, code=_code(policy=method))
    assert [l.act for l in nn_export.read_torchscript_layers(str(p))] == \
        ["linear", "relu", "linear"]


def test_torchscript_code_refusals(tmp_path):
    ref = nn.random_network(SPEC, 4)
    p = tmp_path / "policy.pt"

    def refused(code, match):
        write_pt(p, ref, code=code)
        with pytest.raises(ValueError, match=match):
            nn_export.read_torchscript_layers(str(p))
        assert nn.main(["pt", "--weights", str(p), "-o", str(tmp_path / "x.h")]) == 2

    refused(None, "no code/ folder .* give the layers with --spec")
    # the policy's last line, made what roz_nn.h does not run
    last = "return (actor).forward(torch.squeeze(out, 0), )"
    for ending, match in [
            ("return torch.softmax((actor).forward(out, ), -1)",
             r"code/__torch__.py: Policy.forward: operator torch.softmax is not one roz_nn.h runs"),
            ("return torch.add((actor).forward(out, ), 1)", "operator torch.add is not one"),
            ("return (actor).forward(out, ) * 2.", "operator Mult"),
            ("return torch.tanh(torch.relu((actor).forward(out, )))",
             "activation tanh .* after relu: one activation per layer")]:
        refused(_code(policy=_POLICY.replace(last, ending)), match)
    branch = _POLICY.replace("    actor = self.actor\n",
                             "    actor = self.actor\n    if self.training:\n      pass\n")
    refused(_code(policy=branch), "a If statement")
    refused(_code(alpha="0.5"), "ELU alpha 0.5")
    refused(_code(act_class="GELU"), "a torch.nn.modules.activation.GELU, whose forward is not in")
    first = _POLICY.replace("(memory).forward__0(torch.unsqueeze(obs, 0),",
                            "(memory).forward__0(torch.tanh(obs),")
    refused(_code(policy=first), "activation tanh .* follows no dense layer")
    # a layer the forward never calls leaves its tensors over
    skip = _sequential("ELU")["__torch__/torch/nn/modules/container.py"].replace(
        "return (_2).forward(input1, )", "return input1")
    code = _code()
    code["__torch__/torch/nn/modules/container.py"] = skip
    refused(code, "tensors the forward has no place for: actor.2.weight")
    refused(_code(policy="class Policy(Module):\n  def forward(self x):\n"),
            "not TorchScript's code")
    # nothing in code/ runs: a call that would, if executed, is only a name here
    marker = tmp_path / "ran"
    evil = _POLICY.replace("memory = self.memory",
                           f"__import__('os').system('touch {marker}')\n    memory = self.memory")
    refused(_code(policy=evil), "operator __import__.* is not one roz_nn.h runs")
    assert not marker.exists()


# ---- ONNX -----------------------------------------------------------------------

onnx = pytest.importorskip("onnx")
from onnx import TensorProto, helper, numpy_helper  # noqa: E402


def _model(nodes, inits, path):
    g = helper.make_graph(nodes, "g", [helper.make_tensor_value_info("x", TensorProto.FLOAT, None)],
                          [helper.make_tensor_value_info("y", TensorProto.FLOAT, None)],
                          [numpy_helper.from_array(np.asarray(a, dtype=np.float32), n)
                           for n, a in inits.items()])
    onnx.save(helper.make_model(g), path)
    return str(path)


def _sig(v):
    return 1.0 / (1.0 + np.exp(-v))


def test_onnx_mlp(tmp_path):
    rng = np.random.default_rng(1)
    w1, b1, w2, b2 = (rng.normal(size=s).astype(np.float32) for s in ((6, 4), (6,), (3, 6), (3,)))
    p = _model([helper.make_node("Gemm", ["x", "w1", "b1"], ["h"], transB=1),
                helper.make_node("Elu", ["h"], ["e"]),
                helper.make_node("MatMul", ["e", "w2t"], ["m"]),
                helper.make_node("Add", ["m", "b2"], ["t"]),
                helper.make_node("Tanh", ["t"], ["y"])],
               {"w1": w1, "b1": b1, "w2t": w2.T, "b2": b2}, tmp_path / "mlp.onnx")
    layers = nn_export.read_onnx(p)
    x = rng.normal(size=(3, 4)).astype(np.float32)
    h = x.astype(np.float64) @ w1.T.astype(np.float64) + b1
    want = np.tanh(np.where(h > 0, h, np.expm1(np.minimum(h, 0))) @ w2.T.astype(np.float64) + b2)
    assert np.allclose(nn.forward(layers, x), want, rtol=1e-6, atol=1e-9)


def run_reference(path, xs):
    """onnx.reference's outputs over the steps @p xs, the recurrent state
    (inputs after the first, zero at the start) carried from each step's
    state outputs (the outputs after the first) to the next step."""
    from onnx.reference import ReferenceEvaluator
    m = onnx.load(str(path))
    ev = ReferenceEvaluator(m)
    init = {t.name for t in m.graph.initializer}
    names = [i.name for i in m.graph.input if i.name not in init]
    state = {}
    for i in m.graph.input:
        if i.name in names[1:]:
            shape = [d.dim_value for d in i.type.tensor_type.shape.dim]
            state[i.name] = np.zeros(shape, np.float32)
    out = []
    for x in xs:
        feeds = {names[0]: x.reshape(1, -1).astype(np.float32), **state}
        got = ev.run(None, feeds)
        out.append(np.asarray(got[0]).reshape(-1))
        state = dict(zip(names[1:], got[1:]))
    return np.array(out)


def _rnn_model(op, I, H, rng, path, carried):
    """An LSTM or GRU graph: @p carried, one step per call, the state
    through h_in/c_in -> h_out/c_out (Isaac Lab's export); else a whole
    sequence per call (x: steps x 1 x I), from a zero state."""
    g_n = 4 if op == "LSTM" else 3
    W, R, B = (rng.normal(size=(1, g_n * H, I)), rng.normal(size=(1, g_n * H, H)),
               rng.normal(size=(1, 2 * g_n * H)))
    st = (["h_in"] + (["c_in"] if op == "LSTM" else [])) if carried else []
    ins = ["xs" if carried else "x", "W", "R", "B", "", *st]
    outs = ["Y"] + ((["h_out"] + (["c_out"] if op == "LSTM" else [])) if carried else [])
    kw = {"linear_before_reset": 1} if op == "GRU" else {}
    nodes = ([helper.make_node("Reshape", ["x", "shape"], ["xs"])] if carried else []) + [
        helper.make_node(op, ins, outs, hidden_size=H, **kw),
        helper.make_node("Squeeze", ["Y"], ["y"])]
    vi = lambda n, s: helper.make_tensor_value_info(n, TensorProto.FLOAT, s)  # noqa: E731
    g = helper.make_graph(nodes, "g", [vi("x", [1, I] if carried else None)]
                          + [vi(n, [1, 1, H]) for n in st],
                          [vi("y", None)] + [vi(n, [1, 1, H]) for n in outs[1:]],
                          [numpy_helper.from_array(np.asarray(a, np.float32), n)
                           for n, a in (("W", W), ("R", R), ("B", B))]
                          + [numpy_helper.from_array(np.array([1, 1, I], np.int64), "shape")])
    onnx.save(helper.make_model(g), path)
    return str(path)


@pytest.mark.parametrize("op,carried", [("LSTM", False), ("GRU", False), ("GRU", True)])
def test_onnx_rnn_gate_order_against_onnx_reference(tmp_path, op, carried):
    """ONNX's gate orders (LSTM i, o, f, c; GRU z, r, h) reordered to
    roz_nn.h's: the numpy reference equals onnx.reference over the steps,
    one sequence per call or one step per call with the state carried
    through h_in -> h_out (onnx.reference's LSTM gives no Y_c, so an LSTM
    is checked over a sequence)."""
    from onnx.reference import ReferenceEvaluator
    rng = np.random.default_rng(2)
    p = _rnn_model(op, 3, 2, rng, tmp_path / "rnn.onnx", carried)
    layers = nn_export.read_onnx(p)
    assert [l.kind for l in layers] == [op.lower()]
    xs = rng.normal(size=(5, 3)).astype(np.float32)
    if carried:
        want = run_reference(p, xs)
    else:
        want = ReferenceEvaluator(p).run(None, {"x": xs.reshape(5, 1, 3)})[0].reshape(5, -1)
    assert np.allclose(nn.forward(layers, xs), want, rtol=1e-5, atol=1e-6)


def test_onnx_refusals(tmp_path):
    w = np.ones((2, 2))
    cases = [
        ([helper.make_node("Conv", ["x", "w"], ["y"])], "operator Conv"),
        ([helper.make_node("Gemm", ["x", "w"], ["h"], transB=1),
          helper.make_node("Elu", ["h"], ["y"], alpha=0.5)], "alpha 0.5"),
        ([helper.make_node("Gemm", ["x", "w"], ["y"], alpha=2.0)], "alpha, beta"),
        ([helper.make_node("Relu", ["x"], ["y"])], "follows no dense layer"),
        ([helper.make_node("Gemm", ["x", "x"], ["y"])], "data path as a second operand"),
        ([helper.make_node("Gemm", ["x", "u"], ["y"])], "'u' comes from no earlier node"),
    ]
    for nodes, why in cases:
        with pytest.raises(ValueError, match=why):
            nn_export.read_onnx(_model(nodes, {"w": w}, tmp_path / "bad.onnx"))
    W, R = np.ones((1, 6, 2)), np.ones((1, 6, 2))
    with pytest.raises(ValueError, match="linear_before_reset"):
        nn_export.read_onnx(_model([helper.make_node("GRU", ["x", "W", "R"], ["Y", "y"],
                                                     hidden_size=2)],
                                   {"W": W, "R": R}, tmp_path / "bad.onnx"))
    # external data: refused, never opened
    g = helper.make_graph([helper.make_node("Gemm", ["x", "w"], ["y"], transB=1)], "g",
                          [helper.make_tensor_value_info("x", TensorProto.FLOAT, None)],
                          [helper.make_tensor_value_info("y", TensorProto.FLOAT, None)],
                          [numpy_helper.from_array(np.ones((2, 2), np.float32), "w")])
    m = helper.make_model(g)
    t = m.graph.initializer[0]
    t.ClearField("raw_data")
    t.data_location = TensorProto.EXTERNAL
    t.external_data.add(key="location", value="/etc/passwd")
    onnx.save(m, tmp_path / "ext.onnx")
    with pytest.raises(ValueError, match="external data"):
        nn_export.read_onnx(str(tmp_path / "ext.onnx"))


def test_torchscript_receiver_and_aliases(tmp_path):
    """The receiver keeps the name the user's code gave it (`s`, not
    `self`), and a function bound to a name before it is called is
    refused by the function's own name."""
    ref = nn.random_network(SPEC, 4)
    p = tmp_path / "policy.pt"
    renamed = _POLICY.replace("forward(self:", "forward(s:").replace("self.", "s.")
    write_pt(p, ref, code=_code(policy=renamed))
    assert [l.kind for l in nn_export.read_torchscript_layers(str(p))] == ["lstm", "dense", "dense"]
    alias = _POLICY.replace("return (actor).forward(torch.squeeze(out, 0), )",
                            "_9 = __torch__.torch.nn.functional.dropout\n"
                            "    return (actor).forward(_9(out, 0.1, False, False), )")
    write_pt(p, ref, code=_code(policy=alias))
    with pytest.raises(ValueError, match="operator __torch__.torch.nn.functional.dropout is not"):
        nn_export.read_torchscript_layers(str(p))


def test_torchscript_helper_methods_walked(tmp_path):
    """A module's own helper method (self.act(x)) is walked like forward;
    one that does something roz_nn.h does not is refused inside it."""
    ref = nn.random_network(SPEC, 4)
    p = tmp_path / "policy.pt"
    helper_ok = _POLICY.replace(
        "    actor = self.actor\n    return (actor).forward(torch.squeeze(out, 0), )",
        "    return (self).head(torch.squeeze(out, 0), )") + (
        "  def head(self: __torch__.Policy,\n    x: Tensor) -> Tensor:\n"
        "    return (self.actor).forward(x, )\n")
    write_pt(p, ref, code=_code(policy=helper_ok))
    assert [l.kind for l in nn_export.read_torchscript_layers(str(p))] == ["lstm", "dense", "dense"]
    helper_bad = helper_ok.replace("return (self.actor).forward(x, )",
                                   "return (self.actor).forward(torch.neg(x), )")
    write_pt(p, ref, code=_code(policy=helper_bad))
    with pytest.raises(ValueError, match="Policy.head: operator torch.neg is not one"):
        nn_export.read_torchscript_layers(str(p))
