# SPDX-License-Identifier: Apache-2.0
"""Reading torch.jit.save and torch.save archives (.pt), never running them.

An archive is a zip of <archive>/data.pkl, a pickle of the module's
attributes, <archive>/data/<key>, each tensor storage's raw bytes, and for
TorchScript <archive>/code/, every module's methods as Python source.

data.pkl is read by an unpickler that maps only the calls such files hold
(torch._utils._rebuild_tensor_v2, _rebuild_parameter, the storage types,
OrderedDict, torch.jit._pickle's restore_type_tag and build_*list) and
turns TorchScript's own classes (__torch__.*) into inert attribute bags;
any other global is refused, so nothing in the file is executed. Every
size, count and depth is checked against a named limit (LIMITS) before
the work it bounds.

code/ is parsed with Python's ast and walked, never run: the forward's
values are followed from its input to its output (layers, activations,
shape-only operators and the recurrent state kept in buffers), and
anything else is refused by name.
"""
from __future__ import annotations

import ast
import collections
import io
import pickle
import zipfile
import zlib

import numpy as np

from .nn import Layer, check

#: what a file may make this reader hold or do; each refusal names its limit
LIMITS = {
    "pickle bytes": 16 << 20,      # data.pkl
    "tensor bytes": 256 << 20,     # all tensors, as float32, after their strides
    "tensor dims": 8,
    "tensors": 4096,
    "torch classes": 1024,         # distinct __torch__.* globals in data.pkl
    "module paths": 65536,         # attribute paths walked in data.pkl's object
    "module depth": 32,
    "code files": 512,
    "code bytes": 4 << 20,
    "calls": 10000,                # method calls followed in code/
    "layers": 256,
    "expression depth": 64,        # nested expressions / attribute chains in code/
}

_STORAGE_DTYPES = {"FloatStorage": np.float32, "DoubleStorage": np.float64,
                   "HalfStorage": np.float16, "BFloat16Storage": None,
                   # counters a module may hold (a normalizer's count): read, so that
                   # the module is refused by what it does, not by its storage type
                   "LongStorage": np.int64, "IntStorage": np.int32}
#: torch.jit._pickle's list builders: they return their argument
_JIT_LISTS = {"build_intlist", "build_doublelist", "build_boollist", "build_tensorlist",
              "build_complexlist"}


def _over(what: str, got) -> ValueError:
    return ValueError(f"{got} {what}: over the limit of {LIMITS[what]} {what}")


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
            self.__dict__.update({k: v for k, v in state.items() if isinstance(k, str)})
        else:
            self.__dict__["_state"] = state


class _Tensor:
    def __init__(self, array: np.ndarray):
        self.array = array


def _restore_type_tag(value, type_str=None):
    return value  # a type annotation for TorchScript's loader; the value is kept as is


def _build_list(items):
    if not isinstance(items, list):
        raise ValueError("torch.jit._pickle.build_*list of something that is not a list")
    return items


