# SPDX-License-Identifier: Apache-2.0
"""Writes policy.npz: a small network of the G1 walking policy's kind (an
LSTM over the 47 observations, then two dense layers to 12 actions), its
weights drawn from a fixed seed in PyTorch's initialisation ranges and the
last layer scaled down, so that its actions stay small. It is untrained: it
neither walks nor keeps the G1 up (in MuJoCo the G1 falls on it within a
few seconds, and a fall rule latches FALL); it is the mechanics of a
deployment (docs/policies.md, the deploy tests), not a policy. Run from this folder:

    python make_policy.py        # numpy only; the file is committed
"""
import numpy as np

SPEC = "lstm:47:16,dense:16:16:elu,dense:16:12"


def main() -> None:
    rng = np.random.default_rng(20261206)

    def u(shape, fan, gain=1.0):
        k = gain / np.sqrt(fan)
        return rng.uniform(-k, k, size=shape).astype(np.float32)
    arrays = {
        "l0.weight_ih": u((64, 47), 16), "l0.weight_hh": u((64, 16), 16),
        "l0.bias_ih": u((64,), 16), "l0.bias_hh": u((64,), 16),
        "l1.weight": u((16, 16), 16), "l1.bias": u((16,), 16),
        "l2.weight": u((12, 16), 16, 0.1), "l2.bias": u((12,), 16, 0.1),
    }
    np.savez("policy.npz", **arrays)


if __name__ == "__main__":
    main()
