# SPDX-License-Identifier: Apache-2.0
"""Reading ONNX policies (.onnx), never running them.

The graph is followed along its edges from its data input to its output:
each operator on the data path must be a layer roz_nn.h runs (Gemm,
MatMul + Add, LSTM, GRU), an activation (Relu, Tanh, Sigmoid, Elu with
alpha 1, Exp) or an operator that leaves a single vector's values where
they are (Identity, Squeeze, Unsqueeze, Reshape, Flatten); any other
(Gather, Cast, Concat, Slice, Transpose, ...) is refused by name. Shape
arithmetic that never touches the data's values (Shape -> Gather ->
Concat -> Reshape's shape input) is allowed. A recurrent layer's state
comes from graph inputs and goes to graph outputs (h_in -> h_out: the
caller carries it, as roz_nn.h does) or starts from a zero constant.

Tensors with external data are refused before anything reads them, so a
file never makes this reader open another. metadata_props (Isaac Lab,
mjlab: joint names, default pose, gains, action scale, observations) are
read into Policy.metadata by rozgen.nn_export.
"""
from __future__ import annotations

import os

import numpy as np

from .nn import ACTS, Layer, check

#: what a file may make this reader hold or do; each refusal names its limit
LIMITS = {
    "file bytes": 256 << 20,
    "nodes": 4096,
    "tensor bytes": 256 << 20,   # all initializers and constants, as float64
    "metadata bytes": 1 << 20,   # all metadata_props keys and values
    "layers": 256,
}

#: operators that leave a single vector's values where they are
_NOOPS = {"Identity", "Squeeze", "Unsqueeze", "Reshape", "Flatten"}
#: operators allowed on shapes and constants only (never on the data)
_META = {"Shape", "Gather", "Concat", "Cast", "Slice", "Unsqueeze", "Squeeze", "Constant",
         "ConstantOfShape", "Identity", "Reshape"}
_ACTS = {"Relu": "relu", "Tanh": "tanh", "Sigmoid": "sigmoid", "Elu": "elu", "Exp": "exp"}


def _external(t) -> bool:
    import onnx
    return t.data_location == onnx.TensorProto.EXTERNAL or len(t.external_data) > 0


def _check_tensors(model, path: str):
    """Refuses external data anywhere (initializers, sparse initializers,
    Constant and any tensor attribute, subgraphs) and counts the values
    the file declares, before any tensor is read."""
    import onnx
    g = model.graph
    total = 0

    def tensor(t, what):
        nonlocal total
        if _external(t):
            loc = next((e.value for e in t.external_data if e.key == "location"), "?")
            raise ValueError(f"{path}: {what} has external data ('{loc[:80]}'): refused, "
                             "never read (save the model with its tensors inside)")
        n = 1
        for d in t.dims:
            if d < 0:
                raise ValueError(f"{path}: {what}: a negative dimension")
            n *= d
        total += n * 8
        if total > LIMITS["tensor bytes"]:
            raise ValueError(f"{path}: {what}: more than {LIMITS['tensor bytes']} tensor bytes: "
                             "over the limit")

    for t in g.initializer:
        tensor(t, f"initializer '{t.name}'")
    if len(g.sparse_initializer):
        raise ValueError(f"{path}: sparse initializers are not read")
    if len(g.node) > LIMITS["nodes"]:
        raise ValueError(f"{path}: {len(g.node)} nodes: over the limit of {LIMITS['nodes']} nodes")
    for nd in g.node:
        for a in nd.attribute:
            what = f"{nd.op_type} '{nd.name}' attribute {a.name}"
            if a.type == onnx.AttributeProto.TENSOR:
                tensor(a.t, what)
            elif a.type in (onnx.AttributeProto.TENSORS, onnx.AttributeProto.SPARSE_TENSOR,
                            onnx.AttributeProto.SPARSE_TENSORS, onnx.AttributeProto.GRAPH,
                            onnx.AttributeProto.GRAPHS):
                raise ValueError(f"{path}: {what}: a subgraph or tensor list: refused")


def load(path: str):
    """The onnx ModelProto of @p path, checked (size, external data,
    counts) before any tensor is read."""
    import onnx
    try:
        size = os.path.getsize(path)
    except OSError as e:
        raise ValueError(f"{path}: {e.strerror}") from None
    if size > LIMITS["file bytes"]:
        raise ValueError(f"{path}: {size} bytes: over the limit of {LIMITS['file bytes']} bytes")
    try:
        with open(path, "rb") as f:
            model = onnx.load_model_from_string(f.read())
    except Exception as e:  # a malformed protobuf: refused, never half-read
        raise ValueError(f"{path}: not an ONNX model ({type(e).__name__}: {str(e)[:80]})") from None
    _check_tensors(model, path)
    for op in model.opset_import:
        if op.domain not in ("", "ai.onnx"):
            raise ValueError(f"{path}: operator set '{op.domain}' (only ONNX's own operators)")
    return model


