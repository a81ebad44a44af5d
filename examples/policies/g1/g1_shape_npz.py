# SPDX-License-Identifier: Apache-2.0
"""Writes a random network of the G1 walking policy's full shape (47 -> LSTM
64 -> 32 ELU -> 12; rozgen.nn's random_network, seed 11 as bench/nn's
header) as an .npz under roz's array names, for g1_deployed_full
(examples/controllers): the fuel and time of a deployed inference tick at
the real policy's size (test_mujoco_deploy, bench/nn). It walks nowhere.

    python g1_shape_npz.py OUT.npz
"""
import sys

import numpy as np

from rozgen.nn import random_network

SPEC = "lstm:47:64,dense:64:32:elu,dense:32:12"
NAMES = {"w": "weight", "b": "bias", "w_ih": "weight_ih", "w_hh": "weight_hh",
         "b_ih": "bias_ih", "b_hh": "bias_hh"}

if __name__ == "__main__":
    layers = random_network(SPEC, 11)
    np.savez(sys.argv[1], **{f"l{k}.{NAMES[n]}": a for k, l in enumerate(layers)
                             for n, a in l.arrays.items()})
