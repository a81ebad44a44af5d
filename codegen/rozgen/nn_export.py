# SPDX-License-Identifier: Apache-2.0
"""Reading trained networks into rozgen.nn's model, without running them.

One entry point, read_policy(), takes what training stacks write and
decides the reader from the file's bytes, not its name:

  torch.jit.save archive (zip, code/)   rozgen.nn_torch: layers from the
                                        serialized forward, or from --spec
  torch.save archive (zip, no code/)    rozgen.nn_torch, with --spec
  ONNX model (protobuf)                 rozgen.nn_onnx, with metadata_props
  numpy .npz (zip of .npy)              read_npz_arrays(), with --spec

Every reader refuses a hostile file with a message that names the file and
the rule or limit it broke (docs/policies.md lists them), never a
traceback, and never executes or opens anything the file names.
"""
from __future__ import annotations

import hashlib
import io
import json
import os
import struct
import zipfile
import zlib
from dataclasses import dataclass, field

import numpy as np

from .nn import Layer, check
from .nn_onnx import read_onnx  # noqa: F401  (the `onnx` subcommand's reader)
from .nn_torch import LIMITS as TORCH_LIMITS  # noqa: F401
from .nn_torch import drop_buffers, layers_from_code, layers_from_tensors, read_archive

#: limits of the .npz reader; each refusal names its limit
NPZ_LIMITS = {"arrays": 1024, "array bytes": 64 << 20, "total bytes": 256 << 20}
#: limits of one metadata list
MAX_JOINTS = 1024


@dataclass
class Policy:
    """A policy as read from its file.

    layers: the network, rozgen.nn.Layer list (rozgen.nn.header() writes it).
    metadata: what the file says about the robot, under normalised keys,
        only those the file holds: joint_names (list[str]),
        default_joint_pos, stiffness, damping (list[float], one per joint
        name), action_scale (float, or list[float] one per joint),
        control_dt (float: seconds between two inferences),
        observation_names (list[str]), observation_scales (list[float],
        one per observation name, or dict name -> float).
    source_sha256: hex sha256 of the file's bytes.
    """
    layers: list
    metadata: dict = field(default_factory=dict)
    source_sha256: str = ""


def read_policy(path: str, spec: str | None = None) -> Policy:
    """Reads the policy file @p path (read, never run) into a Policy.

    The format comes from the file's content: a zip holding
    <archive>/data.pkl is a torch archive (torch.jit.save: layers and
    activations from its code/, or from @p spec when given; torch.save
    state dict: @p spec required), a zip of .npy files a numpy .npz
    (@p spec required, arrays named as docs/policies.md says), anything
    else that parses as an ONNX ModelProto an ONNX model (layers from the
    graph; @p spec, if given, must agree with them; metadata_props read
    into .metadata). A spec is 'lstm:47:64,dense:64:32:elu,dense:32:12'.

    Raises ValueError, its message naming the file and the rule or limit
    broken, for anything that is not such a file or not a network
    roz_nn.h runs; never another exception for a malformed file.
    """
    try:
        with open(path, "rb") as f:
            head = f.read(4)
            f.seek(0, os.SEEK_END)
            size = f.tell()
    except OSError as e:
        raise ValueError(f"{path}: {e.strerror}") from None
    if size > (256 << 20):
        raise ValueError(f"{path}: {size} bytes: over the limit of {256 << 20} file bytes")
    with open(path, "rb") as f:
        raw = f.read()
    try:
        return _read(path, raw, head, spec)
    except ValueError as e:  # UnicodeDecodeError from a zip's names, among others
        if str(e).startswith(f"{path}: "):
            raise
        raise ValueError(f"{path}: malformed ({str(e)[:120]})") from None
    except (KeyError, IndexError, TypeError, AttributeError, OverflowError, RecursionError,
            MemoryError, zipfile.BadZipFile, EOFError, NotImplementedError, zlib.error,
            struct.error) as e:  # a file malformed past the rules
        raise ValueError(f"{path}: malformed ({type(e).__name__}: {str(e)[:80]})") from None


def _read(path: str, raw: bytes, head: bytes, spec: str | None) -> Policy:
    sha = hashlib.sha256(raw).hexdigest()
    metadata: dict = {}
    if head[:4] == b"PK\x03\x04":
        try:
            with zipfile.ZipFile(io.BytesIO(raw)) as z:
                names = z.namelist()
        except (zipfile.BadZipFile, OSError) as e:
            raise ValueError(f"{path}: a broken zip archive ({e})") from None
        if any(n.endswith("/data.pkl") and n.count("/") == 1 for n in names):
            tensors, root, code = read_archive(path)
            if spec is not None:
                layers = layers_from_tensors(drop_buffers(tensors, root, code, path), spec, path)
            else:
                layers = layers_from_code(tensors, root, code, path)
        elif names and all(n.endswith(".npy") for n in names):
            if spec is None:
                raise ValueError(f"{path}: a numpy .npz: give the layers with --spec")
            layers = read_npz(spec, path)
        else:
            raise ValueError(f"{path}: a zip archive that is neither a torch archive "
                             "(<archive>/data.pkl) nor a numpy .npz")
    elif head[:1] == b"\x80":
        raise ValueError(f"{path}: a bare pickle (torch.save's legacy format, or a pickled "
                         "object): refused; save with torch.save's default zip format or "
                         "torch.jit.save")
    else:
        from . import nn_onnx
        model = nn_onnx.load(path)
        layers = nn_onnx.read_onnx_model(model, path)
        metadata = normalise_metadata(nn_onnx.metadata_props(model, path), path)
        if spec is not None:
            _agree(layers, spec, path)
    return Policy(layers=layers, metadata=metadata, source_sha256=sha)


