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
nn.LSTM, nn.GRU, nn.Linear), the activations from a --spec, or without one
from the archive's code/ folder (layers_from_code(): TorchScript's
serialized forward, parsed with Python's ast and walked, never run; any
operator it cannot map is refused by name).

ONNX files are read with the onnx package (onnx.load, no external data):
Gemm / MatMul + Add, LSTM, GRU and the activations Relu, Tanh, Sigmoid,
Elu (alpha 1) and Exp, with the shape-only operators around them skipped;
any other operator is refused by name. ONNX's gate orders (LSTM i, o, f, c;
GRU z, r, h) are reordered to PyTorch's (i, f, g, o; r, z, n).
"""
from __future__ import annotations

import ast
import collections
import io
import pickle
import zipfile

import numpy as np

from .nn import ACTS, Layer, check

#: limits on what a file may make this reader hold
MAX_PICKLE_BYTES = 16 << 20
MAX_TENSOR_BYTES = 256 << 20
MAX_CODE_BYTES = 4 << 20

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
    return _read_archive(path)[0]


def _read_archive(path: str):
    """(tensors, the root module's class '__torch__.Policy' or None, the
    code/ folder's files {'__torch__/torch/nn/modules/linear.py': text})."""
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
        code, size = {}, 0
        for n in names:
            if n.startswith(f"{root}/code/") and n.endswith(".py") and ".." not in n:
                size += z.getinfo(n).file_size
                if size > MAX_CODE_BYTES:
                    raise ValueError(f"{path}: more than {MAX_CODE_BYTES} bytes of code")
                code[n[len(root) + 6:]] = z.read(n).decode("utf-8", "replace")
    out: dict = {}
    _flatten(obj, "", out)
    if not out:
        raise ValueError(f"{path}: no tensors")
    cls = f"{type(obj).__module__}.{type(obj).__name__}" if isinstance(obj, _Inert) else None
    return out, cls, code


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


# ---- TorchScript's code/ folder ---------------------------------------------------

#: modules taken whole: their tensors make the layer (or they are an activation)
_OPAQUE = {"torch.nn.modules.linear.Linear": "dense", "torch.nn.modules.rnn.LSTM": "lstm",
           "torch.nn.modules.rnn.GRU": "gru", "torch.nn.modules.activation.Tanh": "tanh",
           "torch.nn.modules.activation.ReLU": "relu",
           "torch.nn.modules.activation.Sigmoid": "sigmoid",
           "torch.nn.modules.activation.ELU": "elu"}
#: operators of the serialized forward, as roz_nn.h's activations
_TS_ACTS = {"tanh": "tanh", "relu": "relu", "sigmoid": "sigmoid", "elu": "elu", "exp": "exp"}
#: operators and tensor methods that only move a single data path's shape
_TS_SHAPE = {"reshape", "view", "flatten", "squeeze", "unsqueeze", "contiguous", "select",
             "slice", "size", "dim", "len"}


def _plain(qualname: str) -> str:
    """'__torch__.torch.nn.modules.linear.___torch_mangle_3.Linear' ->
    'torch.nn.modules.linear.Linear'."""
    parts = [p for p in qualname.split(".") if not p.startswith("___torch_mangle")]
    return ".".join(parts[1:] if parts and parts[0] == "__torch__" else parts)


def _dotted(node) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        base = _dotted(node.value)
        return f"{base}.{node.attr}" if base else None
    if isinstance(node, ast.Subscript):  # Optional[...], Final[float]
        return _dotted(node.value)
    return None


class _Class:
    """A class of the code/ folder: its submodules' types and its forward."""

    def __init__(self, name: str, file: str):
        self.name, self.file = name, file
        self.subs: dict = {}
        self.consts: dict = {}
        self.forward = None


def _classes(code: dict, where: str) -> dict:
    out = {}
    for file, text in code.items():
        module = file[:-3].replace("/", ".")
        try:
            tree = ast.parse(text, filename=file)
        except SyntaxError as e:
            raise ValueError(f"{where}: code/{file}: not TorchScript's code ({e.msg}, line "
                             f"{e.lineno})") from None
        for node in tree.body:
            if not isinstance(node, ast.ClassDef):
                continue
            c = _Class(f"{module}.{node.name}", file)
            for st in node.body:
                if isinstance(st, ast.AnnAssign) and isinstance(st.target, ast.Name):
                    t = _dotted(st.annotation) or ""
                    if t.startswith("__torch__."):
                        c.subs[st.target.id] = t
                    elif isinstance(st.value, ast.Constant):
                        c.consts[st.target.id] = st.value.value
                elif (isinstance(st, ast.Assign) and len(st.targets) == 1
                      and isinstance(st.targets[0], ast.Subscript)
                      and _dotted(st.targets[0].value) == "__annotations__"
                      and isinstance(st.targets[0].slice, ast.Constant)):
                    t = _dotted(st.value) or ""
                    if t.startswith("__torch__."):
                        c.subs[str(st.targets[0].slice.value)] = t
                elif isinstance(st, ast.FunctionDef) and st.name == "forward":
                    c.forward = st
            out[c.name] = c
    return out


class _Walk:
    """The forward's calls in the order they run: ('layer', path, kind) for a
    Linear/LSTM/GRU module, ('act', path, name) for an activation."""

    def __init__(self, classes: dict, where: str):
        self.classes, self.where, self.ops, self.depth = classes, where, [], 0

    def refuse(self, c: _Class, what: str):
        raise ValueError(f"{self.where}: code/{c.file}: {_plain(c.name)}.forward: {what}")

    def module(self, qualname: str, path: str, c_from: _Class):
        kind = _OPAQUE.get(_plain(qualname))
        c = self.classes.get(qualname)
        if kind in ("dense", "lstm", "gru"):
            self.ops.append(("layer", path, kind))
            return
        if kind is not None:
            alpha = c.consts.get("alpha", 1.0) if c is not None else 1.0
            if kind == "elu" and alpha != 1.0:
                self.refuse(c, f"ELU alpha {alpha} (roz_nn.h's ELU has alpha 1)")
            self.ops.append(("act", path, kind))
            return
        if c is None or c.forward is None:
            self.refuse(c_from, f"module {path or 'the root'} is a {_plain(qualname)}, whose "
                                "code is not in the archive")
        self.depth += 1
        if self.depth > 32:
            self.refuse(c, "modules nested deeper than 32")
        env = {"self": (path, qualname)}
        for st in c.forward.body:
            if isinstance(st, (ast.Assign, ast.AnnAssign)):
                value = st.value
                targets = st.targets if isinstance(st, ast.Assign) else [st.target]
                got = self.expr(value, env, c)
                for t in targets:
                    if isinstance(t, ast.Name) and got is not None:
                        env[t.id] = got
            elif isinstance(st, (ast.Return, ast.Expr)):
                if st.value is not None:
                    self.expr(st.value, env, c)
            elif isinstance(st, ast.Pass) or (isinstance(st, ast.Expr)
                                              and isinstance(st.value, ast.Constant)):
                continue
            else:
                self.refuse(c, f"a {type(st).__name__} statement (line {st.lineno}); roz_nn.h "
                               "runs a straight line of layers")
        self.depth -= 1

    def expr(self, node, env, c):
        """Walks @p node in evaluation order; returns (path, class) when it
        names a submodule, else None."""
        if isinstance(node, ast.Name):
            return env.get(node.id)
        if isinstance(node, ast.Constant) or (isinstance(node, ast.UnaryOp)
                                              and isinstance(node.operand, ast.Constant)):
            return None  # an argument: 0, -1, 1.
        if isinstance(node, ast.Attribute):
            base = self.expr(node.value, env, c)
            if base is not None:
                sub = self.classes.get(base[1])
                if sub is not None and node.attr in sub.subs:
                    return (f"{base[0]}.{node.attr}".lstrip("."), sub.subs[node.attr])
            return None
        if isinstance(node, (ast.Tuple, ast.List)):
            for e in node.elts:
                self.expr(e, env, c)
            return None
        if isinstance(node, ast.Subscript):
            self.expr(node.value, env, c)
            return None
        if isinstance(node, (ast.BinOp, ast.UnaryOp)):
            self.refuse(c, f"operator {type(node.op).__name__} ({ast.unparse(node)[:40]}) is "
                           "not one roz_nn.h runs")
        if not isinstance(node, ast.Call):
            self.refuse(c, f"an expression TorchScript's code does not hold: "
                           f"{ast.unparse(node)[:60]}")
        fn = node.func
        name = _dotted(fn) or ""
        if name == "getattr" and len(node.args) == 2 and isinstance(node.args[1], ast.Constant):
            base = self.expr(node.args[0], env, c)
            sub = self.classes.get(base[1]) if base is not None else None
            key = str(node.args[1].value)
            if sub is not None and key in sub.subs:
                return (f"{base[0]}.{key}".lstrip("."), sub.subs[key])
            self.refuse(c, f"getattr of '{key}', which is no submodule")
        method = (isinstance(fn, ast.Attribute) and fn.attr != "forward"
                  and not name.startswith(("torch.", "ops.")))
        if method:  # x.view(...): x first, as it runs
            self.expr(fn.value, env, c)
        for a in node.args:
            self.expr(a, env, c)
        for k in node.keywords:
            self.expr(k.value, env, c)
        if isinstance(fn, ast.Attribute) and fn.attr == "forward":
            recv = self.expr(fn.value, env, c)
            if recv is None:
                self.refuse(c, f"forward of something that is no submodule: "
                               f"{ast.unparse(fn.value)[:60]}")
            self.module(recv[1], recv[0], c)
            return None
        op = fn.attr if isinstance(fn, ast.Attribute) else name
        if name.startswith(("torch.", "ops.")) or isinstance(fn, ast.Attribute):
            if op in _TS_SHAPE:
                return None
            if name.startswith("torch.") and op in _TS_ACTS:
                if op == "elu" and any(not (isinstance(a, ast.Constant) and a.value == 1)
                                       for a in node.args[1:2]):
                    self.refuse(c, f"operator {name} with alpha {ast.unparse(node.args[1])} "
                                   "(roz_nn.h's ELU has alpha 1)")
                self.ops.append(("act", env["self"][0], _TS_ACTS[op]))
                return None
        self.refuse(c, f"operator {name or ast.unparse(fn)[:60]} is not one roz_nn.h runs "
                       f"(Linear, LSTM, GRU modules; {', '.join(_TS_ACTS)}; shape-only "
                       "operators)")


def layers_from_code(tensors: dict, root: str | None, code: dict, where: str) -> list[Layer]:
    """The layers in the order the archive's serialized forward runs them,
    each with the activation that follows it, their tensors found by the
    modules' attribute paths: what a --spec would say, read from the
    file. Refuses an archive without code, an operator or a module it
    cannot map (naming it), an activation that follows no dense layer, two
    in a row, and tensors no layer takes."""
    if not code:
        raise ValueError(f"{where}: no code/ folder (a torch.save file, not TorchScript): give "
                         "the layers with --spec")
    if root is None:
        raise ValueError(f"{where}: data.pkl holds no TorchScript module")
    classes = _classes(code, where)
    w = _Walk(classes, where)
    root_cls = classes.get(root)
    if root_cls is None:
        raise ValueError(f"{where}: the root module's class {_plain(root)} is not in code/")
    w.module(root, "", root_cls)
    layers, used = [], set()
    for op, path, what in w.ops:
        if op == "act":
            if not layers or layers[-1].kind != "dense":
                raise ValueError(f"{where}: activation {what} ({path or 'the root'}) follows no "
                                 "dense layer")
            if layers[-1].act != "linear":
                raise ValueError(f"{where}: activation {what} ({path or 'the root'}) after "
                                 f"{layers[-1].act}: one activation per layer")
            layers[-1].act = what
            continue
        pre = f"{path}." if path else ""
        names = ({"w": "weight", "b": "bias"} if what == "dense" else
                 {"w_ih": "weight_ih_l0", "w_hh": "weight_hh_l0", "b_ih": "bias_ih_l0",
                  "b_hh": "bias_hh_l0"})
        arrays = {ours: tensors[pre + t] for ours, t in names.items() if pre + t in tensors}
        if ("w" if what == "dense" else "w_ih") not in arrays:
            raise ValueError(f"{where}: module {path}: a {what} layer without its weights")
        used.update(pre + t for t in names.values() if pre + t in tensors)
        if what == "dense":
            n_out, n_in = arrays["w"].shape
        else:
            n_out, n_in = arrays["w_hh"].shape[1], arrays["w_ih"].shape[1]
        layers.append(Layer(what, int(n_in), int(n_out), "linear", arrays))
    rest = [n for n in tensors if n not in used]
    if rest:
        raise ValueError(f"{where}: tensors the forward has no place for: {', '.join(rest[:4])}")
    if any(n.endswith(("_l1", "_reverse")) for n in tensors):
        raise ValueError(f"{where}: a stacked or bidirectional RNN (roz_nn.h runs one layer "
                         "forward)")
    check(layers)
    return layers


def read_torchscript_layers(path: str) -> list[Layer]:
    """A TorchScript archive's layers and activations, from its tensors and
    its code/ folder alone (no --spec)."""
    tensors, root, code = _read_archive(path)
    return layers_from_code(tensors, root, code, path)


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
