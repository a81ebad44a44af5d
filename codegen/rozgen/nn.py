# SPDX-License-Identifier: Apache-2.0
"""Neural networks for roz controllers: a small model of the layers
roz_nn.h runs (Dense, LSTM, GRU), a plain numpy reference of their forward
pass, and the C header a controller compiles in (weights as exact hex
floats, the layers, a reset and a forward function).

    python -m rozgen.nn random --spec lstm:47:64,dense:64:32:elu,dense:32:12 \
        --seed 1 --name policy -o policy_net.h [--vectors 8]

writes a random network (PyTorch's initialisation ranges) and, with
--vectors, <name>_vectors.h: inputs and the numpy reference's outputs,
step by step, for tests.

    python -m rozgen.nn npz --spec lstm:47:64,dense:64:32:elu,dense:32:12 \
        --weights policy.npz --name policy -o policy_net.h

writes a trained network from a numpy .npz of its arrays, named l<k>.weight
and l<k>.bias for a dense layer k, l<k>.weight_ih, l<k>.weight_hh,
l<k>.bias_ih and l<k>.bias_hh for an LSTM or GRU (PyTorch's names without
the _l0; docs/policies.md). Read with allow_pickle=False: a file that holds
anything but plain numeric arrays is refused, never executed.

    python -m rozgen.nn pt [--spec lstm:47:64,dense:64:32:elu,dense:32:12] \
        --weights policy.pt -o policy_net.h
    python -m rozgen.nn onnx --weights policy.onnx -o policy_net.h

read TorchScript (and torch.save) archives and ONNX files (rozgen.nn_export:
read, never run); without --spec a TorchScript archive's layers and
activations come from its code/ folder.

    python -m rozgen.nn deploy POLICY --config DEPLOY.yaml --robot ROBOT -o OUT.wasm

a ready controller from a policy and its deploy configuration, checked
against the robot's manifest (rozgen.nn_deploy; docs/policies.md).
"""
from __future__ import annotations

import argparse
import math
import os
import sys
from dataclasses import dataclass, field

import numpy as np

#: activations roz_nn.h knows, by their names in PyTorch and ONNX
ACTS = {"linear": "ROZ_NN_LINEAR", "relu": "ROZ_NN_RELU", "tanh": "ROZ_NN_TANH",
        "sigmoid": "ROZ_NN_SIGMOID", "elu": "ROZ_NN_ELU", "exp": "ROZ_NN_EXP"}


@dataclass
class Layer:
    """One layer: kind 'dense' (w: out x in, b: out, act), 'lstm' (w_ih:
    4H x in, w_hh: 4H x H, b_ih, b_hh: 4H; gates i, f, g, o) or 'gru'
    (3H; gates r, z, n). Arrays are float32."""
    kind: str
    n_in: int
    n_out: int
    act: str = "linear"
    arrays: dict = field(default_factory=dict)


def check(layers: list[Layer]) -> None:
    """Refuses a network roz_nn.h cannot run, naming the layer."""
    if not layers:
        raise ValueError("an empty network")
    for k, l in enumerate(layers):
        where = f"layer {k} ({l.kind})"
        if k > 0 and l.n_in != layers[k - 1].n_out:
            raise ValueError(f"{where}: {l.n_in} inputs after a layer of {layers[k - 1].n_out}")
        if l.act not in ACTS:
            raise ValueError(f"{where}: activation '{l.act}' (roz_nn.h has {', '.join(ACTS)})")
        g = {"dense": 1, "lstm": 4, "gru": 3}.get(l.kind)
        if g is None:
            raise ValueError(f"{where}: unknown kind")
        shapes = ({"w": (l.n_out, l.n_in), "b": (l.n_out,)} if l.kind == "dense" else
                  {"w_ih": (g * l.n_out, l.n_in), "w_hh": (g * l.n_out, l.n_out),
                   "b_ih": (g * l.n_out,), "b_hh": (g * l.n_out,)})
        for name, shape in shapes.items():
            a = l.arrays.get(name)
            if a is None and name.startswith("b"):
                continue
            if a is None or tuple(a.shape) != shape:
                raise ValueError(f"{where}: {name} has shape "
                                 f"{None if a is None else tuple(a.shape)}, expected {shape}")
            if a.dtype != np.float32 or not np.all(np.isfinite(a)):
                raise ValueError(f"{where}: {name} must be finite float32")
        if l.kind != "dense" and l.act != "linear":
            raise ValueError(f"{where}: a recurrent layer has no output activation")