def _agree(layers: list, spec: str, path: str) -> None:
    want = [tuple(p.split(":")[:3]) + ((p.split(":") + ["linear"])[3],) for p in spec.split(",")]
    got = [(l.kind, str(l.n_in), str(l.n_out), l.act) for l in layers]
    if want != got:
        raise ValueError(f"{path}: the graph's layers {':'.join(map(str, got[0])) if got else ''}"
                         f"... disagree with --spec '{spec}'")


# ---- metadata ----------------------------------------------------------------------

#: normalised key -> the keys training stacks write it under, and its type
_META_KEYS = {
    "joint_names": (("joint_names",), "names"),
    "default_joint_pos": (("default_joint_pos", "default_joint_positions"), "floats"),
    "stiffness": (("joint_stiffness", "stiffness", "kps"), "floats"),
    "damping": (("joint_damping", "damping", "kds"), "floats"),
    "action_scale": (("action_scale",), "scale"),
    "control_dt": (("control_dt", "policy_dt"), "scale"),
    "observation_names": (("observation_names", "obs_names"), "names"),
    "observation_scales": (("observation_scales", "obs_scales"), "scales"),
}


def _parse_list(text: str):
    """A metadata value: JSON (a list, object or number), or mjlab's and
    Isaac Lab's comma-separated values."""
    t = text.strip()
    if t[:1] in "[{":
        try:
            return json.loads(t)
        except (json.JSONDecodeError, RecursionError):
            raise ValueError("neither JSON nor comma-separated values") from None
    return [v.strip() for v in t.split(",")] if t else []


def _floats(v, key: str, path: str) -> list:
    if not isinstance(v, list):
        raise ValueError(f"{path}: metadata '{key}': not a list of numbers")
    out = []
    for x in v:
        try:
            f = float(x)
        except (TypeError, ValueError):
            raise ValueError(f"{path}: metadata '{key}': '{str(x)[:40]}' is not a number") from None
        if not np.isfinite(f):
            raise ValueError(f"{path}: metadata '{key}': {f} is not finite")
        out.append(f)
    return out


def normalise_metadata(props: dict, path: str) -> dict:
    """metadata_props (strings) -> Policy.metadata's keys and types; a key
    given under two names, a value that does not parse, or lists whose
    lengths disagree with joint_names / observation_names are refused,
    naming the key."""
    out: dict = {}
    for ours, (theirs, typ) in _META_KEYS.items():
        found = [k for k in theirs if k in props]
        if len(found) > 1:
            raise ValueError(f"{path}: metadata gives {ours} twice ({', '.join(found)})")
        if not found:
            continue
        key = found[0]
        try:
            v = _parse_list(props[key])
        except ValueError as e:
            raise ValueError(f"{path}: metadata '{key}': {e}") from None
        if isinstance(v, list) and len(v) > MAX_JOINTS:
            raise ValueError(f"{path}: metadata '{key}': {len(v)} values: over the limit of "
                             f"{MAX_JOINTS}")
        if typ == "names":
            if not isinstance(v, list) or not all(isinstance(x, str) and x for x in v):
                raise ValueError(f"{path}: metadata '{key}': not a list of names")
            out[ours] = v
        elif typ == "floats":
            out[ours] = _floats(v, key, path)
        elif typ == "scale":
            vals = _floats(v if isinstance(v, list) else [v], key, path)
            out[ours] = vals[0] if len(vals) == 1 else vals
        else:
            if isinstance(v, dict):
                out[ours] = dict(zip(v, _floats(list(v.values()), key, path)))
            else:
                out[ours] = _floats(v, key, path)
    n = len(out.get("joint_names", []))
    for k in ("default_joint_pos", "stiffness", "damping", "action_scale"):
        v = out.get(k)
        if n and isinstance(v, list) and len(v) != n:
            raise ValueError(f"{path}: metadata {k}: {len(v)} values for {n} joint_names")
    obs = out.get("observation_names")
    sc = out.get("observation_scales")
    if obs is not None and isinstance(sc, list) and len(sc) != len(obs):
        raise ValueError(f"{path}: metadata observation_scales: {len(sc)} values for "
                         f"{len(obs)} observation_names")
    return out


# ---- numpy .npz --------------------------------------------------------------------

