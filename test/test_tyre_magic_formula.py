"""Magic Formula motorcycle tyre: closed-form linearization against the full formula.

Derived values (computed from the [MD] coefficients, docs/references.md#md, when they were
transcribed; Fz0 = 1600 N): front at Fz = 1600 N K_alpha ~ 26.7 kN/rad, K_gamma ~ 1.12 kN/rad,
sigma ~ 0.22 m at 10-30 m/s and 0.25 m at 58 m/s; rear at Fz = 2000 N K_alpha ~ 23.5 kN/rad,
K_gamma ~ 0.92 kN/rad, sigma ~ 0.23/0.26/0.36 m at 10/30/58 m/s.
"""
import numpy as np
import pytest

from motoflex_ros.vehicle.tyre import mf_aligning_moment, mf_linearized, mf_side_force

FRONT_MD = dict(
    Fz0=1600.0, Cy=0.8327, pdy1=1.3, pdy2=0.0, pdy3=0.0, pey1=-1.2556, pey2=-3.2068,
    pey4=-3.998, pky1=22.841, pky2=2.1578, pky3=2.5058, pky4=-0.08088, pky5=-0.22882,
    pky6=0.69677, pky7=-0.03077, Cgamma=0.867565, Egamma=-15.815, Ct=1.0917, qbz1=10.486,
    qbz2=-0.001154, qbz5=-0.68973, qbz6=1.0411, qbz9=27.445, qbz10=-1.0792, qdz1=0.19796,
    qdz2=0.06563, qdz3=0.2199, qdz4=0.21866, qdz8=0.3682, qdz9=0.1218, qdz10=0.25439,
    qdz11=-0.17873, qez1=-0.91586, qez2=0.11625, qez5=1.4387, qhz3=-0.003789, qhz4=-0.009862,
    relaxation_a=8.633e-6, relaxation_b=-3.725e-8, relaxation_c=8.389e-10)
REAR_MD = dict(
    FRONT_MD, Cy=0.9, pey1=-2.2227, pey2=-1.669, pey4=-4.288, pky1=15.791, pky2=1.6935,
    pky3=1.4604, pky4=0.669, pky5=0.18708, pky6=0.45512, pky7=0.013293, Cgamma=0.61397,
    Egamma=-19.99, relaxation_a=9.694e-6, relaxation_b=-1.333e-8, relaxation_c=1.898e-9)

H = 1e-30


def _derivative(fun, at=0.0):
    return fun(at + 1j * H).imag / H


@pytest.mark.parametrize("coeffs, fz", [(FRONT_MD, 1600.0), (REAR_MD, 2000.0),
                                        (FRONT_MD, 1100.0)])
def test_mf_linearization_roundtrip(coeffs, fz):
    """Closed-form stiffnesses equal complex-step derivatives of the full formula at 0."""
    crown = 0.06
    tyre = mf_linearized(coeffs, fz, crown)
    assert tyre.k_alpha == pytest.approx(_derivative(lambda a: mf_side_force(coeffs, fz, a, 0.0)),
                                         rel=1e-12)
    assert tyre.k_gamma == pytest.approx(_derivative(lambda g: mf_side_force(coeffs, fz, 0.0, g)),
                                         rel=1e-12)
    d_mz_alpha = _derivative(lambda a: mf_aligning_moment(coeffs, fz, a, 0.0, crown))
    d_mz_gamma = _derivative(lambda g: mf_aligning_moment(coeffs, fz, 0.0, g, crown))
    assert tyre.k_malpha == pytest.approx(-d_mz_alpha, rel=1e-12)
    assert tyre.k_mgamma == pytest.approx(d_mz_gamma, rel=1e-12)


def test_mf_stiffness_published():
    front = mf_linearized(FRONT_MD, 1600.0, 0.06)
    rear = mf_linearized(REAR_MD, 2000.0, 0.09)
    assert front.k_alpha == pytest.approx(26.7e3, rel=0.005)
    assert front.k_gamma == pytest.approx(1.12e3, rel=0.01)
    assert rear.k_alpha == pytest.approx(23.5e3, rel=0.005)
    assert rear.k_gamma == pytest.approx(0.92e3, rel=0.01)
    for v in (10.0, 30.0):
        assert front.relaxation_length(v) == pytest.approx(0.22, abs=0.006)
    assert front.relaxation_length(58.0) == pytest.approx(0.25, abs=0.006)
    for v, sigma in ((10.0, 0.23), (30.0, 0.26), (58.0, 0.36)):
        assert rear.relaxation_length(v) == pytest.approx(sigma, abs=0.006)


def test_mf_side_force_asymptote_analytic():
    """Very large slip: Fy -> Dy sin(Cy pi/2) with Dy = pdy1 Fz (atan -> pi/2)."""
    fz = 1600.0
    peak = FRONT_MD["pdy1"] * fz * np.sin(FRONT_MD["Cy"] * np.pi / 2)
    assert mf_side_force(FRONT_MD, fz, 1e9, 0.0) == pytest.approx(peak, rel=1e-6)
    assert mf_side_force(FRONT_MD, fz, -1e9, 0.0) == pytest.approx(-peak, rel=1e-6)