def random_network(spec: str, seed: int) -> list[Layer]:
    """'lstm:47:64,dense:64:32:elu,dense:32:12' with PyTorch's default
    initialisation ranges (uniform within 1/sqrt(fan))."""
    rng = np.random.default_rng(seed)
    layers = []
    for part in spec.split(","):
        f = part.split(":")
        kind, n_in, n_out = f[0], int(f[1]), int(f[2])
        act = f[3] if len(f) > 3 else "linear"

        def u(shape, fan):
            k = 1.0 / math.sqrt(fan)
            return rng.uniform(-k, k, size=shape).astype(np.float32)
        if kind == "dense":
            arrays = {"w": u((n_out, n_in), n_in), "b": u((n_out,), n_in)}
        else:
            g = {"lstm": 4, "gru": 3}[kind]
            arrays = {"w_ih": u((g * n_out, n_in), n_out), "w_hh": u((g * n_out, n_out), n_out),
                      "b_ih": u((g * n_out,), n_out), "b_hh": u((g * n_out,), n_out)}
        layers.append(Layer(kind, n_in, n_out, act, arrays))
    check(layers)
    return layers


# ---- the numpy reference (float64, PyTorch's equations) ------------------------

#: the nn imports read a value below this as zero of its sign (roz_math.h,
#: roz_math_nn_inputf); exp and sigmoid give +0 below ROZ_MATH_NN_EXP_MIN
TINY = 2.0 ** -51
FLT_MIN = 2.0 ** -126


def _tiny0(a):
    """The value the nn imports read (roz_math_nn_inputf)."""
    if a is None:
        return None
    return np.where(np.abs(a) < TINY, np.copysign(0.0, a), a)


def _mv(w: np.ndarray, x: np.ndarray, b) -> np.ndarray:
    """nn.matvec: W x (+ b), each operand read as the import reads it."""
    y = _tiny0(w) @ _tiny0(x)
    return y if b is None else y + _tiny0(b)


def _act(name: str, x: np.ndarray) -> np.ndarray:
    x = _tiny0(x)
    if name in ("sigmoid", "exp"):
        with np.errstate(over="ignore"):
            y = _act_exact(name, x)
        return np.where(np.abs(y) < FLT_MIN, 0.0, y)
    return _act_exact(name, x)


def _act_exact(name: str, x: np.ndarray) -> np.ndarray:
    if name == "relu":
        return np.maximum(x, 0.0)
    if name == "tanh":
        return np.tanh(x)
    if name == "sigmoid":
        return 1.0 / (1.0 + np.exp(-x))
    if name == "elu":
        return np.where(x > 0, x, np.expm1(np.minimum(x, 0.0)))
    if name == "exp":
        return np.exp(x)
    return x