def read_npz_arrays(path: str) -> dict:
    """The arrays of an .npz, each checked before it is inflated: the
    declared size against NPZ_LIMITS, the .npy header's shape and dtype
    (numbers only, no pickle) against the declared size, and the inflate
    capped at the declared size."""
    try:
        z = zipfile.ZipFile(path)
    except (zipfile.BadZipFile, OSError) as e:
        raise ValueError(f"{path}: not an .npz ({e})") from None
    out, total = {}, 0
    with z:
        infos = z.infolist()
        if len(infos) > NPZ_LIMITS["arrays"]:
            raise ValueError(f"{path}: {len(infos)} arrays: over the limit of "
                             f"{NPZ_LIMITS['arrays']} arrays")
        for info in infos:
            name = info.filename
            if not name.endswith(".npy"):
                raise ValueError(f"{path}: '{name[:60]}' is not an .npy array")
            if info.file_size > NPZ_LIMITS["array bytes"]:
                raise ValueError(f"{path}: '{name[:60]}' declares {info.file_size} bytes: over "
                                 f"the limit of {NPZ_LIMITS['array bytes']} array bytes")
            total += info.file_size
            if total > NPZ_LIMITS["total bytes"]:
                raise ValueError(f"{path}: over the limit of {NPZ_LIMITS['total bytes']} bytes "
                                 "of arrays")
            try:
                with z.open(info) as f:
                    data = f.read(info.file_size + 1)
            except (zipfile.BadZipFile, zlib.error, EOFError, NotImplementedError) as e:
                raise ValueError(f"{path}: '{name[:60]}' is corrupt ({e})") from None
            if len(data) != info.file_size:
                raise ValueError(f"{path}: '{name[:60]}' inflates to more or less than the "
                                 f"{info.file_size} bytes it declares")
            try:
                b = io.BytesIO(data)
                version = np.lib.format.read_magic(b)
                if version == (1, 0):
                    shape, fortran, dtype = np.lib.format.read_array_header_1_0(b)
                else:
                    shape, fortran, dtype = np.lib.format.read_array_header_2_0(b)
            except (ValueError, OSError, SyntaxError) as e:
                raise ValueError(f"{path}: '{name[:60]}': not an .npy array ({e})") from None
            if dtype.kind not in "fiu" or dtype.hasobject:
                raise ValueError(f"{path}: '{name[:-4]}' is {dtype}, not numbers")
            n = 1
            for d in shape:
                n *= d
            if n * dtype.itemsize != len(data) - b.tell():
                raise ValueError(f"{path}: '{name[:-4]}': shape {shape} of {dtype} is not the "
                                 f"{len(data) - b.tell()} bytes stored")
            a = np.frombuffer(data, dtype=dtype, count=n, offset=b.tell())
            a = a.reshape(shape, order="F" if fortran else "C")
            out[name[:-4]] = a
    return out


def read_npz(spec: str, path: str) -> list[Layer]:
    """A network of the shape @p spec with its arrays from an .npz file,
    named l<k>.weight, l<k>.bias (dense layer k), l<k>.weight_ih,
    l<k>.weight_hh, l<k>.bias_ih, l<k>.bias_hh (LSTM or GRU layer k);
    refuses missing, extra, non-numeric or misshapen arrays."""
    from .nn import random_network
    try:
        layers = random_network(spec, 0)  # the shapes; every array replaced below
    except (ValueError, IndexError, KeyError) as e:
        raise ValueError(f"--spec '{spec}': {e}") from None
    names = {"w": "weight", "b": "bias", "w_ih": "weight_ih", "w_hh": "weight_hh",
             "b_ih": "bias_ih", "b_hh": "bias_hh"}
    arrays = read_npz_arrays(path)
    keys = set(arrays)
    for k, l in enumerate(layers):
        for ours, theirs in names.items():
            if ours not in l.arrays:
                continue
            key = f"l{k}.{theirs}"
            if key not in keys:
                if ours.startswith("b"):
                    del l.arrays[ours]
                    continue
                raise ValueError(f"{path}: layer {k} ({l.kind}): no array '{key}'")
            keys.discard(key)
            l.arrays[ours] = arrays[key].astype(np.float32)
    if keys:
        raise ValueError(f"{path}: arrays the spec has no place for: {', '.join(sorted(keys))}")
    try:
        check(layers)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    return layers


# ---- the readers by their former names (the pt subcommand, tests) ------------------

def read_torchscript(path: str) -> dict:
    """The weights of a .pt archive by their attribute paths
    ('memory.weight_ih_l0', 'actor.0.weight'), in the pickle's order;
    the modules' buffers (zero recurrent state) left out."""
    tensors, root, code = read_archive(path)
    return drop_buffers(tensors, root, code, path)


def read_torchscript_layers(path: str) -> list[Layer]:
    """A TorchScript archive's layers and activations, from its tensors and
    its code/ folder alone (no --spec)."""
    tensors, root, code = read_archive(path)
    return layers_from_code(tensors, root, code, path)
