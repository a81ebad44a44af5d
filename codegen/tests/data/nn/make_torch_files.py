# SPDX-License-Identifier: Apache-2.0
"""Writes the small policy files that rozgen.nn_export's tests read: real
torch.jit.save archives, a torch.save state dict and torch.onnx.export
files, each with the inputs and torch's own outputs over a few steps.

Written by torch 2.15.0 (+cu132 wheel, run on the CPU), onnx 1.19.1,
numpy 2.4.6, Python 3.11. The tests never import torch; only this script
does. To write the files again (they change only if this script does):

    python3 -m venv "$TORCHENV"   # any folder outside the repository
    "$TORCHENV"/bin/pip install torch onnx numpy
    "$TORCHENV"/bin/python codegen/tests/data/nn/make_torch_files.py

The networks are the team's own, random (seeded), and small; their shapes
are those training stacks export:
  lstm_exporter.pt  legged_gym / unitree_rl_gym's policy exporter: an LSTM
                    `memory`, an `actor` Sequential, `hidden_state` and
                    `cell_state` buffers that forward() stores the state in
  gru_exporter.pt   the same with a GRU and one `hidden_state` buffer, an
                    Identity normalizer before the actor (Isaac Lab's shape)
  mlp.pt            a scripted Sequential MLP
  mlp_state.pt      torch.save of that MLP's state_dict() (no code: --spec)
  mlp.onnx, lstm.onnx, gru.onnx
                    torch.onnx.export (opset 11, the exporter Isaac Lab and
                    mjlab call); the recurrent ones take and give their state
                    as inputs and outputs (obs, h_in, c_in -> actions, h_out,
                    c_out), and mjlab's metadata_props (comma-separated
                    values, three decimals)
  lstm_dynamo.onnx, gru_dynamo.onnx
                    the same recurrent policies through torch.onnx.export's
                    newer exporter (dynamo=True, opset 20, tensors inside the
                    file), which slices the state and transposes the output
  <name>.io.npz     x: inputs (steps x n_in), y: torch's outputs, the state
                    carried from step to step
"""
import os
import sys

import numpy as np
import onnx
import torch
from torch import nn

HERE = os.path.dirname(os.path.abspath(__file__))
STEPS = 8
JOINTS = ["left_hip_pitch_joint", "left_knee_joint", "right_hip_pitch_joint",
          "right_knee_joint"]


class PolicyExporterLSTM(nn.Module):
    """legged_gym's exporter shape: the state lives in buffers."""

    def __init__(self, n_in, hidden, n_out):
        super().__init__()
        self.actor = nn.Sequential(nn.Linear(hidden, 8), nn.ELU(), nn.Linear(8, n_out))
        self.is_recurrent = True
        self.memory = nn.LSTM(n_in, hidden)
        self.register_buffer("hidden_state", torch.zeros(1, 1, hidden))
        self.register_buffer("cell_state", torch.zeros(1, 1, hidden))

    def forward(self, x):
        out, (h, c) = self.memory(x.unsqueeze(0), (self.hidden_state, self.cell_state))
        self.hidden_state[:] = h
        self.cell_state[:] = c
        return self.actor(out.squeeze(0))

    @torch.jit.export
    def reset_memory(self):
        self.hidden_state[:] = 0.0
        self.cell_state[:] = 0.0


class PolicyExporterGRU(nn.Module):
    def __init__(self, n_in, hidden, n_out):
        super().__init__()
        self.actor = nn.Sequential(nn.Linear(hidden, 8), nn.Tanh(), nn.Linear(8, n_out))
        self.rnn = nn.GRU(n_in, hidden)
        self.normalizer = nn.Identity()
        self.register_buffer("hidden_state", torch.zeros(1, 1, hidden))

    def forward(self, x):
        x, h = self.rnn(x.unsqueeze(0), self.hidden_state)
        self.hidden_state[:] = h
        x = x.squeeze(0)
        return self.actor(self.normalizer(x))


class OnnxLSTM(nn.Module):
    """The state as inputs and outputs (Isaac Lab's ONNX exporter shape)."""

    def __init__(self, src: PolicyExporterLSTM):
        super().__init__()
        self.rnn, self.actor = src.memory, src.actor

    def forward(self, x, h, c):
        y, (h, c) = self.rnn(x.unsqueeze(0), (h, c))
        return self.actor(y.squeeze(0)), h, c


class OnnxGRU(nn.Module):
    def __init__(self, src: PolicyExporterGRU):
        super().__init__()
        self.rnn, self.actor = src.rnn, src.actor

    def forward(self, x, h):
        y, h = self.rnn(x.unsqueeze(0), h)
        return self.actor(y.squeeze(0)), h