class _Unpickler(pickle.Unpickler):
    def __init__(self, f, storages, budget):
        super().__init__(f)
        self._storages, self._budget = storages, budget
        self._classes: dict = {}

    def find_class(self, module, name):
        if module == "torch._utils" and name == "_rebuild_tensor_v2":
            return self._rebuild_tensor
        if module == "torch._utils" and name == "_rebuild_parameter":
            return _rebuild_parameter
        if module == "torch" and name in _STORAGE_DTYPES:
            return _Storage(name)
        if module == "collections" and name == "OrderedDict":
            return collections.OrderedDict
        if module == "torch.jit._pickle" and name == "restore_type_tag":
            return _restore_type_tag
        if module == "torch.jit._pickle" and name in _JIT_LISTS:
            return _build_list
        if module == "__torch__" or module.startswith("__torch__."):
            key = (module, name)
            if key not in self._classes:
                if len(self._classes) >= LIMITS["torch classes"]:
                    raise _over("torch classes", f"more than {len(self._classes)}")
                self._classes[key] = type(name, (_Inert,), {"__module__": module})
            return self._classes[key]
        raise ValueError(f"the pickle asks for {module}.{name}: refused (only tensors and "
                         "TorchScript's module attributes are read)")

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

    def _rebuild_tensor(self, storage, offset, size, stride, requires_grad=False, hooks=None,
                        *rest):
        if not isinstance(storage, np.ndarray):
            raise ValueError("a tensor without a storage")
        if not isinstance(size, (tuple, list)) or not isinstance(stride, (tuple, list)):
            raise ValueError("a tensor whose size or stride is not a tuple")
        size, stride = tuple(size), tuple(stride)
        if len(size) > LIMITS["tensor dims"]:
            raise _over("tensor dims", len(size))
        if (len(size) != len(stride) or not all(type(v) is int and v >= 0 for v in size + stride)
                or type(offset) is not int or offset < 0):
            raise ValueError(f"a tensor of size {size!r:.60}, stride {stride!r:.60}")
        self._budget[1] += 1
        if self._budget[1] > LIMITS["tensors"]:
            raise _over("tensors", self._budget[1])
        numel = 1
        for n in size:
            numel *= n
        if numel == 0:
            return _Tensor(np.zeros(size, dtype=np.float32))
        # checked before anything is made: a stride-0 or overlapping tensor
        # would make more values than its storage holds
        if numel > storage.size:
            raise ValueError(f"a tensor of size {size} and stride {stride} has {numel} values, "
                             f"more than its storage's {storage.size}")
        last = offset + sum((n - 1) * s for n, s in zip(size, stride))
        if last >= storage.size:
            raise ValueError(f"a tensor of size {size} and stride {stride} at {offset} reaches "
                             f"past its storage of {storage.size} values")
        self._budget[0] += numel * 4
        if self._budget[0] > LIMITS["tensor bytes"]:
            raise _over("tensor bytes", self._budget[0])
        a = np.lib.stride_tricks.as_strided(storage[offset:], shape=size,
                                            strides=[s * storage.itemsize for s in stride])
        return _Tensor(np.array(a, dtype=np.float32))


def _rebuild_parameter(data, requires_grad=False, hooks=None, *rest):
    if not isinstance(data, _Tensor):
        raise ValueError("a parameter that is not a tensor")
    return data


def _flatten(obj, where: str) -> tuple[dict, set]:
    """The tensors under @p obj by attribute path, in the pickle's order, and
    the paths of the modules' buffers (a module's '__buffers__' is in its
    code, so they are found later); iterative, bounded by depth and paths."""
    out: dict = {}
    stack = [(obj, "", 0)]
    walked = 0
    while stack:
        o, prefix, depth = stack.pop()
        walked += 1
        if walked > LIMITS["module paths"]:
            raise ValueError(f"{where}: data.pkl: more than {LIMITS['module paths']} module "
                             "paths: over the limit (a module reached many times?)")
        if depth > LIMITS["module depth"]:
            raise ValueError(f"{where}: data.pkl: modules nested deeper than "
                             f"{LIMITS['module depth']} (module depth limit)")
        if isinstance(o, _Tensor):
            out[prefix] = o.array
            continue
        if isinstance(o, dict):
            items = [(str(k), v) for k, v in o.items()]
        elif isinstance(o, _Inert):
            items = [(k, v) for k, v in o.__dict__.items() if not k.startswith("_")]
        else:
            continue
        for k, v in reversed(items):
            stack.append((v, f"{prefix}.{k}" if prefix else k, depth + 1))
    return out


