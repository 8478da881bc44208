"""Whipple bicycle benchmark (Meijaard et al. 2007) through the general engine from YAML.

Published values: [Meijaard 2007] in docs/references.md (14 significant digits, from Meijaard,
Papadopoulos, Ruina, Schwab, Proc. R. Soc. A 463 (2007), eqs. (A.1)-(A.4) and Table 2).
"""
import numpy as np
import pytest

from motoflex_ros.config import config_path
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle

M_PUB = [[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]]
C1_PUB = [[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]]
K0_PUB = [[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]]
K2_PUB = [[0.0, 76.59734589573222], [0.0, 2.65431523794604]]
EIG_PUB = {
    5.0: [-0.77534188219585 + 4.46486771378823j, -0.77534188219585 - 4.46486771378823j,
          -0.32286642900409, -14.07838969279820],
    10.0: [-3.72016840437287 + 10.90681139476287j, -3.72016840437287 - 10.90681139476287j,
           0.16105338653172, -24.62459635017404],
}
# held-out: weave and capsize critical speeds, Meijaard et al. (2007) sect. 4.2
WEAVE_SPEED_PUB, CAPSIZE_SPEED_PUB = 4.29238253634111, 6.02426201538837


@pytest.fixture(scope="module")
def bicycle():
    return linearize(load_vehicle(config_path("vehicles", "whipple_benchmark")))


def test_matrices_published(bicycle):
    so = bicycle.second_order()
    for got, want in ((so.M, M_PUB), (so.C1, C1_PUB), (so.K0, K0_PUB), (so.K2, K2_PUB)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)
    np.testing.assert_allclose(so.C0, 0.0, atol=1e-9)


@pytest.mark.parametrize("speed", [5.0, 10.0])
def test_eigenvalues_published(bicycle, speed):
    got = bicycle.eigenvalues(speed)
    assert len(got) == 4
    for want in EIG_PUB[speed]:
        assert np.min(np.abs(got - want)) < 1e-9, (want, got)


def _crossing(bicycle, select, low, high):
    """Speed [m/s] where the selected eigenvalue's real part crosses zero (bisection)."""
    for _ in range(60):
        mid = 0.5 * (low + high)
        if select(bicycle.eigenvalues(mid)).real < 0:
            high = mid
        else:
            low = mid
    return 0.5 * (low + high)


def test_critical_speeds_published(bicycle):
    def weave(ev):
        return max((z for z in ev if abs(z.imag) > 1e-9), key=lambda z: z.real)

    def capsize(ev):
        return max((z for z in ev if abs(z.imag) <= 1e-9), key=lambda z: z.real)

    # weave stabilises with speed, capsize destabilises: flip the sign for capsize
    assert _crossing(bicycle, weave, 3.0, 5.0) == pytest.approx(WEAVE_SPEED_PUB, abs=1e-8)
    v_c = _crossing(bicycle, lambda ev: -capsize(ev), 5.0, 7.0)
    assert v_c == pytest.approx(CAPSIZE_SPEED_PUB, abs=1e-8)


def test_speed_polynomial_roundtrip(bicycle):
    """A(v) from the fitted polynomial equals a direct linearization at an unseen speed."""
    from motoflex_ros.vehicle.linearize import linearize_at

    E, A = linearize_at(bicycle.system, 13.7)
    E_fit, A_fit = bicycle.pencil([13.7])
    np.testing.assert_allclose(E_fit[0], E, atol=1e-10)
    np.testing.assert_allclose(A_fit[0], A, atol=1e-9)
