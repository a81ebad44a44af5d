# SPDX-License-Identifier: Apache-2.0
"""Reading trained networks into rozgen.nn's model, without running them.

TorchScript and torch.save files (.pt) are zip archives: <archive>/data.pkl,
a pickle of the module's attributes, and <archive>/data/<key>, each tensor
storage's raw bytes. read_torchscript() unpickles data.pkl with an
unpickler that maps only the tensor-rebuild calls (torch._utils
._rebuild_tensor_v2, _rebuild_parameter, the storage types, OrderedDict)
and turns TorchScript's own classes (__torch__.*) into inert attribute
bags; any other global a pickle asks for is refused, so nothing in the
file is executed. Storages are read whole, checked against the size the
pickle claims, and every tensor's shape and strides are checked inside its
storage. The layers then come from the tensors' names and shapes (PyTorch's
nn.LSTM, nn.GRU, nn.Linear), the activations from a --spec.

ONNX files are read with the onnx package (onnx.load, no external data):
Gemm / MatMul + Add, LSTM, GRU and the activations Relu, Tanh, Sigmoid,
Elu (alpha 1) and Exp, with the shape-only operators around them skipped;
any other operator is refused by name. ONNX's gate orders (LSTM i, o, f, c;
GRU z, r, h) are reordered to PyTorch's (i, f, g, o; r, z, n).
"""
from __future__ import annotations

import collections
import io
import pickle
import zipfile

import numpy as np

from .nn import ACTS, Layer, check

#: limits on what a file may make this reader hold
MAX_PICKLE_BYTES = 16 << 20
MAX_TENSOR_BYTES = 256 << 20

_STORAGE_DTYPES = {"FloatStorage": np.float32, "DoubleStorage": np.float64,
                   "HalfStorage": np.float16, "BFloat16Storage": None}


class _Storage:
    """A storage type named by a pickle (torch.FloatStorage, ...)."""

    def __init__(self, name: str):
        self.name = name


class _Inert:
    """A TorchScript class (__torch__.*): its state kept, nothing run."""

    def __init__(self, *args, **kwargs):
        self.__dict__["_args"] = args

    def __setstate__(self, state):
        if isinstance(state, dict):
            self.__dict__.update(state)
        else:
            self.__dict__["_state"] = state


def _inert_class(module: str, name: str):
    return type(name, (_Inert,), {"__module__": module})


class _Tensor:
    def __init__(self, array: np.ndarray):
        self.array = array


class _Unpickler(pickle.Unpickler):
    def __init__(self, f, storages):
        super().__init__(f)
        self._storages = storages

    def find_class(self, module, name):
        if module == "torch._utils" and name == "_rebuild_tensor_v2":
            return _rebuild_tensor
        if module == "torch._utils" and name == "_rebuild_parameter":
            return _rebuild_parameter
        if module == "torch" and name in _STORAGE_DTYPES:
            return _Storage(name)
        if module == "collections" and name == "OrderedDict":
            return collections.OrderedDict
        if module.startswith("__torch__"):
            return _inert_class(module, name)
        raise ValueError(f"the pickle asks for {module}.{name}: refused (only tensors are read)")

    def persistent_load(self, pid):
        if (not isinstance(pid, tuple) or len(pid) != 5 or pid[0] != "storage"
                or not isinstance(pid[1], _Storage) or not isinstance(pid[2], str)
                or not isinstance(pid[4], int)):
            raise ValueError(f"a persistent id that is not a tensor storage: {pid!r:.80}")
        _, stype, key, _location, numel = pid
        dtype = _STORAGE_DTYPES[stype.name]
        if dtype is None:
            raise ValueError(f"storage {key}: {stype.name} is not supported")
        raw = self._storages(key)
        if numel < 0 or len(raw) != numel * np.dtype(dtype).itemsize:
            raise ValueError(f"storage {key}: {len(raw)} bytes, the pickle says {numel} "
                             f"values of {np.dtype(dtype).itemsize} bytes")
        return np.frombuffer(raw, dtype=np.dtype(dtype).newbyteorder("<"))


def _rebuild_tensor(storage, offset, size, stride, requires_grad=False, hooks=None, *rest):
    if not isinstance(storage, np.ndarray):
        raise ValueError("a tensor without a storage")
    size, stride = tuple(size), tuple(stride)
    if (len(size) != len(stride) or not all(isinstance(v, int) and v >= 0 for v in size + stride)
            or not isinstance(offset, int) or offset < 0):
        raise ValueError(f"a tensor of size {size!r:.60}, stride {stride!r:.60}")
    if 0 in size:
        return _Tensor(np.zeros(size, dtype=np.float32))
    last = offset + sum((n - 1) * s for n, s in zip(size, stride))
    if last >= storage.size:
        raise ValueError(f"a tensor of size {size} and stride {stride} at {offset} reaches "
                         f"past its storage of {storage.size} values")
    a = np.lib.stride_tricks.as_strided(storage[offset:], shape=size,
                                        strides=[s * storage.itemsize for s in stride])
    return _Tensor(np.array(a, dtype=np.float32))


