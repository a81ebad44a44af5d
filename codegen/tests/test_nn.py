# SPDX-License-Identifier: Apache-2.0
"""rozgen.nn: the numpy reference against hand-written PyTorch equations,
the header's exact weights, and .npz weights read safely."""
import math

import numpy as np
import pytest

from rozgen import nn


def test_lstm_step_matches_the_equations():
    layers = nn.random_network("lstm:3:2", 5)
    a = {k: v.astype(np.float64) for k, v in layers[0].arrays.items()}
    x = np.array([[0.5, -1.0, 2.0]], dtype=np.float32)
    g = a["w_ih"] @ x[0] + a["b_ih"] + a["b_hh"]  # h = 0
    sig = lambda v: 1.0 / (1.0 + np.exp(-v))  # noqa: E731
    i, f, gg, o = sig(g[0:2]), sig(g[2:4]), np.tanh(g[4:6]), sig(g[6:8])
    c = i * gg  # c = 0 before
    assert np.allclose(nn.forward(layers, x)[0], o * np.tanh(c), rtol=0, atol=1e-15)
    del f


def test_gru_and_dense_shapes():
    layers = nn.random_network("gru:4:3,dense:3:2:elu", 1)
    y = nn.forward(layers, np.zeros((5, 4), dtype=np.float32))
    assert y.shape == (5, 2)


def test_header_has_exact_weights():
    layers = nn.random_network("dense:2:2:tanh", 3)
    text = nn.header(layers, "t", "test")
    for v in layers[0].arrays["w"].ravel():
        assert float(v).hex() + "f" in text
    assert "ROZ_NN_TANH" in text and "t_forward" in text


def test_refusals():
    with pytest.raises(ValueError, match="activation 'gelu'"):
        nn.random_network("dense:2:2:gelu", 1)
    with pytest.raises(ValueError, match="2 inputs after a layer of 3"):
        nn.random_network("dense:2:3,dense:2:1", 1)
    layers = nn.random_network("dense:2:2", 1)
    layers[0].arrays["w"] = np.full((2, 2), math.inf, dtype=np.float32)
    with pytest.raises(ValueError, match="finite"):
        nn.check(layers)


def test_npz_round_trip_and_hostile(tmp_path):
    ref = nn.random_network("lstm:5:4,dense:4:3:relu", 9)
    p = tmp_path / "w.npz"
    arrays = {"l0.weight_ih": ref[0].arrays["w_ih"], "l0.weight_hh": ref[0].arrays["w_hh"],
              "l0.bias_ih": ref[0].arrays["b_ih"], "l0.bias_hh": ref[0].arrays["b_hh"],
              "l1.weight": ref[1].arrays["w"], "l1.bias": ref[1].arrays["b"]}
    np.savez(p, **arrays)
    got = nn.read_npz("lstm:5:4,dense:4:3:relu", str(p))
    assert nn.header(got, "p", "x") == nn.header(ref, "p", "x")
    # a pickled object is refused, never unpickled
    q = tmp_path / "evil.npz"
    np.savez(q, **{**arrays, "l1.bias": np.array([object()], dtype=object)})
    with pytest.raises(ValueError):
        nn.read_npz("lstm:5:4,dense:4:3:relu", str(q))
    # a lying shape, a missing and an extra array
    np.savez(q, **{**arrays, "l1.weight": np.zeros((3, 5), dtype=np.float32)})
    with pytest.raises(ValueError, match="shape"):
        nn.read_npz("lstm:5:4,dense:4:3:relu", str(q))
    np.savez(q, **{k: v for k, v in arrays.items() if k != "l1.weight"})
    with pytest.raises(ValueError, match="no array 'l1.weight'"):
        nn.read_npz("lstm:5:4,dense:4:3:relu", str(q))
    np.savez(q, **arrays, extra=np.zeros(2))
    with pytest.raises(ValueError, match="extra"):
        nn.read_npz("lstm:5:4,dense:4:3:relu", str(q))


def test_reference_reads_tiny_numbers_as_the_imports_do():
    """roz_math.h's rule: a value below 2^-51 is read as zero of its sign,
    exp and sigmoid give +0 where they would be subnormal."""
    layers = nn.random_network("dense:2:1:exp", 1)
    layers[0].arrays["w"] = np.array([[1e-20, 0.5]], dtype=np.float32)
    layers[0].arrays["b"] = np.array([-3e-39], dtype=np.float32)
    y = nn.forward(layers, np.array([[1e20, 0.0]], dtype=np.float32))
    assert y[0, 0] == 1.0  # W's 1e-20 read as 0: e^0, not e^1
    layers[0].arrays["w"] = np.array([[2.0**-51, 0.5]], dtype=np.float32)
    y = nn.forward(layers, np.array([[2.0**51, 0.0]], dtype=np.float32))
    assert y[0, 0] == np.exp(1.0)  # 2^-51 is kept
    y = nn.forward(layers, np.array([[0.0, -175.0]], dtype=np.float32))
    assert y[0, 0] == 0.0  # e^-87.5 would be subnormal in float
    y = nn.forward(layers, np.array([[0.0, -174.0]], dtype=np.float32))
    assert y[0, 0] == math.exp(-87.0)