def forward(layers: list[Layer], inputs: np.ndarray) -> np.ndarray:
    """Runs the network over a sequence (steps x n_in) from a zero state;
    returns steps x n_out, in float64."""
    d = lambda a: None if a is None else a.astype(np.float64)  # noqa: E731
    state = [None] * len(layers)
    out = []
    for x in inputs.astype(np.float64):
        for k, l in enumerate(layers):
            a = {n: d(v) for n, v in l.arrays.items()}
            H = l.n_out
            if l.kind == "dense":
                x = _act(l.act, _mv(a["w"], x, a.get("b")))
                continue
            gi = _mv(a["w_ih"], x, a.get("b_ih"))
            if l.kind == "lstm":
                h, c = state[k] if state[k] is not None else (np.zeros(H), np.zeros(H))
                g = _tiny0(gi) + _mv(a["w_hh"], h, a.get("b_hh"))  # nn.matvec's ACCUMULATE
                i, f, gg, o = (_act("sigmoid", g[:H]), _act("sigmoid", g[H:2 * H]),
                               _act("tanh", g[2 * H:3 * H]), _act("sigmoid", g[3 * H:]))
                c = f * c + i * gg
                h = o * _act("tanh", c)
                state[k] = (h, c)
            else:
                h = state[k] if state[k] is not None else np.zeros(H)
                gh = _mv(a["w_hh"], h, a.get("b_hh"))
                r = _act("sigmoid", gi[:H] + gh[:H])
                z = _act("sigmoid", gi[H:2 * H] + gh[H:2 * H])
                n = _act("tanh", gi[2 * H:] + r * gh[2 * H:])
                h = (1.0 - z) * n + z * h
                state[k] = h
            x = h
        out.append(x)
    return np.array(out)


# ---- the C header ---------------------------------------------------------------

def _floats(a: np.ndarray) -> str:
    vals = [float(v).hex() + "f" for v in np.asarray(a, dtype=np.float32).ravel()]
    vals = ["0.0f" if v in ("0x0.0p+0f",) else ("-0.0f" if v == "-0x0.0p+0f" else v)
            for v in vals]
    lines = [", ".join(vals[i:i + 6]) for i in range(0, len(vals), 6)]
    return "{\n    " + ",\n    ".join(lines) + "\n}"


def header(layers: list[Layer], name: str, source: str) -> str:
    """The C header: weights, roz_nn.h layers, <name>_reset() and
    <name>_forward(in, out) (0, or -1 when the host refused a call)."""
    check(layers)
    if not name.isidentifier():
        raise ValueError(f"name '{name}' is not a C identifier")
    up = name.upper()
    o = [f"/* Generated by rozgen.nn from {source}. DO NOT EDIT. */",
         f"#ifndef {up}_NET_H", f"#define {up}_NET_H", "", '#include "roz_nn.h"', "",
         f"#define {up}_N_IN {layers[0].n_in}", f"#define {up}_N_OUT {layers[-1].n_out}", ""]
    width = max(l.n_out for l in layers)
    for k, l in enumerate(layers):
        p = f"{name}_l{k}"
        names = ["w", "b"] if l.kind == "dense" else ["w_ih", "w_hh", "b_ih", "b_hh"]
        o.append(f"/* layer {k}: {l.kind} {l.n_in} -> {l.n_out}"
                 + (f", {l.act}" if l.kind == "dense" else "") + " */")
        for n in names:
            a = l.arrays.get(n)
            if a is not None:
                o.append(f"static const float {p}_{n}[{a.size}] = {_floats(a)};")
        ref = lambda n: f"{p}_{n}" if l.arrays.get(n) is not None else "0"  # noqa: E731
        if l.kind == "dense":
            o.append(f"static const roz_nn_dense_t {p} = {{ {l.n_in}, {l.n_out}, {ref('w')}, "
                     f"{ref('b')}, {ACTS[l.act]} }};")
        else:
            macro = "ROZ_NN_LSTM_DEFINE" if l.kind == "lstm" else "ROZ_NN_GRU_DEFINE"
            o.append(f"{macro}({p}, {l.n_in}, {l.n_out}, {ref('w_ih')}, {ref('w_hh')}, "
                     f"{ref('b_ih')}, {ref('b_hh')});")
        o.append("")
    o.append(f"static float {name}_buf[2][{width}];")
    o.append("")
    o.append(f"/** Zeroes the recurrent state (call at tick 0). */")
    o.append(f"static inline void {name}_reset(void)")
    o.append("{")
    for k, l in enumerate(layers):
        if l.kind != "dense":
            o.append(f"    roz_nn_{l.kind}_reset(&{name}_l{k});")
    o.append("}")
    o.append("")
    o.append(f"/** One step: {up}_N_IN inputs to {up}_N_OUT outputs; 0, or -1 when the host")
    o.append(" *  refused a call. */")
    o.append(f"static inline int {name}_forward(const float *in, float *out)")
    o.append("{")
    o.append("    const float *x = in;")
    for k, l in enumerate(layers):
        last = k == len(layers) - 1
        p = f"{name}_l{k}"
        if l.kind == "dense":
            y = "out" if last else f"{name}_buf[{k % 2}]"
            o.append(f"    if (roz_nn_dense(&{p}, x, {y}) != 0)")
            o.append("        return -1;")
            if not last:
                o.append(f"    x = {y};")
        else:
            o.append(f"    if (roz_nn_{l.kind}_step(&{p}, x) != 0)")
            o.append("        return -1;")
            if last:
                o.append(f"    for (int k = 0; k < {l.n_out}; k++)")
                o.append(f"        out[k] = {p}.h[k];")
            else:
                o.append(f"    x = {p}.h;")
    o.append("    return 0;")
    o.append("}")
    o.append("")
    o.append(f"#endif /* {up}_NET_H */")
    return "\n".join(o) + "\n"