def _rebuild_parameter(data, requires_grad=False, hooks=None, *rest):
    if not isinstance(data, _Tensor):
        raise ValueError("a parameter that is not a tensor")
    return data


def _flatten(obj, prefix, out, depth=0):
    if depth > 32:
        raise ValueError("modules nested deeper than 32")
    if isinstance(obj, _Tensor):
        out[prefix] = obj.array
    elif isinstance(obj, dict):
        for k, v in obj.items():
            _flatten(v, f"{prefix}.{k}" if prefix else str(k), out, depth + 1)
    elif isinstance(obj, _Inert):
        for k, v in obj.__dict__.items():
            if not k.startswith("_"):
                _flatten(v, f"{prefix}.{k}" if prefix else k, out, depth + 1)


def read_torchscript(path: str) -> dict:
    """The tensors of a .pt archive by their attribute paths
    ('memory.weight_ih_l0', 'actor.0.weight'), in the pickle's order."""
    try:
        z = zipfile.ZipFile(path)
    except (zipfile.BadZipFile, OSError) as e:
        raise ValueError(f"{path}: not a zip archive ({e})") from None
    with z:
        names = z.namelist()
        pkl = [n for n in names if n.endswith("/data.pkl") and n.count("/") == 1]
        if len(pkl) != 1:
            raise ValueError(f"{path}: not a TorchScript or torch.save archive "
                             f"(no single <archive>/data.pkl)")
        root = pkl[0].split("/")[0]
        info = z.getinfo(pkl[0])
        if info.file_size > MAX_PICKLE_BYTES:
            raise ValueError(f"{path}: data.pkl of {info.file_size} bytes")
        total = [0]

        def storage(key):
            n = f"{root}/data/{key}"
            if "/" in key or ".." in key or n not in names:
                raise ValueError(f"{path}: no storage '{key}'")
            size = z.getinfo(n).file_size
            total[0] += size
            if total[0] > MAX_TENSOR_BYTES:
                raise ValueError(f"{path}: more than {MAX_TENSOR_BYTES} bytes of tensors")
            return z.read(n)

        try:
            obj = _Unpickler(io.BytesIO(z.read(pkl[0])), storage).load()
        except ValueError as e:
            raise ValueError(f"{path}: {e}") from None
        except Exception as e:  # a malformed pickle: refused, never half-read
            raise ValueError(f"{path}: malformed data.pkl ({type(e).__name__}: {e})") from None
    out: dict = {}
    _flatten(obj, "", out)
    if not out:
        raise ValueError(f"{path}: no tensors")
    return out


def layers_from_tensors(tensors: dict, spec: str, where: str) -> list[Layer]:
    """Matches the spec's layers, in order, to the tensors, in order:
    weight_ih_l0, weight_hh_l0, bias_ih_l0, bias_hh_l0 for an LSTM or GRU,
    weight and bias for a dense layer; names and shapes must agree."""
    items = list(tensors.items())
    at = 0
    layers = []
    for k, part in enumerate(spec.split(",")):
        f = part.split(":")
        kind, n_in, n_out = f[0], int(f[1]), int(f[2])
        act = f[3] if len(f) > 3 else "linear"
        want = ({"w": "weight", "b": "bias"} if kind == "dense" else
                {"w_ih": "weight_ih_l0", "w_hh": "weight_hh_l0", "b_ih": "bias_ih_l0",
                 "b_hh": "bias_hh_l0"})
        arrays = {}
        for ours, suffix in want.items():
            if at < len(items) and items[at][0].rsplit(".", 1)[-1] == suffix:
                arrays[ours] = items[at][1]
                at += 1
            elif not ours.startswith("b"):
                got = items[at][0] if at < len(items) else "nothing"
                raise ValueError(f"{where}: layer {k} ({kind}): expected a '{suffix}', found {got}")
        layers.append(Layer(kind, n_in, n_out, act, arrays))
    if at != len(items):
        raise ValueError(f"{where}: tensors the spec has no place for: "
                         f"{', '.join(n for n, _ in items[at:][:4])}")
    if any(n.endswith(("_l1", "_reverse")) for n in tensors):
        raise ValueError(f"{where}: a stacked or bidirectional RNN (roz_nn.h runs one layer "
                         f"forward)")
    check(layers)
    return layers


# ---- ONNX ------------------------------------------------------------------------

#: operators that only move shapes around a single data path
_SHAPE_OPS = {"Squeeze", "Unsqueeze", "Reshape", "Flatten", "Identity", "Constant", "Shape",
              "Gather", "Concat", "Cast", "Transpose", "Slice", "ConstantOfShape"}
_ONNX_ACTS = {"Relu": "relu", "Tanh": "tanh", "Sigmoid": "sigmoid", "Elu": "elu", "Exp": "exp"}