def metadata(model_path, n_obs):
    """mjlab's attach_metadata_to_onnx: lists as comma-separated values."""
    csv = lambda v: ",".join(f"{x:.3f}" if isinstance(x, float) else str(x) for x in v)  # noqa
    props = {"run_path": "roz/test", "joint_names": csv(JOINTS),
             "joint_stiffness": csv([100.0, 150.0, 100.0, 150.0]),
             "joint_damping": csv([2.0, 4.0, 2.0, 4.0]),
             "default_joint_pos": csv([-0.1, 0.3, -0.1, 0.3]),
             "command_names": csv(["twist"]),
             "observation_names": csv(["base_ang_vel", "projected_gravity", "joint_pos"][:n_obs]),
             "observation_scales": csv([0.25, 1.0, 1.0][:n_obs]),
             "action_scale": str(0.25)}
    m = onnx.load(model_path)
    for k, v in props.items():
        e = m.metadata_props.add()
        e.key, e.value = k, v
    onnx.save(m, model_path)


def strip_debug(model_path):
    """Drop the exporter's debug text (per-node stack traces and doc
    strings name the folders of the machine that wrote the file); the
    graph and its tensors are untouched."""
    m = onnx.load(model_path)
    m.doc_string = ""
    graphs = [m.graph]
    while graphs:
        g = graphs.pop()
        g.doc_string = ""
        for n in g.node:
            n.doc_string = ""
            del n.metadata_props[:]
            graphs.extend(a.g for a in n.attribute if a.HasField("g"))
        for v in list(g.input) + list(g.output) + list(g.value_info):
            v.doc_string = ""
            del v.metadata_props[:]
    for f in m.functions:
        for n in f.node:
            n.doc_string = ""
            del n.metadata_props[:]
    onnx.save(m, model_path)


def steps(module, x):
    with torch.no_grad():
        return np.stack([module(torch.from_numpy(x[i:i + 1]))[0].numpy() for i in range(len(x))])


def save_io(name, x, y):
    np.savez(os.path.join(HERE, f"{name}.io.npz"), x=x.astype(np.float32), y=y.astype(np.float32))


def main() -> int:
    torch.manual_seed(7)
    rng = np.random.default_rng(7)
    out = lambda n: os.path.join(HERE, n)  # noqa: E731

    lstm = PolicyExporterLSTM(6, 12, 4).eval()
    x = rng.normal(size=(STEPS, 6)).astype(np.float32)
    torch.jit.save(torch.jit.script(lstm), out("lstm_exporter.pt"))
    save_io("lstm_exporter", x, steps(torch.jit.load(out("lstm_exporter.pt")), x))

    gru = PolicyExporterGRU(5, 10, 3).eval()
    xg = rng.normal(size=(STEPS, 5)).astype(np.float32)
    torch.jit.save(torch.jit.script(gru), out("gru_exporter.pt"))
    save_io("gru_exporter", xg, steps(torch.jit.load(out("gru_exporter.pt")), xg))

    mlp = nn.Sequential(nn.Linear(7, 16), nn.ELU(), nn.Linear(16, 8), nn.ReLU(),
                        nn.Linear(8, 4)).eval()
    xm = rng.normal(size=(STEPS, 7)).astype(np.float32)
    torch.jit.save(torch.jit.script(mlp), out("mlp.pt"))
    save_io("mlp", xm, steps(torch.jit.load(out("mlp.pt")), xm))
    torch.save(mlp.state_dict(), out("mlp_state.pt"))

    kw = dict(export_params=True, opset_version=11, dynamo=False)
    torch.onnx.export(mlp, (torch.zeros(1, 7),), out("mlp.onnx"), input_names=["obs"],
                      output_names=["actions"], **kw)
    metadata(out("mlp.onnx"), 3)
    lstm_o = OnnxLSTM(lstm).eval()
    torch.onnx.export(lstm_o, (torch.zeros(1, 6), torch.zeros(1, 1, 12), torch.zeros(1, 1, 12)),
                      out("lstm.onnx"), input_names=["obs", "h_in", "c_in"],
                      output_names=["actions", "h_out", "c_out"], **kw)
    metadata(out("lstm.onnx"), 2)
    gru_o = OnnxGRU(gru).eval()
    torch.onnx.export(gru_o, (torch.zeros(1, 5), torch.zeros(1, 1, 10)), out("gru.onnx"),
                      input_names=["obs", "h_in"], output_names=["actions", "h_out"], **kw)
    metadata(out("gru.onnx"), 2)
    dyn = dict(export_params=True, dynamo=True, external_data=False)
    torch.onnx.export(lstm_o, (torch.zeros(1, 6), torch.zeros(1, 1, 12), torch.zeros(1, 1, 12)),
                      out("lstm_dynamo.onnx"), input_names=["obs", "h_in", "c_in"],
                      output_names=["actions", "h_out", "c_out"], **dyn)
    torch.onnx.export(gru_o, (torch.zeros(1, 5), torch.zeros(1, 1, 10)), out("gru_dynamo.onnx"),
                      input_names=["obs", "h_in"], output_names=["actions", "h_out"], **dyn)
    strip_debug(out("lstm_dynamo.onnx"))
    strip_debug(out("gru_dynamo.onnx"))
    for n in ("lstm_dynamo.onnx", "gru_dynamo.onnx", "lstm_exporter.pt", "gru_exporter.pt", "mlp.pt", "mlp_state.pt", "mlp.onnx",
              "lstm.onnx", "gru.onnx"):
        print(f"{n}: {os.path.getsize(out(n))} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