def read_archive(path: str):
    """(tensors by attribute path, the root module's class
    '__torch__.Policy' or None, the code/ folder's files
    {'__torch__/torch/nn/modules/linear.py': text})."""
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
        if info.file_size > LIMITS["pickle bytes"]:
            raise ValueError(f"{path}: data.pkl of {info.file_size} bytes: over the limit of "
                             f"{LIMITS['pickle bytes']} pickle bytes")
        budget = [0, 0]  # tensor bytes made, tensors made

        def storage(key):
            n = f"{root}/data/{key}"
            if "/" in key or ".." in key or n not in names:
                raise ValueError(f"no storage '{key}'")
            size = z.getinfo(n).file_size  # declared; checked before it is read
            if size > LIMITS["tensor bytes"]:
                raise _over("tensor bytes", size)
            return _read_capped(z, n, size)

        try:
            obj = _Unpickler(io.BytesIO(_read_capped(z, pkl[0], info.file_size)), storage,
                             budget).load()
        except ValueError as e:
            raise ValueError(f"{path}: {e}") from None
        except Exception as e:  # a malformed pickle: refused, never half-read
            raise ValueError(f"{path}: malformed data.pkl ({type(e).__name__}: {e})") from None
        code, size, files = {}, 0, 0
        for n in names:
            if n.startswith(f"{root}/code/") and n.endswith(".py") and ".." not in n:
                files += 1
                if files > LIMITS["code files"]:
                    raise ValueError(f"{path}: more than {LIMITS['code files']} files in code/: "
                                     "over the limit of code files")
                size += z.getinfo(n).file_size
                if size > LIMITS["code bytes"]:
                    raise ValueError(f"{path}: more than {LIMITS['code bytes']} bytes of code: "
                                     "over the limit of code bytes")
                try:
                    text = _read_capped(z, n, z.getinfo(n).file_size)
                except ValueError as e:
                    raise ValueError(f"{path}: {e}") from None
                code[n[len(root) + 6:]] = text.decode("utf-8", "replace")
    out = _flatten(obj, path)
    if not out:
        raise ValueError(f"{path}: no tensors")
    cls = f"{type(obj).__module__}.{type(obj).__name__}" if isinstance(obj, _Inert) else None
    return out, cls, code


def _read_capped(z: zipfile.ZipFile, name: str, size: int) -> bytes:
    """A member's bytes, inflating no more than its declared @p size (a
    deflate bomb that lies about its size stops there)."""
    try:
        with z.open(name) as f:
            data = f.read(size + 1)
    except (zipfile.BadZipFile, zlib.error, EOFError, NotImplementedError) as e:
        raise ValueError(f"{name}: corrupt ({e})") from None
    if len(data) != size:
        raise ValueError(f"{name}: {len(data)} bytes inflated, the archive declares {size}")
    return data


def layers_from_tensors(tensors: dict, spec: str, where: str) -> list[Layer]:
    """Matches the spec's layers to the file's modules: its tensors grouped
    by module path ('memory.weight_ih_l0' -> module 'memory'), recurrent
    modules (weight_ih_l0, weight_hh_l0, bias_ih_l0, bias_hh_l0) to the
    spec's LSTM/GRU layers and dense modules (weight, bias) to its dense
    layers, each kind in file order (a module's attributes are pickled in
    the order they were set, so an exporter's `actor` may come before its
    `memory`); names, counts and shapes must agree."""
    parts = spec.split(",")
    if len(parts) > LIMITS["layers"]:
        raise ValueError(f"{where}: a spec of {len(parts)} layers: over the limit of "
                         f"{LIMITS['layers']} layers")
    if any(n.endswith(("_l1", "_reverse")) for n in tensors):
        raise ValueError(f"{where}: a stacked or bidirectional RNN (roz_nn.h runs one layer "
                         f"forward)")
    rnn_names = {"weight_ih_l0": "w_ih", "weight_hh_l0": "w_hh", "bias_ih_l0": "b_ih",
                 "bias_hh_l0": "b_hh"}
    dense_names = {"weight": "w", "bias": "b"}
    modules: dict = {}  # path -> {suffix: array}, in first-appearance order
    for n, a in tensors.items():
        prefix, _, suffix = n.rpartition(".")
        modules.setdefault(prefix, {})[suffix] = a
    rnns, denses = [], []
    for prefix, t in modules.items():
        if set(t) <= set(rnn_names) and "weight_ih_l0" in t:
            rnns.append((prefix, {rnn_names[k]: v for k, v in t.items()}))
        elif set(t) <= set(dense_names) and "weight" in t:
            denses.append((prefix, {dense_names[k]: v for k, v in t.items()}))
        else:
            raise ValueError(f"{where}: module '{prefix or 'the root'}' holds "
                             f"{', '.join(sorted(t))[:80]}: neither a Linear nor an LSTM/GRU")
    layers = []
    for k, part in enumerate(parts):
        f = part.split(":")
        try:
            kind, n_in, n_out = f[0], int(f[1]), int(f[2])
        except (IndexError, ValueError):
            raise ValueError(f"--spec: '{part}' is not kind:inputs:outputs[:activation]") from None
        act = f[3] if len(f) > 3 else "linear"
        pool = denses if kind == "dense" else rnns
        if not pool:
            want = "weight" if kind == "dense" else "weight_ih_l0"
            raise ValueError(f"{where}: layer {k} ({kind}): expected a '{want}', found no "
                             "module left of that kind")
        _, arrays = pool.pop(0)
        layers.append(Layer(kind, n_in, n_out, act, arrays))
    rest = [p for p, _ in rnns + denses]
    if rest:
        raise ValueError(f"{where}: tensors the spec has no place for: modules "
                         f"{', '.join(p or 'the root' for p in rest[:4])}")
    try:
        check(layers)
    except ValueError as e:
        raise ValueError(f"{where}: {e}") from None
    return layers