def vectors_header(layers: list[Layer], name: str, steps: int, seed: int) -> str:
    """Inputs (normal, float32) and the numpy reference's float64 outputs."""
    rng = np.random.default_rng(seed + 1000)
    x = rng.normal(size=(steps, layers[0].n_in)).astype(np.float32)
    y = forward(layers, x)
    up = name.upper()
    o = [f"/* Generated by rozgen.nn: test vectors for {name}. DO NOT EDIT. */",
         f"#ifndef {up}_VECTORS_H", f"#define {up}_VECTORS_H", "",
         f"#define {up}_TEST_STEPS {steps}",
         f"static const float {name}_test_in[{steps}][{layers[0].n_in}] = {{"]
    for row in x:
        o.append("    {" + ", ".join(float(v).hex() + "f" for v in row) + "},")
    o.append("};")
    o.append(f"static const double {name}_test_out[{steps}][{layers[-1].n_out}] = {{")
    for row in y:
        o.append("    {" + ", ".join(float(v).hex() for v in row) + "},")
    o.append("};")
    o.append(f"#endif /* {up}_VECTORS_H */")
    return "\n".join(o) + "\n"


def read_npz(spec: str, path: str) -> list[Layer]:
    """A network of the shape `spec` with its arrays from an .npz file;
    refuses missing, extra, non-numeric or misshapen arrays, and checks
    every array's declared size before inflating it (rozgen.nn_export)."""
    from . import nn_export
    return nn_export.read_npz(spec, path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="rozgen-nn", description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("random", help="a random network (tests, examples, benchmarks)")
    r.add_argument("--spec", required=True)
    r.add_argument("--seed", type=int, default=1)
    r.add_argument("--name", default="policy")
    r.add_argument("--vectors", type=int, default=0, help="steps of test vectors to write")
    r.add_argument("-o", "--output", required=True)
    n = sub.add_parser("npz", help="a trained network from a numpy .npz of its arrays")
    n.add_argument("--spec", required=True)
    n.add_argument("--weights", required=True)
    n.add_argument("--name", default="policy")
    n.add_argument("--vectors", type=int, default=0, help="steps of test vectors to write")
    n.add_argument("-o", "--output", required=True)
    t = sub.add_parser("pt", help="a trained network from a TorchScript or torch.save .pt "
                                  "(read, never run; layers and activations from --spec, or "
                                  "without it from the archive's code/)")
    t.add_argument("--spec")
    t.add_argument("--weights", required=True)
    o = sub.add_parser("onnx", help="a trained network from an ONNX file (layers and "
                                    "activations from its graph)")
    o.add_argument("--weights", required=True)
    for q in (t, o):
        q.add_argument("--name", default="policy")
        q.add_argument("--vectors", type=int, default=0, help="steps of test vectors to write")
        q.add_argument("-o", "--output", required=True)
    d = sub.add_parser("deploy", help="a ready controller (.wasm and its C) from a policy and "
                                      "its deploy configuration, checked against a robot")
    d.add_argument("policy", metavar="POLICY", help=".pt, .onnx or .npz")
    d.add_argument("--config", metavar="DEPLOY.yaml",
                   help="unitree_rl_gym's deploy YAML (without it: the ONNX file's metadata)")
    d.add_argument("--robot", required=True, metavar="ROBOT",
                   help="a built-in manifest's name (unitree_g1) or a robot.toml")
    d.add_argument("--spec", help="the layers, for an .npz or a .pt without code/")
    d.add_argument("--command", metavar="VX,VY,WZ",
                   help="the constant velocity command when the robot has no command channels "
                        "(m/s, m/s, rad/s; default: the configuration's cmd_init, else 0)")
    d.add_argument("--source", metavar="OUT.c", help="where the C goes (default: beside -o)")
    d.add_argument("--deploy-file", metavar="OUT.toml",
                   help="where the deploy sequence goes, the file rozrun --deploy reads "
                        "(default: beside -o, OUT.deploy.toml)")
    d.add_argument("--sdk", metavar="DIR", help="the controller SDK's headers (default: found)")
    d.add_argument("--no-wasm", action="store_true", help="write the C only")
    d.add_argument("-o", "--output", required=True, metavar="OUT.wasm")
    a = ap.parse_args(argv)
    if a.cmd == "deploy":
        from . import nn_deploy
        try:
            cmd = nn_deploy.parse_command(a.command) if a.command else None
            p = nn_deploy.deploy(a.policy, a.config, a.robot, a.output, spec=a.spec, command=cmd,
                                 c_out=a.source, sdk=a.sdk, wasm=not a.no_wasm,
                                 deploy_out=a.deploy_file)
        except (ValueError, KeyError, IndexError, OSError) as e:
            print(f"rozgen-nn deploy: {e}", file=sys.stderr)
            return 2
        for note in p.notes:
            print(f"rozgen-nn deploy: {note}")
        m = p.manifest
        print(f"rozgen-nn deploy: {a.output}: {m.robot_id}, {len(p.joints)} joints driven, "
              f"{len(p.held)} held, inference every {p.decimation} ticks "
              f"({m.control_rate_hz / p.decimation:g} Hz), fuel {nn_deploy.fuel(p)} units a tick "
              f"declared")
        return 0
    try:
        if a.cmd == "random":
            layers = random_network(a.spec, a.seed)
            text = header(layers, a.name, f"random '{a.spec}' seed {a.seed}")
        elif a.cmd == "npz":
            layers = read_npz(a.spec, a.weights)
            text = header(layers, a.name, f"{os.path.basename(a.weights)} as '{a.spec}'")
        elif a.cmd == "pt":
            from . import nn_export  # the reader follows the file's bytes, not its suffix
            layers = nn_export.read_policy(a.weights, a.spec).layers
            text = header(layers, a.name, f"{os.path.basename(a.weights)} "
                          + ("(its code/)" if a.spec is None else f"as '{a.spec}'"))
        else:
            from . import nn_export
            layers = nn_export.read_policy(a.weights).layers
            text = header(layers, a.name, os.path.basename(a.weights))
        a.seed = getattr(a, "seed", 1)
    except (ValueError, KeyError, IndexError, OSError) as e:
        print(f"rozgen.nn: {e}", file=sys.stderr)
        return 2
    with open(a.output, "w") as f:
        f.write(text)
    if a.vectors:
        out = a.output[:-2] + "_vectors.h" if a.output.endswith(".h") else a.output + ".vectors.h"
        with open(out, "w") as f:
            f.write(vectors_header(layers, a.name, a.vectors, a.seed))
    return 0


if __name__ == "__main__":
    sys.exit(main())
