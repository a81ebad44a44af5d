# SPDX-License-Identifier: Apache-2.0
"""Writes a random network of the G1 walking policy's shape (rozgen.nn's
random_network, seed 11 as bench/nn's header) as an .npz under roz's array
names, for the deployed controller that bench/nn times:

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