def metadata_props(model, path: str) -> dict:
    """The model's metadata_props as a dict of strings, bounded."""
    total, out = 0, {}
    for p in model.metadata_props:
        total += len(p.key) + len(p.value)
        if total > LIMITS["metadata bytes"]:
            raise ValueError(f"{path}: metadata_props over the limit of "
                             f"{LIMITS['metadata bytes']} metadata bytes")
        out[p.key] = p.value
    return out


def read_onnx_model(model, path: str) -> list[Layer]:
    """The layers of an ONNX model, following its graph from its data input
    to its output (see the module's doc)."""
    import onnx
    from onnx import numpy_helper

    g = model.graph
    init = {t.name: t for t in g.initializer}
    const: dict = {}  # name -> np.ndarray, read when a layer needs it

    def value_of(name, where):
        if name in const:
            return const[name]
        if name in init:
            a = numpy_helper.to_array(init[name])
            n = int(np.prod(init[name].dims)) if len(init[name].dims) else 1
            if a.size != n:
                raise ValueError(f"{where}: '{name}': {a.size} values, dims say {n}")
            const[name] = a
            return a
        return None

    attrs = lambda nd: {a.name: onnx.helper.get_attribute_value(a) for a in nd.attribute}  # noqa
    shapes = _shapes(model)
    inputs = [i.name for i in g.input if i.name not in init]
    outputs = [o.name for o in g.output]
    # kinds of values: ("data", version) | ("meta",) | ("const",) |
    # ("state_in", name) | ("state_out", layer, slot)
    kind: dict = {n: ("const",) for n in init}
    state_in = set()
    # the state inputs are the ones that feed a recurrent layer's initial state,
    # directly or through operators that keep its values (torch's dynamo export
    # slices h_in[0:1] first)
    origin = {n: n for n in inputs}
    for nd in g.node:
        if nd.op_type in _NOOPS | {"Slice"} and nd.input and nd.input[0] in origin:
            origin[nd.output[0]] = origin[nd.input[0]]
        if nd.op_type in ("LSTM", "GRU"):
            for i in range(5, min(len(nd.input), 7)):
                if nd.input[i] in origin:
                    state_in.add(origin[nd.input[i]])
    data_in = [n for n in inputs if n not in state_in]
    if len(data_in) != 1:
        raise ValueError(f"{path}: {len(data_in)} data inputs ({', '.join(data_in)[:80]}); "
                         "roz_nn.h runs a network of one input vector")
    for n in state_in:
        kind[n] = ("state_in", n)
    kind[data_in[0]] = ("data", 0)
    version = [0]
    layers: list[Layer] = []
    pending = [None]  # a MatMul's layer waiting for its Add
    state_of: dict = {}  # layer index -> [state input names or None]
    state_out: dict = {}  # output name -> (layer, slot)

    def flat(name):
        """True when @p name's inferred shape has at most one dimension
        above 1, so that a Transpose keeps its values in order."""
        dims = shapes.get(name)
        return dims is not None and sum(1 for d in dims if d != 1) <= 1

    def whole(nd):
        """True when the Slice @p nd keeps all of its input (starts 0, ends
        past every dimension, steps 1), by constants and the inferred shape."""
        dims = shapes.get(nd.input[0])
        if dims is None or len(nd.input) < 3:
            return False
        vals = [value_of(i, path) if i else None for i in nd.input[1:5]] + [None] * 4
        starts, ends, axes, steps = vals[:4]
        if starts is None or ends is None:
            return False
        axes = list(range(len(starts))) if axes is None else list(axes)
        steps = [1] * len(starts) if steps is None else list(steps)
        for st, en, ax, sp in zip(starts, ends, axes, steps):
            if not -len(dims) <= ax < len(dims) or dims[ax] is None:
                return False
            if st != 0 or sp != 1 or en < dims[ax]:
                return False
        return True

    def new_data(out):
        version[0] += 1
        kind[out] = ("data", version[0])

    def take(nd, name, where):
        k = kind.get(name)
        if k is None or k[0] != "data":
            raise ValueError(f"{where}: input '{name}' is not the network's data path")
        if k[1] != version[0]:
            raise ValueError(f"{where}: input '{name}' is an earlier value: roz_nn.h runs a "
                             "straight line of layers, each on the one before")

    def weight(nd, i, where):
        if i >= len(nd.input) or nd.input[i] == "":
            return None
        a = value_of(nd.input[i], where)
        if a is None:
            raise ValueError(f"{where}: input {i} is not a constant")
        return np.asarray(a, dtype=np.float64)

    for nd in g.node:
        op, at = nd.op_type, attrs(nd)
        where = f"{path}: {op} '{nd.name}'"
        kinds = [kind.get(i) if i else ("const",) for i in nd.input]
        if any(k is None for k in kinds):
            missing = [i for i, k in zip(nd.input, kinds) if k is None]
            raise ValueError(f"{where}: input '{missing[0]}' comes from no earlier node")
        on_data = any(k[0] == "data" for k in kinds)
        if not on_data and op in _META and not any(k[0].startswith("state") for k in kinds):
            if op == "Constant":
                a = at.get("value")
                if a is None:
                    raise ValueError(f"{where}: a Constant without a 'value' tensor")
                const[nd.output[0]] = numpy_helper.to_array(a)  # external data refused above
                kind[nd.output[0]] = ("const",)
            else:
                for o in nd.output:
                    kind[o] = ("meta",)
            continue
        if op == "Shape" and on_data:
            kind[nd.output[0]] = ("meta",)  # the data's shape: arithmetic on it never
            continue                         # reaches the data's values
        on_state = bool(kinds) and kinds[0][0] == "state_in"
        if not on_data and on_state and (op in _NOOPS or (op == "Slice" and whole(nd))):
            kind[nd.output[0]] = kinds[0]  # the state, its values where they were
            continue
        if not on_data:
            raise ValueError(f"{where}: operator {op} on the recurrent state or constants is not "
                             "one roz_nn.h runs")
        if len(layers) >= LIMITS["layers"]:
            raise ValueError(f"{path}: more than {LIMITS['layers']} layers: over the limit")
        if op == "Transpose" and flat(nd.input[0]) or op == "Slice" and whole(nd):
            take(nd, nd.input[0], where)  # values where they were: a no-op on one vector
            kind[nd.output[0]] = kind[nd.input[0]]
            continue
        if op in _NOOPS:
            take(nd, nd.input[0], where)
            if any(k[0] == "data" for k in kinds[1:]):
                raise ValueError(f"{where}: the data path as a shape")
            kind[nd.output[0]] = kind[nd.input[0]]
            continue
        take(nd, nd.input[0], where)
        if any(k[0] == "data" for k in kinds[1:]):
            raise ValueError(f"{where}: the data path as a second operand")
        if op == "Gemm":
            if at.get("alpha", 1.0) != 1.0 or at.get("beta", 1.0) != 1.0 or at.get("transA", 0):
                raise ValueError(f"{where}: alpha, beta or transA not 1, 1, 0")
            w = weight(nd, 1, where)
            w = w if at.get("transB", 0) else w.T
            b = weight(nd, 2, where)
            if w.ndim != 2 or (b is not None and b.size != w.shape[0]):
                raise ValueError(f"{where}: weights of shape {w.shape}, bias of "
                                 f"{None if b is None else b.size}")
            layers.append(Layer("dense", w.shape[1], w.shape[0], "linear",
                                {"w": w.astype(np.float32)} |
                                ({"b": b.reshape(-1).astype(np.float32)} if b is not None else {})))
            pending[0] = None
            new_data(nd.output[0])
        elif op == "MatMul":
            w = weight(nd, 1, where)
            if w.ndim != 2:
                raise ValueError(f"{where}: weights of shape {w.shape}")
            w = w.T
            pending[0] = Layer("dense", w.shape[1], w.shape[0], "linear",
                               {"w": w.astype(np.float32)})
            layers.append(pending[0])
            new_data(nd.output[0])
            kind[nd.output[0]] = ("data", version[0], "matmul")
        elif op == "Add":
            k = kind[nd.input[0]]
            b = weight(nd, 1, where)
            if len(k) < 3 or pending[0] is None:
                raise ValueError(f"{where}: an Add that is not a MatMul's bias (roz_nn.h adds "
                                 "only a layer's own bias)")
            if b is None or b.size != pending[0].n_out:
                raise ValueError(f"{where}: not a bias of {pending[0].n_out} values")
            pending[0].arrays["b"] = b.reshape(-1).astype(np.float32)
            pending[0] = None
            kind[nd.output[0]] = ("data", version[0])
        elif op in _ACTS:
            if op == "Elu" and at.get("alpha", 1.0) != 1.0:
                raise ValueError(f"{where}: alpha {at['alpha']} (roz_nn.h's ELU has alpha 1)")
            if not layers or layers[-1].kind != "dense" or layers[-1].act != "linear":
                raise ValueError(f"{where}: an activation that follows no dense layer")
            layers[-1].act = _ACTS[op]
            pending[0] = None
            new_data(nd.output[0])
        elif op in ("LSTM", "GRU"):
            layers.append(_recurrent(nd, at, where, weight, value_of, kind, state_of,
                                     len(layers)))
            pending[0] = None
            new_data(nd.output[0])
            for slot, o in enumerate(nd.output[1:3]):
                if o:
                    kind[o] = ("state_out", len(layers) - 1, slot)
                    state_out[o] = (len(layers) - 1, slot)
        else:
            raise ValueError(f"{where}: operator {op} is not one roz_nn.h runs (Gemm, MatMul + "
                             f"Add, LSTM, GRU, {', '.join(_ACTS)}, and {', '.join(sorted(_NOOPS))} "
                             "that leave the values where they are)")
    data_out = [o for o in outputs if o not in state_out]
    if len(data_out) != 1:
        raise ValueError(f"{path}: {len(data_out)} outputs besides the recurrent state "
                         f"({', '.join(data_out)[:80]})")
    k = kind.get(data_out[0])
    if k is None or k[0] != "data" or k[1] != version[0]:
        raise ValueError(f"{path}: output '{data_out[0]}' is not the last layer's output")
    # a state that comes in from the caller must go back out to it
    outs = {v: o for o, v in state_out.items()}
    for k_layer, names in state_of.items():
        for slot, n in enumerate(names):
            if n is not None and (k_layer, slot) not in outs:
                raise ValueError(f"{path}: layer {k_layer}'s state comes from input '{n}' but its "
                                 "new state is no output, so it is not carried from step to step")
    for k_layer, l in enumerate(layers):
        if l.act not in ACTS:
            raise ValueError(f"{path}: layer {k_layer}: activation {l.act}")
    check(layers)
    return layers