# ---- TorchScript's code/ folder ---------------------------------------------------

#: modules taken whole: their tensors make the layer, or they are an
#: activation, or they pass their input on unchanged
_OPAQUE = {"torch.nn.modules.linear.Linear": "dense", "torch.nn.modules.rnn.LSTM": "lstm",
           "torch.nn.modules.rnn.GRU": "gru", "torch.nn.modules.activation.Tanh": "tanh",
           "torch.nn.modules.activation.ReLU": "relu",
           "torch.nn.modules.activation.Sigmoid": "sigmoid",
           "torch.nn.modules.activation.ELU": "elu",
           "torch.nn.modules.linear.Identity": "identity"}
#: operators of the serialized forward, as roz_nn.h's activations
_TS_ACTS = {"tanh": "tanh", "relu": "relu", "sigmoid": "sigmoid", "elu": "elu", "exp": "exp"}
#: operators that leave a single vector's values where they are
_TS_SHAPE = {"reshape", "view", "flatten", "squeeze", "unsqueeze", "contiguous"}


def _plain(qualname: str) -> str:
    """'__torch__.torch.nn.modules.linear.___torch_mangle_3.Linear' ->
    'torch.nn.modules.linear.Linear'."""
    parts = [p for p in qualname.split(".") if not p.startswith("___torch_mangle")]
    return ".".join(parts[1:] if parts and parts[0] == "__torch__" else parts)


def _dotted(node) -> str | None:
    """'a.b.c' for a Name/Attribute chain (Optional[...] -> Optional),
    iteratively; None for anything else."""
    parts = []
    while True:
        if isinstance(node, ast.Subscript):
            node = node.value
        elif isinstance(node, ast.Attribute):
            parts.append(node.attr)
            node = node.value
        elif isinstance(node, ast.Name):
            parts.append(node.id)
            return ".".join(reversed(parts))
        else:
            return None
        if len(parts) > LIMITS["expression depth"]:
            return None


def _text(node) -> str:
    """A short text of @p node for a message, never a traceback."""
    try:
        return ast.unparse(node)[:60]
    except (RecursionError, ValueError):
        return type(node).__name__


class _Class:
    """A class of the code/ folder: its submodules' types, constants,
    buffers and methods."""

    def __init__(self, name: str, file: str):
        self.name, self.file = name, file
        self.subs: dict = {}
        self.consts: dict = {}
        self.buffers: list = []
        self.methods: dict = {}


def _classes(code: dict, where: str) -> dict:
    out = {}
    for file, text in code.items():
        module = file[:-3].replace("/", ".")
        try:
            tree = ast.parse(text, filename=file)
        except SyntaxError as e:
            raise ValueError(f"{where}: code/{file}: not TorchScript's code ({e.msg}, line "
                             f"{e.lineno})") from None
        except (RecursionError, MemoryError):
            raise ValueError(f"{where}: code/{file}: expressions nested deeper than the parser "
                             "takes (expression depth limit)") from None
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
                elif (isinstance(st, ast.Assign) and len(st.targets) == 1
                      and isinstance(st.targets[0], ast.Name)
                      and st.targets[0].id == "__buffers__" and isinstance(st.value, ast.List)):
                    c.buffers = [e.value for e in st.value.elts
                                 if isinstance(e, ast.Constant) and isinstance(e.value, str)]
                elif isinstance(st, ast.FunctionDef):
                    c.methods[st.name] = st
            out[c.name] = c
    return out


