# SPDX-License-Identifier: Apache-2.0
"""Behaviour cloning of the UR5 PD hold (examples/controllers/pd_hold.c):
an MLP (12 -> 32 tanh -> 6) learns v = 2 (pose - q) - 0.1 qd, clamped to
the UR5's +-3.14 rad/s, from states sampled around the pose, by full-batch
Adam in numpy (float64, a fixed seed; a few seconds). The network is the
team's own, made here, and written by rozgen.nn as the header ur5_bc.c
compiles in.

    python train.py -o ur5_bc_net.h   (PYTHONPATH=<roz>/codegen)
"""
import argparse
import sys

import numpy as np

from rozgen import nn

POSE = np.array([0.0, -1.2, 1.5, -0.3, 1.57, 0.0])
KP, KD, VMAX = 2.0, 0.1, 3.14


def teacher(q, qd):
    return np.clip(KP * (POSE - q) - KD * qd, -VMAX, VMAX)


def train(seed=1, steps=1500, n=2048, hidden=32):
    rng = np.random.default_rng(seed)
    # half the states anywhere the arm starts from, half near the pose, where
    # the hold's accuracy is decided
    span = np.where(np.arange(n)[:, None] < n // 2, 1.8, 0.15)
    q = POSE + span * rng.uniform(-1, 1, size=(n, 6))
    qd = span / 1.8 * rng.uniform(-1.5, 1.5, size=(n, 6))
    x, y = np.hstack([q, qd]), teacher(q, qd)
    w1 = rng.normal(scale=1 / np.sqrt(12), size=(hidden, 12))
    b1 = np.zeros(hidden)
    w2 = rng.normal(scale=1 / np.sqrt(hidden), size=(6, hidden))
    b2 = np.zeros(6)
    params = [w1, b1, w2, b2]
    m = [np.zeros_like(p) for p in params]
    v = [np.zeros_like(p) for p in params]
    b1m, b2m, eps = 0.9, 0.999, 1e-8
    for t in range(1, steps + 1):
        lr = 1e-2 * (0.02 ** (t / steps))  # decayed to 2e-4
        h = np.tanh(x @ w1.T + b1)
        out = h @ w2.T + b2
        err = out - y
        g_out = 2 * err / n
        g_w2, g_b2 = g_out.T @ h, g_out.sum(0)
        g_h = (g_out @ w2) * (1 - h * h)
        g_w1, g_b1 = g_h.T @ x, g_h.sum(0)
        for i, g in enumerate((g_w1, g_b1, g_w2, g_b2)):
            m[i] = b1m * m[i] + (1 - b1m) * g
            v[i] = b2m * v[i] + (1 - b2m) * g * g
            params[i] -= lr * (m[i] / (1 - b1m ** t)) / (np.sqrt(v[i] / (1 - b2m ** t)) + eps)
    mse = float(np.mean(err ** 2))
    f32 = lambda a: a.astype(np.float32)  # noqa: E731
    layers = [nn.Layer("dense", 12, hidden, "tanh", {"w": f32(w1), "b": f32(b1)}),
              nn.Layer("dense", hidden, 6, "linear", {"w": f32(w2), "b": f32(b2)})]
    return layers, mse


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("-o", "--output", required=True)
    a = ap.parse_args()
    layers, mse = train()
    with open(a.output, "w") as f:
        f.write(nn.header(layers, "bc", f"examples/controllers/ur5_bc/train.py (mse {mse:.2e})"))
    print(f"ur5_bc: trained, mean squared error {mse:.3e} (rad/s)^2")
    return 0


if __name__ == "__main__":
    sys.exit(main())