def read_onnx(path: str) -> list[Layer]:
    import onnx
    from onnx import numpy_helper

    model = onnx.load(path, load_external_data=False)
    g = model.graph
    init = {}
    for t in g.initializer:
        if t.data_location == onnx.TensorProto.EXTERNAL:
            raise ValueError(f"{path}: initializer '{t.name}' has external data: refused")
        n = 1
        for d in t.dims:
            n *= d
        if n * 8 > MAX_TENSOR_BYTES:
            raise ValueError(f"{path}: initializer '{t.name}' of {n} values")
        a = numpy_helper.to_array(t)
        if a.size != n:
            raise ValueError(f"{path}: initializer '{t.name}': {a.size} values, dims say {n}")
        init[t.name] = a
    for nd in g.node:  # Constant nodes' tensors are initializers too
        if nd.op_type == "Constant" and nd.attribute and nd.attribute[0].name == "value":
            init[nd.output[0]] = numpy_helper.to_array(nd.attribute[0].t)
    attrs = lambda nd: {a.name: onnx.helper.get_attribute_value(a) for a in nd.attribute}  # noqa

    def weight(nd, i):
        if i >= len(nd.input) or nd.input[i] == "":
            return None
        if nd.input[i] not in init:
            raise ValueError(f"{path}: {nd.op_type} '{nd.name}': input {i} is not a constant")
        return np.asarray(init[nd.input[i]], dtype=np.float64)

    layers: list[Layer] = []
    pending = None  # a MatMul waiting for its Add
    for nd in g.node:
        op, at = nd.op_type, attrs(nd)
        where = f"{path}: {op} '{nd.name}'"
        if op in _SHAPE_OPS:
            continue
        if op == "Gemm":
            if at.get("alpha", 1.0) != 1.0 or at.get("beta", 1.0) != 1.0 or at.get("transA", 0):
                raise ValueError(f"{where}: alpha, beta or transA not 1, 1, 0")
            w = weight(nd, 1)
            w = w if at.get("transB", 0) else w.T
            b = weight(nd, 2)
            layers.append(Layer("dense", w.shape[1], w.shape[0], "linear",
                                {"w": w.astype(np.float32)} |
                                ({"b": b.reshape(-1).astype(np.float32)} if b is not None else {})))
        elif op == "MatMul":
            w = weight(nd, 1).T
            pending = Layer("dense", w.shape[1], w.shape[0], "linear", {"w": w.astype(np.float32)})
            layers.append(pending)
        elif op == "Add" and pending is not None:
            b = weight(nd, 1)
            if b is None or b.size != pending.n_out:
                raise ValueError(f"{where}: not a bias of {pending.n_out} values")
            pending.arrays["b"] = b.reshape(-1).astype(np.float32)
            pending = None
        elif op in _ONNX_ACTS:
            if op == "Elu" and at.get("alpha", 1.0) != 1.0:
                raise ValueError(f"{where}: alpha {at['alpha']} (roz_nn.h's ELU has alpha 1)")
            if not layers or layers[-1].kind != "dense" or layers[-1].act != "linear":
                raise ValueError(f"{where}: an activation that follows no dense layer")
            layers[-1].act = _ONNX_ACTS[op]
            pending = None
        elif op in ("LSTM", "GRU"):
            g_n = 4 if op == "LSTM" else 3
            if at.get("direction", b"forward") not in (b"forward", "forward"):
                raise ValueError(f"{where}: direction {at['direction']!r}")
            if at.get("layout", 0) or at.get("input_forget", 0) or "activations" in at \
                    or "clip" in at:
                raise ValueError(f"{where}: layout, input_forget, clip or activations set")
            if op == "GRU" and at.get("linear_before_reset", 0) != 1:
                raise ValueError(f"{where}: linear_before_reset 0 (PyTorch's GRU is 1)")
            if op == "LSTM" and len(nd.input) > 7 and nd.input[7]:
                raise ValueError(f"{where}: peepholes")
            for i in range(5, len(nd.input)):  # initial h, c: roz_nn.h starts from 0
                if nd.input[i] in init and np.any(init[nd.input[i]] != 0):
                    raise ValueError(f"{where}: a non-zero initial state")
            W, R, B = weight(nd, 1), weight(nd, 2), weight(nd, 3)
            if W.shape[0] != 1:
                raise ValueError(f"{where}: {W.shape[0]} directions")
            H = int(at["hidden_size"])
            order = [0, 2, 3, 1] if op == "LSTM" else [1, 0, 2]  # to i,f,g,o / r,z,n
            re = lambda m: np.concatenate([m[k * H:(k + 1) * H] for k in order])  # noqa: E731
            arrays = {"w_ih": re(W[0]).astype(np.float32), "w_hh": re(R[0]).astype(np.float32)}
            if B is not None:
                arrays["b_ih"] = re(B[0][:g_n * H]).astype(np.float32)
                arrays["b_hh"] = re(B[0][g_n * H:]).astype(np.float32)
            layers.append(Layer(op.lower(), W.shape[2], H, "linear", arrays))
            pending = None
        else:
            raise ValueError(f"{where}: operator {op} is not one roz_nn.h runs "
                             f"(Gemm, MatMul + Add, LSTM, GRU, {', '.join(_ONNX_ACTS)})")
    for k, l in enumerate(layers):
        if l.act not in ACTS:
            raise ValueError(f"{path}: layer {k}: activation {l.act}")
    check(layers)
    return layers
