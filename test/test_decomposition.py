"""Eq. (12a)-(12b): stiffness split along the torsion and bending axes, by round trip."""
import numpy as np
import pytest

from motoflex_ros.errors import ModelError
from motoflex_ros.lumped_stiffness.decomposition import (
    decompose_stiffness,
    static_stiffness_from_split,
)


@pytest.mark.parametrize("k_t, k_b, beta_t, b_t, beta_b, b_b, b", [
    (3.75e5, 3.59e6, 0.05, 0.19, 1.62, 0.95, 0.4),     # frame-like (Table 2)
    (5.95e3, 1.71e5, 3.09, 0.027, 1.62, 0.2, 0.07),    # front assembly-like
    (1.04e6, 1.39e5, 0.02, 0.014, 1.52, 0.37, 0.37),   # swingarm-like
])
def test_decomposition_roundtrip(k_t, k_b, beta_t, b_t, beta_b, b_b, b):
    beta, k = static_stiffness_from_split(k_t, k_b, beta_t, b_t, beta_b, b_b, b)
    split = decompose_stiffness(k, beta, b, beta_t, b_t, beta_b, b_b)
    assert split.k_t == pytest.approx(k_t, rel=1e-10)
    assert split.k_b == pytest.approx(k_b, rel=1e-10)


def test_decomposition_satisfies_eq12_as_printed():
    k, beta, b = 1.03e6, 0.6, 0.3
    beta_t, b_t, beta_b, b_b = 0.1, 0.2, 1.7, 0.9
    s = decompose_stiffness(k, beta, b, beta_t, b_t, beta_b, b_b)
    assert b**2 / k == pytest.approx(b_b**2 / s.k_b + b_t**2 / s.k_t, rel=1e-12)   # (12a)
    u, w = b_b / s.k_b, b_t / s.k_t
    tan_beta = (u * np.sin(beta_b) + w * np.sin(beta_t)) / (u * np.cos(beta_b)
                                                             + w * np.cos(beta_t))
    assert np.tan(beta) == pytest.approx(tan_beta, rel=1e-12)                      # (12b)


def test_decomposition_invariant_to_axis_half_turn():
    """The axis angle is defined modulo pi (eq. 6); with b from eq. (7) the split is the same."""
    args = dict(k=1.0e5, beta=1.2, b=0.3, beta_t=0.2, b_t=0.1, beta_b=1.8, b_b=0.4)
    ref = decompose_stiffness(**args)
    flipped = decompose_stiffness(**{**args, "beta_t": 0.2 + np.pi, "b_t": -0.1})
    assert flipped.k_t == pytest.approx(ref.k_t, rel=1e-12)
    assert flipped.k_b == pytest.approx(ref.k_b, rel=1e-12)


def test_decomposition_refuses_coincident_axes():
    with pytest.raises(ModelError):
        decompose_stiffness(1e5, 0.5, 0.3, 0.5, 0.3, 0.5, 0.3)