# The values a forward's names hold, while it is walked:
#   ("data", version)          the single data path (version: the op that made it)
#   ("mod", path, qualname)    a submodule
#   ("buf", path)              a buffer (recurrent state kept in the module)
#   ("state", layer, slot)     a recurrent layer's new state (slot 0: h, 1: c)
#   ("tuple", [values])
#   None                       a constant or something the walk does not follow

class _Walk:
    """The forward's layers in the order they run, following its values."""

    def __init__(self, classes: dict, tensors: dict, where: str):
        self.classes, self.tensors, self.where = classes, tensors, where
        self.ops: list = []          # ("layer", path, kind) / ("act", path, name)
        self.version = 0             # of the newest data value
        self.state_in: dict = {}     # layer index -> the buffers its state comes from
        self.stored: dict = {}       # buffer path -> (layer index, slot)
        self.calls = 0
        self.depth = 0
        self.stack: list = []        # the methods being walked, innermost last

    def refuse(self, c: _Class | None, what: str):
        method = self.stack[-1] if self.stack else "forward"
        name = f"code/{c.file}: {_plain(c.name)}.{method}" if c is not None else "code/"
        raise ValueError(f"{self.where}: {name}: {what}")

    def _new_data(self):
        self.version += 1
        return ("data", self.version)

    def _take(self, v, c, what: str):
        """@p v as the input of an operation: the newest data value."""
        if v is None or v[0] != "data":
            self.refuse(c, f"{what} of something that is not the network's data path")
        if v[1] != self.version:
            self.refuse(c, f"{what} of an earlier value: roz_nn.h runs a straight line of "
                           "layers, each on the one before")

    def call(self, mod, args: list, c_from: _Class | None, method: str = "forward"):
        """A call of @p method of the submodule @p mod = ("mod", path, qualname)."""
        self.calls += 1
        if self.calls > LIMITS["calls"]:
            self.refuse(c_from, f"more than {LIMITS['calls']} calls: over the limit of calls")
        _, path, qualname = mod
        kind = _OPAQUE.get(_plain(qualname))
        c = self.classes.get(qualname)
        if kind is not None:
            return self._opaque(kind, path, c, c_from, method, args)
        fn = c.methods.get(method) if c is not None else None
        if fn is None:
            self.refuse(c_from, f"module {path or 'the root'} is a {_plain(qualname)}, whose "
                                f"{method} is not in the archive")
        self.depth += 1
        if self.depth > LIMITS["module depth"]:
            self.refuse(c, f"calls nested deeper than {LIMITS['module depth']} (module depth "
                           "limit)")
        params = [a.arg for a in fn.args.args]
        if not params or len(args) > len(params) - 1:
            self.refuse(c, f"{len(args)} arguments to {method}, which takes {len(params) - 1}")
        env = {params[0]: mod, "$self": mod}  # the receiver, whatever the code names it
        env.update(dict(zip(params[1:], args)))
        self.stack.append(method)
        out = self.body(fn, env, c)
        self.stack.pop()
        self.depth -= 1
        return out

    def _opaque(self, kind, path, c, c_from, method, args):
        if kind in ("lstm", "gru"):
            fn = c.methods.get(method) if c is not None else None
            if fn is not None and len(fn.args.args) > 1:
                ann = _dotted(fn.args.args[1].annotation) if fn.args.args[1].annotation else ""
                if ann and ann != "Tensor":
                    self.refuse(c_from, f"{path}.{method} takes a {ann}, not a Tensor")
            if c is not None:
                for key, want in (("num_layers", 1), ("bidirectional", False), ("proj_size", 0)):
                    if c.consts.get(key, want) != want:
                        self.refuse(c_from, f"{path}: {key} {c.consts[key]} (roz_nn.h runs one "
                                            "layer, forward)")
        elif method != "forward":
            what = _plain(c.name) if c is not None else kind
            self.refuse(c_from, f"{path}.{method}: only forward of a {what}")
        if not args:
            self.refuse(c_from, f"{path or 'the root'}.{method} without an input")
        self._take(args[0], c_from, f"{path}.{method}")
        if kind == "identity":
            return args[0]
        if kind in ("dense", "lstm", "gru"):
            if len(self.ops) >= LIMITS["layers"]:
                self.refuse(c_from, f"more than {LIMITS['layers']} layers: over the limit of "
                                    "layers")
            self.ops.append(("layer", path, kind))
            if kind == "dense":
                if len(args) != 1:
                    self.refuse(c_from, f"{path}.forward with {len(args)} arguments")
                return self._new_data()
            return self._recurrent(kind, path, args, c_from)
        alpha = c.consts.get("alpha", 1.0) if c is not None else 1.0
        if kind == "elu" and alpha != 1.0:
            self.refuse(c_from, f"ELU alpha {alpha} (roz_nn.h's ELU has alpha 1)")
        self.ops.append(("act", path, kind))
        return self._new_data()

    def _recurrent(self, kind, path, args, c_from):
        k = sum(1 for op in self.ops if op[0] == "layer") - 1
        slots = 2 if kind == "lstm" else 1
        hx = args[1] if len(args) > 1 else None
        if hx is None:
            self.refuse(c_from, f"{path} is called without its state, so every call starts "
                                "from zero; roz_nn.h carries the state from step to step (keep "
                                "it in buffers, as legged_gym's exporter does)")
        bufs = hx[1] if hx[0] == "tuple" else [hx]
        if len(bufs) != slots or any(b is None or b[0] != "buf" for b in bufs):
            self.refuse(c_from, f"{path}'s state is not the module's buffers")
        self.state_in[k] = [b[1] for b in bufs]
        state = [("state", k, s) for s in range(slots)]
        return ("tuple", [self._new_data(), ("tuple", state) if slots == 2 else state[0]])

    def body(self, fn, env, c):
        for st in fn.body:
            if isinstance(st, ast.Assign):
                got = self.expr(st.value, env, c, 0)
                for t in st.targets:
                    self.bind(t, got, env, c)
            elif isinstance(st, ast.AnnAssign) and st.value is not None:
                self.bind(st.target, self.expr(st.value, env, c, 0), env, c)
            elif isinstance(st, ast.Return):
                return self.expr(st.value, env, c, 0) if st.value is not None else None
            elif isinstance(st, ast.Expr):
                if not isinstance(st.value, ast.Constant):
                    self.expr(st.value, env, c, 0)
            elif not isinstance(st, ast.Pass):
                self.refuse(c, f"a {type(st).__name__} statement (line {st.lineno}); roz_nn.h "
                               "runs a straight line of layers")
        return None

    def bind(self, t, value, env, c):
        if isinstance(t, ast.Name):
            env[t.id] = value
        elif isinstance(t, (ast.Tuple, ast.List)):
            if value is None:
                return
            if value[0] != "tuple" or len(value[1]) != len(t.elts):
                self.refuse(c, f"unpacking {len(t.elts)} values from {_text(t)}")
            for sub, v in zip(t.elts, value[1]):
                self.bind(sub, v, env, c)
        else:
            self.refuse(c, f"an assignment to {_text(t)}")

    def expr(self, node, env, c, depth):
        """Walks @p node in evaluation order; returns its value (see above)."""
        if depth > LIMITS["expression depth"]:
            self.refuse(c, f"an expression nested deeper than {LIMITS['expression depth']} "
                           "(expression depth limit)")
        d = depth + 1
        if isinstance(node, ast.Name):
            return env.get(node.id)
        if isinstance(node, ast.Attribute) and (_dotted(node) or "").startswith(
                ("torch.", "__torch__.", "ops.")):
            return ("fn", _dotted(node))  # _0 = __torch__.torch.nn.functional.dropout
        if isinstance(node, ast.Constant) or (isinstance(node, ast.UnaryOp)
                                              and isinstance(node.operand, ast.Constant)):
            return None  # an argument: 0, -1, 1.
        if isinstance(node, ast.Attribute):
            return self.attr(self.expr(node.value, env, c, d), node.attr)
        if isinstance(node, (ast.Tuple, ast.List)):
            return ("tuple", [self.expr(e, env, c, d) for e in node.elts])
        if isinstance(node, ast.Subscript):
            base = self.expr(node.value, env, c, d)
            if base is not None and base[0] == "tuple" and isinstance(node.slice, ast.Constant) \
                    and type(node.slice.value) is int and -len(base[1]) <= node.slice.value \
                    < len(base[1]):
                return base[1][node.slice.value]
            if base is not None and base[0] == "data":
                self.refuse(c, f"indexing the data path ({_text(node)})")
            return None
        if isinstance(node, (ast.BinOp, ast.UnaryOp, ast.BoolOp, ast.Compare)):
            self.refuse(c, f"operator {type(getattr(node, 'op', node)).__name__} "
                           f"({_text(node)}) is not one roz_nn.h runs")
        if not isinstance(node, ast.Call):
            self.refuse(c, f"an expression TorchScript's code does not hold: {_text(node)}")
        return self.call_expr(node, env, c, d)

    def attr(self, base, name):
        if base is None or base[0] != "mod":
            return None
        sub = self.classes.get(base[2])
        if sub is None:
            return None
        full = f"{base[1]}.{name}".lstrip(".")
        if name in sub.subs:
            return ("mod", full, sub.subs[name])
        if name in sub.buffers:
            return ("buf", full)
        return None  # a parameter, a constant, training, ...

    def call_expr(self, node, env, c, d):
        fn = node.func
        name = _dotted(fn) or ""
        if isinstance(fn, ast.Name) and (env.get(fn.id) or ("",))[0] == "fn":
            name = env[fn.id][1]  # a function bound to a name first, then called
            fn = ast.parse(name, mode="eval").body
        if name == "getattr" and len(node.args) == 2 and isinstance(node.args[1], ast.Constant):
            base = self.expr(node.args[0], env, c, d)
            got = self.attr(base, str(node.args[1].value))
            if got is None or got[0] != "mod":
                self.refuse(c, f"getattr of '{node.args[1].value}', which is no submodule")
            return got
        if isinstance(fn, ast.Attribute) and (fn.attr == "forward"
                                              or fn.attr.startswith("forward__")):
            recv = self.expr(fn.value, env, c, d)
            args = [self.expr(a, env, c, d) for a in node.args]
            if node.keywords:
                self.refuse(c, f"{fn.attr} with keyword arguments ({_text(node)})")
            if recv is None or recv[0] != "mod":
                self.refuse(c, f"forward of something that is no submodule: {_text(fn.value)}")
            return self.call(recv, args, c, fn.attr)
        method = isinstance(fn, ast.Attribute) and not name.startswith(("torch.", "ops."))
        recv = self.expr(fn.value, env, c, d) if method else None
        if recv is not None and recv[0] == "mod" and _OPAQUE.get(_plain(recv[2])) is None:
            sub = self.classes.get(recv[2])
            if sub is not None and fn.attr in sub.methods:  # a helper method of the module
                if node.keywords:
                    self.refuse(c, f"{fn.attr} with keyword arguments ({_text(node)})")
                return self.call(recv, [self.expr(a, env, c, d) for a in node.args], c, fn.attr)
        args = [self.expr(a, env, c, d) for a in node.args]
        for k in node.keywords:
            self.expr(k.value, env, c, d)
        op = fn.attr if isinstance(fn, ast.Attribute) else name
        if name.startswith("__torch__.torch.nn.functional.") and op in _TS_ACTS:
            method, name = False, f"torch.{op}"  # F.relu(x): torch.relu, as serialized
        if method:
            args = [recv] + args
        elif not name.startswith("torch."):
            self.refuse(c, f"operator {name or _text(fn)} is not one roz_nn.h runs")
        first = args[0] if args else None
        if op in _TS_SHAPE and first is not None and first[0] == "data":
            self._take(first, c, f"operator {op}")
            return first
        if op == "slice" and first is not None and first[0] == "buf" and len(args) == 1:
            return first  # buffer[:] (a whole-buffer view, to copy the state into)
        if op == "copy_" and name == "torch.copy_" and len(args) == 2 and first is not None \
                and first[0] == "buf":
            src = args[1]
            if src is None or src[0] != "state":
                self.refuse(c, f"buffer {first[1]} is set to something that is not a "
                               "recurrent layer's new state")
            self.stored[first[1]] = (src[1], src[2])
            return None
        if name.startswith("torch.") and op in _TS_ACTS and first is not None:
            self._take(first, c, f"operator {name}")
            if op == "elu" and any(not (isinstance(a, ast.Constant) and a.value == 1)
                                   for a in node.args[1:2]):
                self.refuse(c, f"operator {name} with alpha {_text(node.args[1])} (roz_nn.h's "
                               "ELU has alpha 1)")
            self.ops.append(("act", env["$self"][1], _TS_ACTS[op]))
            return self._new_data()
        self.refuse(c, f"operator {name or _text(fn)} is not one roz_nn.h runs (Linear, LSTM, "
                       f"GRU modules; {', '.join(_TS_ACTS)}; shape-only operators)")