def _shapes(model) -> dict:
    """Static shapes by value name, from onnx's shape inference (None for a
    dimension it cannot fix); {} when inference fails."""
    import onnx
    try:
        inferred = onnx.shape_inference.infer_shapes(model)
    except Exception:  # a graph inference cannot follow: no shape is then known
        return {}
    out = {}
    g = inferred.graph
    for vi in list(g.input) + list(g.value_info) + list(g.output):
        t = vi.type.tensor_type
        if t.HasField("shape"):
            out[vi.name] = [d.dim_value if d.HasField("dim_value") else None
                            for d in t.shape.dim]
    return out


def _recurrent(nd, at, where, weight, value_of, kind, state_of, index) -> Layer:
    op = nd.op_type
    g_n = 4 if op == "LSTM" else 3
    if at.get("direction", b"forward") not in (b"forward", "forward"):
        raise ValueError(f"{where}: direction {at['direction']!r}")
    if at.get("layout", 0) or at.get("input_forget", 0) or "activations" in at or "clip" in at:
        raise ValueError(f"{where}: layout, input_forget, clip or activations set")
    if op == "GRU" and at.get("linear_before_reset", 0) != 1:
        raise ValueError(f"{where}: linear_before_reset 0 (PyTorch's GRU is 1)")
    if op == "LSTM" and len(nd.input) > 7 and nd.input[7]:
        raise ValueError(f"{where}: peepholes")
    if len(nd.input) > 4 and nd.input[4]:
        raise ValueError(f"{where}: sequence_lens given")
    names = []
    for i in range(5, 5 + (2 if op == "LSTM" else 1)):
        n = nd.input[i] if i < len(nd.input) else ""
        k = kind.get(n) if n else None
        if not n:
            names.append(None)
        elif k is not None and k[0] == "state_in":
            names.append(n)
        elif k is not None and k[0] == "const":
            if np.any(value_of(n, where) != 0):
                raise ValueError(f"{where}: a non-zero initial state")
            names.append(None)
        else:
            raise ValueError(f"{where}: initial state '{n}' is neither a graph input nor zero")
    state_of[index] = names
    W, R, B = weight(nd, 1, where), weight(nd, 2, where), weight(nd, 3, where)
    H = int(at["hidden_size"])
    if W.ndim != 3 or W.shape[0] != 1 or W.shape[1] != g_n * H or R.shape != (1, g_n * H, H) \
            or (B is not None and B.shape != (1, 2 * g_n * H)):
        raise ValueError(f"{where}: weights of shapes {W.shape}, {R.shape}, "
                         f"{None if B is None else B.shape} for {H} hidden units, one direction")
    order = [0, 2, 3, 1] if op == "LSTM" else [1, 0, 2]  # to i,f,g,o / r,z,n
    re = lambda m: np.concatenate([m[k * H:(k + 1) * H] for k in order])  # noqa: E731
    arrays = {"w_ih": re(W[0]).astype(np.float32), "w_hh": re(R[0]).astype(np.float32)}
    if B is not None:
        arrays["b_ih"] = re(B[0][:g_n * H]).astype(np.float32)
        arrays["b_hh"] = re(B[0][g_n * H:]).astype(np.float32)
    return Layer(op.lower(), W.shape[2], H, "linear", arrays)


def read_onnx(path: str) -> list[Layer]:
    """The layers of the ONNX file @p path (see the module's doc)."""
    return read_onnx_model(load(path), path)