def drop_buffers(tensors: dict, root: str | None, code: dict, where: str) -> dict:
    """@p tensors without the modules' buffers (recurrent state that
    legged_gym's exporter keeps in the module, named by each class's
    __buffers__ in code/), which must be zero: they are state, not
    weights, and roz_nn.h starts from zero."""
    if not code or root is None:
        return tensors
    classes = _classes(code, where)
    bufs, stack = set(), [("", root, 0)]
    while stack:
        prefix, qual, depth = stack.pop()
        c = classes.get(qual)
        if c is None or depth > LIMITS["module depth"] or len(bufs) > LIMITS["tensors"]:
            continue
        pre = f"{prefix}." if prefix else ""
        bufs.update(pre + b for b in c.buffers)
        stack.extend((pre + k, v, depth + 1) for k, v in c.subs.items())
    out = {}
    for n, a in tensors.items():
        if n in bufs:
            if np.any(a != 0):
                raise ValueError(f"{where}: buffer {n} holds a non-zero state; roz_nn.h starts "
                                 "from zero (reset at tick 0): save the policy after resetting "
                                 "its memory")
            continue
        out[n] = a
    return out


def layers_from_code(tensors: dict, root: str | None, code: dict, where: str) -> list[Layer]:
    """The layers in the order the archive's serialized forward runs them,
    each with the activation that follows it, their tensors found by the
    modules' attribute paths: what a --spec would say, read from the
    file. A recurrent layer's state must be the module's buffers, zero in
    the file, set to the layer's new state each call (roz_nn.h carries it;
    legged_gym's and Isaac Lab's exporters). Refuses an archive without
    code, an operator or a module it cannot map (naming it), a forward
    that is not a straight line of layers, and tensors no layer takes."""
    if not code:
        raise ValueError(f"{where}: no code/ folder (a torch.save file, not TorchScript): give "
                         "the layers with --spec")
    if root is None:
        raise ValueError(f"{where}: data.pkl holds no TorchScript module")
    classes = _classes(code, where)
    w = _Walk(classes, tensors, where)
    root_cls = classes.get(root)
    if root_cls is None:
        raise ValueError(f"{where}: the root module's class {_plain(root)} is not in code/")
    out = w.call(("mod", "", root), [("data", 0)], None)
    if out is None or out[0] != "data" or out[1] != w.version:
        w.refuse(root_cls, "does not return the output of its last layer")
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
    for k, bufs in w.state_in.items():
        for slot, buf in enumerate(bufs):
            if w.stored.get(buf) != (k, slot):
                raise ValueError(f"{where}: buffer {buf} is layer {k}'s state but the forward "
                                 f"does not store the layer's new {'hc'[slot]} in it, so the "
                                 "state is not carried from step to step")
            a = tensors.get(buf)
            if a is None or a.size != layers[k].n_out:
                raise ValueError(f"{where}: buffer {buf}: {None if a is None else a.shape}, not "
                                 f"one state of {layers[k].n_out}")
            if np.any(a != 0):
                raise ValueError(f"{where}: buffer {buf} holds a non-zero state; roz_nn.h "
                                 "starts from zero (reset at tick 0): save the policy after "
                                 "resetting its memory")
            used.add(buf)
    rest = [n for n in tensors if n not in used]
    if rest:
        raise ValueError(f"{where}: tensors the forward has no place for: {', '.join(rest[:4])}")
    if any(n.endswith(("_l1", "_reverse")) for n in tensors):
        raise ValueError(f"{where}: a stacked or bidirectional RNN (roz_nn.h runs one layer "
                         "forward)")
    check(layers)
    return layers
